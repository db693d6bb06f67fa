#pragma once
// The viewer's `z` recording as plain data: while recording, a key (eye and
// a look-at point ahead) every `step` of pose distance, and every frame
// counted, so that playing the saved path (docs/camera-path.md) retraces
// the motion at about its recorded pace. No GL.
#include "app/viewer_motion.h"
#include "core/camera.h"
#include "scenes/camera_path.h"

namespace hw::app {

class PathRecorder {
 public:
  // A new recording at width x height, with `base`'s field of view and
  // planes; each key's look-at point lies lookDistance ahead of it (scene
  // units), keys are `step` of pose distance apart.
  void start(const Camera& base, int width, int height, double lookDistance, double step);
  bool recording() const { return recording_; }
  // A frame shown at `cam` while recording (nothing otherwise): a key when it
  // is the first or at least `step` from the last key.
  void addFrame(const Camera& cam, const PoseMetric& metric);
  // Stops at `cam`, its last key unless the last key is there already;
  // frames = the frames recorded (at least 1). Returns the path.
  const scenes::CameraPath& stop(const Camera& cam, const PoseMetric& metric);
  // The last recording (empty keys if none).
  const scenes::CameraPath& path() const { return path_; }

 private:
  double look_ = 1, step_ = 0.25;
  bool recording_ = false;
  scenes::CameraPath path_;
  Camera lastKey_;
  int frames_ = 0;
};

}  // namespace hw::app
