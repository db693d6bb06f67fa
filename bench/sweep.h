#pragma once
// Threshold sweep: the walk at τ = 2^6 … 2^16 for both Δ² criteria, against
// baselines at matched quad count (uniform tiles, Rail-Track viewer; one quad
// per pixel, post-rendering warping), on the same frames. Run time against
// error: writes sweep.json / sweep.csv, PNG plots, an overlay per τ and a
// static index.html.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/camera.h"
#include "core/result.h"
#include "scenes/camera_path.h"
#include "scenes/scene.h"

namespace hw::bench {

struct SweepOptions {
  std::vector<double> taus;   // z' units; empty = 2^6, 2^7, …, 2^16
  bool bothCriteria = true;   // five-point and per-axis max (else five-point only)
  bool baselines = true;      // uniform tiles (matched to each five-point τ) and per-pixel
  bool variants = true;       // region-local planarity and strip merging (issue #9), five-point
  int maxFrames = 0;          // frames of the path per run; 0 = all
  DepthMode depthMode = kDefaultDepthMode;
  int overlayFrame = -1;      // keyframe for the overlays; −1 = the middle keyframe
  std::string outDir;         // required
  bool progress = true;
  std::string glRenderer, glVersion;
};

// A GL context must be current. Returns the sweep.json document.
Result<nlohmann::json> runSweep(const scenes::Scene& scene, const std::string& sceneLabel,
                                const scenes::CameraPath& path, const SweepOptions& options);

}  // namespace hw::bench
