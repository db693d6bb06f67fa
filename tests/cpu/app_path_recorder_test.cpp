// The viewer's `z` recording (app/path_recorder.h): a key every step of pose
// distance and at the stop, every frame counted, the session's camera
// settings kept, and the saved path reads back (docs/camera-path.md).
#include <gtest/gtest.h>

#include <cmath>

#include "app/path_recorder.h"

namespace hw::app {
namespace {

constexpr double kPi = 3.14159265358979323846;

Camera at(double x) {
  const glm::dvec3 eye(x, 1.5, 0);
  return Camera::lookAt(eye, eye + glm::dvec3(0, 0, -1), glm::dvec3(0, 1, 0), 50 * kPi / 180, 64,
                        48, 0.2, 300);
}

TEST(PathRecorder, KeysEveryStepAndAtTheStop) {
  const PoseMetric m{1.0, kPi};
  PathRecorder r;
  EXPECT_FALSE(r.recording());
  r.addFrame(at(0), m);  // not recording: ignored
  r.start(at(0), 320, 240, 2.0, 0.25);
  EXPECT_TRUE(r.recording());
  for (int i = 0; i <= 20; ++i) r.addFrame(at(0.1 * i), m);  // 0.1 units a frame
  const scenes::CameraPath& p = r.stop(at(2.05), m);
  EXPECT_FALSE(r.recording());
  EXPECT_EQ(p.frames, 21);
  // Keys at x = 0, 0.3, 0.6, ..., 1.8 (each the first frame >= 0.25 past the
  // last; 0.1 steps accumulate rounding, so 0.3 apart), then the stop's.
  ASSERT_GE(p.keys.size(), 8u);
  ASSERT_LE(p.keys.size(), 10u);
  EXPECT_EQ(p.keys.front().eye, at(0).eye);
  EXPECT_EQ(p.keys.back().eye, at(2.05).eye);
  for (std::size_t k = 1; k + 1 < p.keys.size(); ++k)
    EXPECT_GE(p.keys[k].eye.x - p.keys[k - 1].eye.x, 0.25 - 1e-12) << k;
  // Look-at points 2 units ahead; the session's size, fov and planes.
  EXPECT_NEAR(p.keys.front().lookAt.z, -2.0, 1e-12);
  EXPECT_EQ(p.width, 320);
  EXPECT_EQ(p.height, 240);
  EXPECT_NEAR(p.fovYDeg, 50.0, 1e-9);
  EXPECT_EQ(p.nearPlane, 0.2);
  EXPECT_EQ(p.farPlane, 300);
  // Written and read back (the file format's checks pass).
  auto back = scenes::parseCameraPath(scenes::cameraPathToJson(p), "recorded");
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(back->keys.size(), p.keys.size());
  EXPECT_EQ(back->frames, 21);
}

TEST(PathRecorder, AStillViewerRecordsOneKey) {
  const PoseMetric m{1.0, kPi};
  PathRecorder r;
  r.start(at(3), 64, 48, 1.0, 0.25);
  for (int i = 0; i < 5; ++i) r.addFrame(at(3), m);
  const scenes::CameraPath& p = r.stop(at(3), m);
  EXPECT_EQ(p.keys.size(), 1u);
  EXPECT_EQ(p.frames, 5);
  // Stopped at once: one key, one frame.
  r.start(at(3), 64, 48, 1.0, 0.25);
  EXPECT_EQ(r.stop(at(4), m).keys.size(), 1u);
  EXPECT_EQ(r.path().frames, 1);
}

}  // namespace
}  // namespace hw::app
