#pragma once
// The walk's frames one at a time, for the library (include/hybridwalk): the
// path's keyframe schedule and cache driving the frame engine
// (session/frame_engine.h) the walk drives, so frame i is bit for bit the
// walk's frame i (--mode hybrid) for the same scene, cameras and options;
// without the reference, the recorder, the frame budget and the output
// files. Keyframes are built on first use on the calling thread.
#include <memory>
#include <vector>

#include "core/camera.h"
#include "core/result.h"
#include "gapfill/compose.h"
#include "keyframe/geometry_renderer.h"
#include "keyframe/keyframe_cache.h"
#include "scenes/scene.h"
#include "session/frame_engine.h"
#include "session/hole_pass.h"
#include "session/in_between.h"
#include "session/walk.h"
#include "warp/warper.h"

namespace hw::session {

// What drawing one frame did and cost (ms). Keyframe figures count the
// keyframes built (rendered, meshed, uploaded) during this frame.
struct FrameInfo {
  bool keyframe = false;  // the frame is a keyframe image shown as it is
  int k0 = -1, k1 = -1;   // its bracketing keyframes (path frame indices; equal on a keyframe)
  int keyframesBuilt = 0;
  double keyframeRenderMs = 0;  // geometry draw + readback
  double lodMs = 0;             // Δ buffer + subdivision + corners
  double uploadMs = 0;          // mesh + texture to the GPU
  InBetweenStats inBetween;     // in-between frames only
  double nearMs = 0;            // near objects drawn as geometry (nearDistance > 0)
  HolePassResult holes;         // renderHoles: the hole rectangles drawn (every one found)
  int quads = 0;                // quads warped, or the shown keyframe's
  double totalMs = 0;           // the whole frame
};

class PathFrames {
 public:
  // Needs a current GL context (kept current while this object is used).
  // Uses of `options`: lod, mesh, tileSize, depthMode, inBetween, warp,
  // keyframeFrames, keyframeCacheBytes, keyframePrefetch, renderHoles (every
  // rectangle: renderHolesBudget applies to the walk's auto mode); the walk's other
  // fields (output, reference, budget, async keyframes, sources) are not
  // read. `writeEyeZ`: the warped layers carry eye z (Layer::eyeZ) whatever
  // the composition needs (frames are identical either way). Errors: no
  // cameras, keyframeEvery < 1, cameras not all of one size, GL failures.
  static Result<std::unique_ptr<PathFrames>> create(const scenes::Scene& scene,
                                                    std::vector<Camera> cameras, int keyframeEvery,
                                                    const WalkOptions& options, bool writeEyeZ);
  ~PathFrames();

  int frames() const { return static_cast<int>(cams_.size()); }
  int next() const { return next_; }  // the frame step() draws
  const Camera& camera(int i) const { return cams_[static_cast<std::size_t>(i)]; }
  const keyframe::KeyframeSchedule& schedule() const { return schedule_; }

  // Draws frame next() into frame() and advances. Error after the last
  // frame, or from GL.
  Status step(FrameInfo* info);
  const gapfill::Frame& frame() const { return engine_->previous(); }  // the last frame drawn
  // With writeEyeZ, after a keyframe frame: the keyframe's eye z (0 where
  // empty). After an in-between frame the layers' are in inBetweenStep().
  const Image<float>& keyframeEyeZ() const { return shownEyeZ_; }
  InBetweenStep& inBetweenStep() { return engine_->step(); }
  keyframe::GeometryRenderer& renderer() { return engine_->renderer(); }

 private:
  PathFrames(std::vector<Camera> cameras, const WalkOptions& options);
  Status setUp(const scenes::Scene& scene, int keyframeEvery, bool writeEyeZ);
  Status getSource(int k, const keyframe::CachedKeyframe** out, FrameInfo* info);
  Status keyframeFrame(int i, int k0, FrameInfo* info);
  Status inBetweenFrame(int i, int k0, int k1, FrameInfo* info);

  std::vector<Camera> cams_;
  WalkOptions opt_;
  std::unique_ptr<FrameEngine> engine_;
  keyframe::KeyframeSchedule schedule_;
  std::unique_ptr<keyframe::KeyframeCache> cache_;
  bool writeEyeZ_ = false;
  Image<float> shownEyeZ_;
  int next_ = 0;
};

}  // namespace hw::session
