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
// Checks the files of `entries` are present with their sizes and writes
// index.json (last, atomically: a database without index.json is incomplete).
Status writeBakeIndex(const std::string& outDir, const keyframe::KeyframeDbProvenance& provenance,
                      const std::vector<keyframe::KeyframeDbEntry>& entries);

}  // namespace hw::session
