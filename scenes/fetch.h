#pragma once
// Real scenes from Debian packages, never installed system-wide: the
// OpenArena .debs are fetched with `apt-get download` into a cache folder and
// unpacked there with `dpkg-deb -x`; their .pk3 files feed scenes/q3bsp.h.
#include <string>
#include <vector>

#include "core/result.h"

namespace hw::scenes {

// The Debian packages holding OpenArena's maps and textures.
const std::vector<std::string>& scenePackages();

// The outdoor scenes' packages, fetched only on request (torcs-data alone is
// a 333 MB download, 534 MB unpacked): morse-simulator-data (82 MB; MORSE
// environments, .blend) and torcs-data (TORCS tracks, .acc). See
// scenes/outdoor_scenes.h.
const std::vector<std::string>& outdoorScenePackages();

// $HYBRIDWALK_CACHE, else $HOME/.cache/hybridwalk/scenes (else ./hybridwalk-scenes).
std::string defaultSceneCacheDir();

// Downloads each of scenePackages() into cacheDir/debs (a package whose .deb
// is already there is not downloaded again) and unpacks it into cacheDir/root
// (skipped when cacheDir/root/.unpacked/<deb> says it was). Idempotent; an
// interrupted download leaves no .deb behind. `progress`: one line per step
// on stderr, plus apt-get's own output. Errors name the package and quote
// apt-get's or dpkg-deb's message (and suggest `apt-get update` when apt-get
// cannot find the package).
// With `outdoor`, outdoorScenePackages() are fetched too, after them.
Status fetchScenePackages(const std::string& cacheDir, bool progress, bool outdoor = false);

// All *.pk3 files under `dir` (recursive, symlinks followed), sorted by path
// as the game loads them: alphabetically, later files overriding earlier
// ones. Empty when `dir` does not exist.
std::vector<std::string> findPk3s(const std::string& dir);

// The pk3s for q3: scenes: findPk3s(cacheDir/root), then those of each folder
// in $HYBRIDWALK_PK3_DIR (':'-separated), which therefore override them.
std::vector<std::string> defaultPk3Paths(const std::string& cacheDir = defaultSceneCacheDir());
// Why the folders above cannot be searched: $HYBRIDWALK_CACHE or an entry of
// $HYBRIDWALK_PK3_DIR that exists but is a file, a symlink loop or otherwise
// not a folder ("" when each is a folder or absent).
std::string pk3SearchProblems();

}  // namespace hw::scenes
