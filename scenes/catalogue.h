#pragma once
// Every scene the --scene option can name, by kind: the built-in ones, the
// OpenArena maps, TORCS tracks and MORSE environments of the scene cache
// (scenes/fetch.h), marking the kinds not fetched yet.
#include <string>
#include <vector>

namespace hw::scenes {

struct SceneEntry {
  std::string kind;  // "built-in", "q3", "torcs", "morse"
  std::string spec;  // what --scene takes; for a kind not fetched, its form ("q3:MAP")
  bool fetched = true;
  std::string note;  // e.g. the TORCS category, or how to fetch the kind
};

// All entries, kinds in the order above, names sorted within a kind. A kind
// whose files are not in `cacheDir` is one entry with fetched = false and a
// note naming the `hybridwalk scenes fetch` command that provides it.
std::vector<SceneEntry> listScenes(const std::string& cacheDir);

// The --scene option's help: every form a scene spec can take.
const char* sceneSpecHelp();

}  // namespace hw::scenes
