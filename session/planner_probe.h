#pragma once
// Low-resolution probes of path frames for the keyframe planner: rendered
// keyframes forward-splatted into a frame's probe camera, composed by
// gapfill's rules (gapfill::chooseForeground, gapfill::compose), and
// compared with the frame's own probe.
#include <functional>
#include <map>
#include <memory>
#include <tuple>
#include <utility>
#include <vector>

#include "core/camera.h"
#include "core/image.h"
#include "core/result.h"
#include "gapfill/compose.h"
#include "keyframe/geometry_renderer.h"
#include "session/planner_predictors.h"

namespace hw::session {

// How KeyframeProbe::probeError measures a composed probe warp.
// Defaults: the best measured on the schedule-oracle tables (indoor and
// q3:oa_dm5, 256², docs/results/2026-12-01/schedule/README.md).
struct ProbeErrorOptions {
  // Squared error charged per hole pixel, (0–255)² units: the walk fills holes
  // from the previous frame, usually close but not exact.
  double holeMse = 1000;
  // Compare box-blurred images (radius in probe pixels, 0 = none): textures
  // alias at 64 px, and a sub-pixel shift of an aliased texture is not an error
  // the full-resolution warp makes.
  int blurRadius = 1;
  // Without blur: each composed pixel is compared with the closest-matching
  // reference pixel within this many probe pixels (0 = the same pixel): a
  // splat rounds positions to whole probe pixels, the warp does not.
  int shiftTolerance = 0;
  // Holes take the previous frame's composed probe, as the walk fills them
  // (the segment's chain from keyframe k0 on), instead of costing holeMse.
  bool previousFill = true;
  // Render probes at supersample× the probe size and box-filter colour down
  // (depth: the nearest sample): anti-aliased probes. 1 = off.
  int supersample = 2;
};


// Low-resolution probes (colour + eye depth) of path frames, rendered on
// demand and kept, and the features of a frame between two of them. The
// probe camera is the path camera with the longer side scaled to probeSize
// pixels (same field of view).
class KeyframeProbe {
 public:
  // `renderer` must outlive the probe; it is used at probe resolution (times
  // error.supersample).
  KeyframeProbe(keyframe::GeometryRenderer& renderer, std::function<Camera(int)> cameraOf, int probeSize,
                ProbeErrorOptions error = {});
  ~KeyframeProbe();
  KeyframeProbe(const KeyframeProbe&) = delete;
  KeyframeProbe& operator=(const KeyframeProbe&) = delete;

  // Features are memoised per (k0, k1, frame): repeated plans on one probe
  // (e.g. a search for the target giving N keyframes) cost little.
  Result<FrameFeatures> features(int k0, int k1, int frame);
  // FrameFeatures::probeMse of (k0, k1, frame), memoised; renders the frame's
  // probe too (with previousFill, those of the frames before it in the
  // segment as well). A frame equal to a keyframe's camera gives 0. Keyframe probes
  // warped into a frame are cached (least recently used, ~64 MB).
  Result<double> probeError(int k0, int k1, int frame);
  // FrameFeatures::relDistance alone (no splats), for ProbePsnrDistance.
  Result<double> relDistance(int k0, int k1, int frame);
  int probesRendered() const { return probesRendered_; }
  double renderMs() const { return renderMs_; }  // probe draws + readbacks
  double splatMs() const { return splatMs_; }    // CPU forward splats
  int probeSize() const { return probeSize_; }
  const ProbeErrorOptions& errorOptions() const { return error_; }

  struct Probe;  // one rendered low-resolution keyframe (planner_probe.cpp)
 private:
  Result<const Probe*> probe(int frame);
  Camera probeCamera(int frame) const;
  struct Warped;
  Result<const Warped*> warped(int key, int frame);
  // One frame's composed probe (left in scratch) and its error; holes from
  // `previous` when given (same size), else charged holeMse.
  Result<double> composeAndCompare(int k0, int k1, int frame, const gapfill::Frame* previous);
  struct Chain {
    int frame = -1;        // the last frame composed
    gapfill::Frame image;  // its composed probe
  };
  std::map<std::pair<int, int>, Chain> chains_;

  keyframe::GeometryRenderer& renderer_;
  std::function<Camera(int)> cameraOf_;
  int probeSize_;
  ProbeErrorOptions error_;
  std::map<int, std::unique_ptr<Probe>> probes_;
  std::map<std::tuple<int, int, int>, FrameFeatures> memo_;
  std::map<std::tuple<int, int, int>, double> errorMemo_, distanceMemo_;
  std::map<std::pair<int, int>, std::unique_ptr<Warped>> warpCache_;
  long warpTick_ = 0;
  int probesRendered_ = 0;
  double renderMs_ = 0, splatMs_ = 0;
  struct Scratch;
  std::unique_ptr<Scratch> scratch_;
};


// The features predictor `p` reads for (k0, k1, frame): probeMse (and
// relDistance) alone for probe-psnr (+distance), KeyframeProbe::features()
// and probeMse for probe-psnr+features, features() for the others.
Result<FrameFeatures> predictorFeatures(KeyframeProbe& probe, Predictor p, int k0, int k1,
                                        int frame);

}  // namespace hw::session
