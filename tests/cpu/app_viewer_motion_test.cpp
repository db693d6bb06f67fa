// Where the viewer places its next keyframe (app/viewer_motion.h): the pose
// distance counts each threshold as 1, a steady motion is extrapolated to the
// camera that far ahead, and on a played path the look-ahead picks the first
// camera far enough ahead (or past the newest keyframe), wrapping around.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "app/viewer_motion.h"

namespace hw::app {
namespace {

constexpr double kPi = 3.14159265358979323846;

Camera at(double x, double z, double yawDeg = 0) {
  const double yaw = yawDeg * kPi / 180;
  const glm::dvec3 eye(x, 1.5, z);
  return Camera::lookAt(eye, eye + glm::dvec3(std::sin(yaw), 0, -std::cos(yaw)),
                        glm::dvec3(0, 1, 0), 60 * kPi / 180, 64, 48, 0.1, 100);
}

TEST(ViewerMotion, PoseDistanceCountsEachThresholdAsOne) {
  const PoseMetric m{2.0, 15 * kPi / 180};
  EXPECT_NEAR(m(at(0, 0), at(2, 0)), 1.0, 1e-12);
  EXPECT_NEAR(m(at(0, 0), at(0, 0, 15)), 1.0, 1e-9);
  EXPECT_NEAR(m(at(0, 0), at(1, 0, 30)), 2.5, 1e-9);
  EXPECT_EQ(m(at(3, 4, 7), at(3, 4, 7)), 0.0);
}

TEST(ViewerMotion, SteadyMotionIsExtrapolatedThatFarAhead) {
  const PoseMetric m{2.0, 15 * kPi / 180};
  MotionEstimate e;
  // Not moving yet: the camera itself.
  EXPECT_EQ(e.extrapolate(at(0, 0), 1.0, m, 64, 48).eye, at(0, 0).eye);
  // 0.5 units per frame along -Z at 10 frames/s, long enough to converge.
  for (int i = 0; i < 60; ++i) e.update(at(0, -0.5 * i), at(0, -0.5 * (i + 1)), 0.1);
  EXPECT_NEAR(e.velocity().z, -5.0, 1e-9);
  EXPECT_NEAR(e.yawRate(), 0.0, 1e-12);
  const Camera now = at(0, -30);
  const Camera ahead = e.extrapolate(now, 1.0, m, 64, 48);  // 1 pose unit = 2 scene units
  EXPECT_NEAR(ahead.eye.z, -32.0, 1e-6);
  EXPECT_NEAR(ahead.eye.x, 0.0, 1e-9);
  EXPECT_NEAR(m(ahead, now), 1.0, 1e-6);
  EXPECT_EQ(ahead.width, 64);
  // A turn on the spot: the angle ahead is the threshold.
  MotionEstimate turn;
  for (int i = 0; i < 60; ++i) turn.update(at(0, 0, i), at(0, 0, i + 1), 0.1);
  EXPECT_NEAR(turn.yawRate(), 10 * kPi / 180, 1e-9);
  EXPECT_NEAR(m(turn.extrapolate(at(0, 0, 60), 1.0, m, 64, 48), at(0, 0, 60)), 1.0, 1e-6);
  EXPECT_GT(turn.extrapolate(at(0, 0, 60), 1.0, m, 64, 48).forward.x, at(0, 0, 60).forward.x);
  // dt 0 (a repeated frame) changes nothing.
  MotionEstimate same = turn;
  same.update(at(0, 0), at(5, 5), 0);
  EXPECT_EQ(same.yawRate(), turn.yawRate());
}

TEST(ViewerMotion, PathLookAheadPicksTheFirstCameraFarEnoughAndWraps) {
  const PoseMetric m{1.0, kPi};
  std::vector<Camera> path;
  for (int i = 0; i < 10; ++i) path.push_back(at(i, 0));  // one unit apart along +X
  // At camera 3, camera 4 shown next: 2 units ahead is camera 5.
  EXPECT_EQ(pathCameraAhead(path, 4, path[3], 2.0, m).eye.x, 5.0);
  // Farther than the path reaches: the farthest of the next 9 (camera 9;
  // the loop's cameras 0-2 are nearer).
  EXPECT_EQ(pathCameraAhead(path, 4, path[3], 50.0, m).eye.x, 9.0);
  // Near the end it wraps to the path's start.
  EXPECT_EQ(pathCameraAhead(path, 0, path[9], 9.0, m).eye.x, 0.0);
}

TEST(ViewerMotion, BeyondTheNewestKeyframeOnThePath) {
  const PoseMetric m{1.0, kPi};
  std::vector<Camera> path;
  for (int i = 0; i < 10; ++i) path.push_back(at(i, 0));
  // Viewer at 2 (3 next), newest keyframe at 4: 1.5 beyond it is camera 6
  // (cameras 3 and 4 are not past the newest).
  EXPECT_EQ(pathCameraBeyond(path, 3, path[2], path[4], 1.5, m).eye.x, 6.0);
  // Nothing past the newest: the viewer's own camera.
  EXPECT_EQ(pathCameraBeyond(path, 3, path[2], at(20, 0), 1.0, m).eye.x, 2.0);
}

}  // namespace
}  // namespace hw::app
