#pragma once
// Keyframe baking: every keyframe of a path rendered by the geometry renderer
// and meshed by the Δ²z' LOD builder (Zheng et al. 1999 §1.1–1.2) ahead of
// time, written as a keyframe database (keyframe/keyframe_db.h,
// docs/keyframe-db.md) that `walk --keyframes DB` reads instead.
#include <string>
#include <vector>

#include "core/result.h"
#include "keyframe/keyframe_db.h"
#include "keyframe/lod_builder.h"
#include "scenes/camera_path.h"
#include "scenes/scene.h"

namespace hw::session {

struct BakeOptions {
  keyframe::LodOptions lod;  // τ, criterion, planarity, merge strips (as walk)
  DepthMode depthMode = kDefaultDepthMode;
  int maxFrames = 0;   // frames of the path; 0 = all
  std::string outDir;  // the database directory (required)
  bool progress = true;
};

// Frames of the walk (maxFrames applied).
int bakeFrames(const scenes::CameraPath& path, int maxFrames);
// The keyframes a walk over `frames` frames uses (KeyframeSchedule).
std::vector<int> bakeKeyframeList(const scenes::CameraPath& path, int frames);
// What a database of this scene/path/options records (and a walk expects).
keyframe::KeyframeDbProvenance bakeProvenance(const std::string& sceneLabel, std::size_t triangles,
                                              const scenes::CameraPath& path, int frames,
                                              const keyframe::LodOptions& lod, DepthMode depthMode);

// Renders, meshes and writes the keyframe files of `keyframes` into outDir
// (each atomically). A GL context must be current.
Result<std::vector<keyframe::KeyframeDbEntry>> bakeKeyframes(const scenes::Scene& scene,
                                                             const scenes::CameraPath& path,
                                                             const std::vector<int>& keyframes,
                                                             const BakeOptions& options);
// What a bake does in its output folder (held by this run, core/output_dir.h).
enum class BakeStart {
  Fresh,     // bake every keyframe
  Resume,    // rerun the chunks an interrupted run left (core/chunked_runs.h)
  Complete,  // --resume on a finished database of this very bake: nothing to do
};
// Without `resume`: removes the earlier database the folder's index.json lists
// (index.json first, then the keyframe files it names; nothing else) and
// returns Fresh. With `resume`: Complete, touching nothing, when index.json
// holds this bake (provenance, keyframe schedule, every file's header and
// camera: KeyframeDb::checkFiles); an error naming the difference when it
// holds another bake; Resume when there is no usable index but an interrupted
// run's chunk plan (whose command is checked when the chunks run); otherwise
// an error saying there is nothing to resume. Never removes a valid database
// under --resume.
Result<BakeStart> prepareBakeDir(const std::string& outDir,
                                 const keyframe::KeyframeDbProvenance& provenance,
                                 const scenes::CameraPath& path, const std::vector<int>& keyframes,
                                 DepthMode depthMode, bool resume);

// Checks the files of `entries` are present with their sizes and writes
// index.json (last, atomically: a database without index.json is incomplete).
Status writeBakeIndex(const std::string& outDir, const keyframe::KeyframeDbProvenance& provenance,
                      const std::vector<keyframe::KeyframeDbEntry>& entries);

}  // namespace hw::session
