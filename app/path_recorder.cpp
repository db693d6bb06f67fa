// The viewer's camera path recording (app/path_recorder.h).
#include "app/path_recorder.h"

#include <algorithm>

namespace hw::app {

void PathRecorder::start(const Camera& base, int width, int height, double lookDistance,
                         double step) {
  look_ = lookDistance;
  step_ = step;
  constexpr double kPi = 3.14159265358979323846;
  path_ = scenes::CameraPath{};
  path_.width = width;
  path_.height = height;
  path_.fovYDeg = base.fovYRadians * 180.0 / kPi;
  path_.nearPlane = base.nearPlane;
  path_.farPlane = base.farPlane;
  frames_ = 0;  // keys and frames are added from this frame's camera on
  recording_ = true;
}

void PathRecorder::addFrame(const Camera& cam, const PoseMetric& metric) {
  if (!recording_) return;
  ++frames_;
  if (path_.keys.empty() || metric(cam, lastKey_) >= step_) {
    path_.keys.push_back({cam.eye, cam.eye + cam.forward * look_});
    lastKey_ = cam;
  }
}

const scenes::CameraPath& PathRecorder::stop(const Camera& cam, const PoseMetric& metric) {
  recording_ = false;
  if (path_.keys.empty() || metric(cam, lastKey_) > 0)
    path_.keys.push_back({cam.eye, cam.eye + cam.forward * look_});
  path_.frames = std::max(frames_, 1);
  return path_;
}

}  // namespace hw::app
