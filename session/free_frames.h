#pragma once
// Hybrid frames at cameras given one at a time (the library's free camera,
// include/hybridwalk/renderer.h): backward warping needs a keyframe on each
// side of the frame, so keyframes are placed as the synchronous viewer places
// them (app/gl/viewer.cpp liveKeyframes): two kept, one rendered ahead along
// the camera's motion (extrapolated from the last two cameras) once the
// camera has passed the newest, and one rendered where the camera stands
// when none is within reach. Each frame is the in-between step the walk and
// the viewer use (session/in_between.h).
#include <array>
#include <memory>

#include "core/camera.h"
#include "core/result.h"
#include "gapfill/compose.h"
#include "keyframe/geometry_renderer.h"
#include "keyframe/keyframe_cache.h"
#include "scenes/scene.h"
#include "session/frame_engine.h"
#include "session/in_between.h"
#include "session/keyframe_survey.h"
#include "session/path_frames.h"
#include "session/walk.h"
#include "warp/warper.h"

namespace hw::session {

struct FreeKeyframeOptions {
  // A keyframe is worth one pose-distance unit when it is this far (scene
  // units, > 0) or this much turned (degrees, > 0) from the camera; the
  // distances add up (the viewer's ViewerOptions::keyframeDistance/AngleDeg).
  double distance = 1.0;
  double angleDeg = 15.0;
};


class FreeFrames {
 public:
  // Needs a current GL context. `options` as PathFrames::create reads it
  // (keyframeFrames and the cache settings unused). Errors: distance or
  // angle not > 0, GL failures.
  static Result<std::unique_ptr<FreeFrames>> create(const scenes::Scene& scene,
                                                    const WalkOptions& options,
                                                    const FreeKeyframeOptions& keyframes,
                                                    bool writeEyeZ);
  ~FreeFrames();

  // Draws the frame at `cam` into frame(). info->k0/k1 are -1. Errors: GL.
  Status draw(const Camera& cam, FrameInfo* info);
  const gapfill::Frame& frame() const { return engine_->previous(); }  // the last frame drawn
  // With writeEyeZ, after a keyframe frame (info->keyframe): its eye z.
  const Image<float>& keyframeEyeZ() const { return shownEyeZ_; }
  InBetweenStep& inBetweenStep() { return engine_->step(); }
  keyframe::GeometryRenderer& renderer() { return engine_->renderer(); }
  // Pose distance between two cameras (FreeKeyframeOptions units).
  double poseDistance(const Camera& a, const Camera& b) const;
  // The camera `distance` pose units ahead along the motion from `prev` to
  // `cam`; `cam` itself when it is not moving or the motion cannot be
  // extrapolated.
  Camera aheadCamera(const Camera& prev, const Camera& cam, double distance) const;

 private:
  struct Slot {
    std::unique_ptr<keyframe::CachedKeyframe> kf;
    bool valid = false;
    int serial = 0;  // build order, and the keyframe's id in the engine
  };
  FreeFrames(const WalkOptions& options, const FreeKeyframeOptions& keyframes);
  Status setUp(const scenes::Scene& scene, bool writeEyeZ);
  Status build(Slot& slot, const Camera& cam, FrameInfo* info);

  WalkOptions opt_;
  FreeKeyframeOptions kopt_;
  bool writeEyeZ_ = false;
  std::unique_ptr<FrameEngine> engine_;
  keyframe::LodBuilder builder_;
  std::array<Slot, 2> slots_;
  int serial_ = 0;
  Camera prevCam_;
  bool havePrevCam_ = false;
  int newestSerialPrev_ = -1;
  double newestSPrev_ = 0;
  Image<float> shownEyeZ_;
};

}  // namespace hw::session
