// The scene catalogue behind `hybridwalk scenes list`. See catalogue.h.
#include "scenes/catalogue.h"

#include <algorithm>
#include <filesystem>

#include "scenes/fetch.h"
#include "scenes/q3bsp.h"

namespace hw::scenes {

namespace fs = std::filesystem;

std::vector<SceneEntry> listScenes(const std::string& cacheDir) {
  std::vector<SceneEntry> out;
  out.push_back(
      {"built-in", "indoor", true, "procedural rooms; indoor:N for ~N triangles (e.g. indoor:1M)"});
  out.push_back({"built-in", "outdoor", true, "procedural terrain; outdoor:N for ~N triangles"});

  const auto pk3s = defaultPk3Paths(cacheDir);
  auto maps = pk3s.empty() ? Result<std::vector<std::string>>(std::vector<std::string>{})
                           : listQ3Maps(pk3s);
  if (maps.ok() && !maps->empty()) {
    for (const std::string& m : *maps) out.push_back({"q3", "q3:" + m, true, "OpenArena map"});
  } else {
    out.push_back(
        {"q3", "q3:MAP", false,
         maps.ok() ? "run `hybridwalk scenes fetch`" : "cannot list: " + maps.error().message});
  }

  const fs::path root = fs::path(cacheDir) / "root" / "usr" / "share";
  std::error_code ec;
  std::vector<SceneEntry> tracks;
  const fs::path torcs = root / "games" / "torcs" / "tracks";
  if (fs::is_directory(torcs, ec)) {
    for (const auto& cat : fs::directory_iterator(torcs, ec)) {
      if (!cat.is_directory(ec)) continue;
      for (const auto& t : fs::directory_iterator(cat.path(), ec)) {
        const std::string name = t.path().filename().string();
        if (!fs::is_regular_file(t.path() / (name + ".acc"), ec)) continue;
        const bool described = fs::is_regular_file(t.path() / (name + ".xml"), ec);
        tracks.push_back({"torcs", "torcs:" + name, true,
                          cat.path().filename().string() + " track" +
                              (described ? "" : " (no track description: road-texture trace)")});
      }
    }
  }
  std::sort(tracks.begin(), tracks.end(),
            [](const auto& a, const auto& b) { return a.spec < b.spec; });
  if (tracks.empty())
    tracks.push_back({"torcs", "torcs:TRACK", false, "run `hybridwalk scenes fetch --outdoor`"});
  out.insert(out.end(), tracks.begin(), tracks.end());

  std::vector<SceneEntry> envs;
  const fs::path morse = root / "morse" / "data" / "environments";
  if (fs::is_directory(morse, ec)) {
    for (auto it = fs::recursive_directory_iterator(morse, ec);
         !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
      if (it->path().extension() != ".blend" || !it->is_regular_file(ec)) continue;
      std::string rel = fs::relative(it->path(), morse, ec).replace_extension().generic_string();
      envs.push_back({"morse", "morse:" + rel, true, "MORSE environment"});
    }
  }
  std::sort(envs.begin(), envs.end(), [](const auto& a, const auto& b) { return a.spec < b.spec; });
  if (envs.empty())
    envs.push_back({"morse", "morse:ENV/FILE", false, "run `hybridwalk scenes fetch --outdoor`"});
  out.insert(out.end(), envs.begin(), envs.end());
  return out;
}

const char* sceneSpecHelp() {
  return "Scene: 'indoor' or 'outdoor' (built-in; append ':N' for ~N triangles, e.g. indoor:1M; "
         "default 100k); q3:MAP (an OpenArena map, after 'hybridwalk scenes fetch'); torcs:TRACK "
         "(a TORCS track) or morse:ENV/FILE (a MORSE environment), after 'scenes fetch "
         "--outdoor'; or a model file: Assimp formats (OBJ, glTF, PLY, COLLADA, FBX, ...), TORCS "
         ".acc, Blender .blend. 'hybridwalk scenes list' shows every scene by name";
}

}  // namespace hw::scenes
