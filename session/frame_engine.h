#pragma once
// The frame engine: the per-frame work every driver shares (the walk, the
// library's path and free-camera frames, the viewer). It owns the geometry
// renderer, the warper, the keyframes on the GPU, the in-between step
// (Zheng et al. 1999 §2.2: nearer keyframe in front, the previous frame where
// both miss), near geometry (§3) and the hole pass, and draws one frame per
// call: a keyframe shown, an in-between frame, or the geometry. Where
// keyframes come from (a path schedule, poses, a database, a worker) is the
// driver's; so are the reference render, the metrics and the output.
#include <map>
#include <memory>
#include <vector>

#include <glm/vec3.hpp>

#include "core/camera.h"
#include "core/result.h"
#include "gapfill/compose.h"
#include "gapfill/gl/gpu_frames.h"
#include "keyframe/geometry_renderer.h"
#include "keyframe/keyframe.h"
#include "keyframe/keyframe_cache.h"
#include "keyframe/quad_mesh.h"
#include "scenes/scene.h"
#include "session/frame_budget.h"
#include "session/hole_pass.h"
#include "session/in_between.h"
#include "session/walk.h"
#include "warp/warper.h"

namespace hw::session {

// The hole pass's time cap (WalkOptions::renderHolesBudget): rectangles are
// drawn, most holes first, while their estimated cost fits both
// `fraction` x `geometryMs` and what keeps the frame (`frameMsSoFar` spent)
// below one geometry frame.
struct HoleBudget {
  double fraction = 0;      // of a geometry frame; <= 0: no cap
  double geometryMs = 0;    // a geometry frame's cost at this view (<= 0: unknown, no cap)
  double frameMsSoFar = 0;  // the frame's work before the hole pass
  // >= 0: draw this many rectangles (at most those found) whatever the cost,
  // as a pinned run did (session/mode_pin.h); the fields above are then unused.
  int rects = -1;
};

// The keyframe schedule of a path of `frames` frames: every `keyframeEvery`
// frames, or at `keyframeFrames` (sorted, deduplicated, the ends always).
keyframe::KeyframeSchedule pathSchedule(int frames, int keyframeEvery,
                                        const std::vector<int>& keyframeFrames);

// The fill floor of an in-between frame at one resolution (ms, medians): one
// full-screen textured quad warped as a layer, and as both layers of an
// in-between frame (the step's draw, its readback included).
struct FloorTimes {
  double oneLayerMs = -1;
  double twoLayersMs = -1;
  int reps = 0;
};

class FrameEngine {
 public:
  // Needs a current GL context. Reads from `options`: depthMode, inBetween,
  // warp. `writeEyeZ`: the warped layers carry eye z whatever the composition
  // needs (frames are identical either way); `markLargeQuads` false turns the
  // warper's large-leaf mask off (it only feeds a metric). Errors: GL.
  static Result<std::unique_ptr<FrameEngine>> create(const scenes::Scene& scene,
                                                     const WalkOptions& options, bool writeEyeZ,
                                                     bool markLargeQuads = true);
  ~FrameEngine();

  keyframe::GeometryRenderer& renderer() { return *renderer_; }
  warp::Warper& warper() { return *warper_; }
  // Whether the layers are drawn by the CPU warper (WalkOptions::warper).
  bool cpuWarper() const { return cpuWarper_; }
  const warp::WarpOptions& warpOptions() const { return wopt_; }
  InBetweenStep& step() { return step_; }
  const InBetweenOptions& inBetweenOptions() const { return step_.options(); }

  // Frames kept on the GPU (for a driver that shows them there, the viewer):
  // composition, the previous-frame fill and the hole pass's rectangles stay
  // in GL textures, and only the masks are read back (frame().holesBefore,
  // .valid and the counts stay current; frame().colour does not: readFrame).
  // Its in-between frames' stats: composeMs is the composition pass on the
  // GPU, readbackMs the masks' readback.
  // Possible with OpenGL's warper, the fused overlay, the copy fallback and
  // no near geometry; false (and unchanged) otherwise. The frames are the
  // same bit for bit; frame ages (gapfill/age.h) are not kept. Forgets the
  // previous frame.
  bool keepFramesOnGpu(bool on);
  bool framesOnGpu() const { return gpu_ != nullptr; }
  // The frame drawn (row 0 = top), wherever it is kept.
  void readFrame(Image<Rgba8>& out);
  // The current frame's colour texture on the GPU (row 0 = bottom); 0 unless
  // framesOnGpu().
  unsigned frameTexture() const { return gpu_ ? gpu_->colourTexture() : 0; }

  // The frame being drawn, and the last one presented (the previous-frame
  // fill reads it).
  gapfill::Frame& frame() { return frame_; }
  const gapfill::Frame& previous() const { return previous_; }
  bool hasPrevious() const { return havePrevious_; }
  // The frame drawn becomes the previous frame of the next.
  void present();
  // The next frame has no previous frame (a jump, another size).
  void forgetPrevious() { havePrevious_ = false; }

  // Keyframes on the GPU, by the driver's id (a path frame index, a slot's
  // serial). `nearEye`: the eye whose near clusters the keyframe left out
  // (RenderOptions::keyframeExcludeNear), drawn by every frame that warps it.
  bool has(int id) const { return keyframes_.count(id) != 0; }
  Status upload(int id, const keyframe::Keyframe& keyframe, const keyframe::QuadMesh& mesh,
                const glm::dvec3& nearEye, warp::WarpStats* stats);
  const warp::WarpSource& source(int id) const;  // precondition (checked): has(id)
  void release(int id) { keyframes_.erase(id); }
  void releaseBefore(int id);  // every id < `id`
  void releaseAll() { keyframes_.clear(); }

  // Keyframe `id` (uploaded, with its image `keyframe`) shown as the frame at
  // `cam`, with near objects (stats->nearMs >= 0 when drawn). The frame gets
  // the keyframe's depth when the fallback reprojects. `alsoNear` (an id,
  // -1: none): a keyframe whose near clusters are drawn too.
  Status showKeyframe(const Camera& cam, int id, const keyframe::Keyframe& keyframe,
                      InBetweenStats* stats, int alsoNear = -1);
  // An image shown as the frame as it is (a keyframe rendered at this very
  // camera): no holes, nothing older.
  Status showImage(const Image<Rgba8>& colour);
  // The in-between frame at `cam` from keyframes `a` and `b` (-1: one layer):
  // the one whose keyframe eye is nearer in front (gapfill::chooseForeground,
  // ties to `a`), the previous frame where both miss, near objects of both.
  // *foreground = the id drawn in front.
  Status warp(const Camera& cam, int a, int b, InBetweenStats& stats, int* foreground);
  // The geometry renderer's image at `cam` as the frame (exact: no holes).
  Status drawGeometry(const Camera& cam, keyframe::RenderStats* stats);
  // The hole pass (WalkOptions::renderHoles) on the frame: every hole
  // rectangle, or (budget given with a cap) those that fit it. *budgetMs:
  // the cap in ms, NaN without one.
  Status renderHoles(const Camera& cam, const HoleBudget* budget, HolePassResult* out,
                     double* budgetMs = nullptr);
  // The fill floor at `cam` (its resolution): a keyframe of a plane facing
  // the camera (one leaf, one quad) warped back to it, `reps` >= 1 timed
  // draws of each kind after an untimed one. The engine's frames are not touched.
  // Its keyframe is charged to the memory budget while it lives (refused
  // like a walk's keyframe when it does not fit).
  Status measureFloor(const Camera& cam, int reps, FloorTimes* out);

 private:
  struct Entry {
    std::unique_ptr<warp::WarpSource> source;
    glm::dvec3 keyframeEye{0.0};
    glm::dvec3 nearEye{0.0};
  };
  explicit FrameEngine(const WalkOptions& options);
  const Entry& entry(int id) const;
  Status warpOnGpu(const Camera& cam, const warp::WarpSource& fg, const warp::WarpSource* bg,
                   InBetweenStats& st);

  InBetweenStep step_;
  DepthMode depthMode_;
  std::unique_ptr<keyframe::GeometryRenderer> renderer_;
  Status createWarper(warp::WarperChoice choice, int cpuThreads);

  warp::WarpOptions wopt_;
  std::unique_ptr<warp::Warper> warper_;
  bool cpuWarper_ = false;
  std::map<int, Entry> keyframes_;
  HolePass holePass_;
  HoleTiling holeTiling_;
  HoleCostModel holeCost_;
  gapfill::Frame frame_, previous_;
  bool havePrevious_ = false;
  std::unique_ptr<gapfill::GpuFrames> gpu_;  // framesOnGpu()
};

}  // namespace hw::session
