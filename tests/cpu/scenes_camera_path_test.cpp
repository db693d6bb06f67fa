// Camera path JSON: strict validation with messages naming the key, round
// trips, and constant-speed Catmull-Rom sampling (DESIGN.md "Camera path").
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "scenes/camera_path.h"

namespace hw::scenes {
namespace {

const char* kGood = R"({ "width": 320, "height": 240, "fov_y_deg": 50, "near": 0.2, "far": 500,
  "up": [0, 1, 0],
  "keys": [ {"eye": [0, 1.7, 0], "look_at": [0, 1.7, -5]},
            {"eye": [4, 1.7, -6], "look_at": [8, 1.7, -10]},
            {"eye": [10, 2.0, -6], "look_at": [14, 1.5, -3]},
            {"eye": [12, 1.7, 3], "look_at": [12, 1.7, 9]} ],
  "frames": 90, "keyframe_every": 5 })";

TEST(CameraPath, ParsesAllFields) {
  auto p = parseCameraPath(kGood, "good.json");
  ASSERT_TRUE(p.ok()) << p.error().message;
  EXPECT_EQ(p->width, 320);
  EXPECT_EQ(p->height, 240);
  EXPECT_DOUBLE_EQ(p->fovYDeg, 50);
  EXPECT_DOUBLE_EQ(p->nearPlane, 0.2);
  EXPECT_DOUBLE_EQ(p->farPlane, 500);
  EXPECT_EQ(p->frames, 90);
  EXPECT_EQ(p->keyframeEvery, 5);
  ASSERT_EQ(p->keys.size(), 4u);
  EXPECT_EQ(p->keys[1].eye, glm::dvec3(4, 1.7, -6));
  EXPECT_EQ(p->keys[3].lookAt, glm::dvec3(12, 1.7, 9));
  EXPECT_TRUE(p->isKeyframe(0));
  EXPECT_TRUE(p->isKeyframe(5));
  EXPECT_FALSE(p->isKeyframe(6));
}

TEST(CameraPath, OptionalKeysTakeStructDefaults) {
  auto p = parseCameraPath(R"({"keys": [{"eye": [0,0,0], "look_at": [1,0,0]}], "frames": 3})",
                           "min.json");
  ASSERT_TRUE(p.ok()) << p.error().message;
  const CameraPath d;
  EXPECT_EQ(p->width, d.width);
  EXPECT_EQ(p->height, d.height);
  EXPECT_EQ(p->fovYDeg, d.fovYDeg);
  EXPECT_EQ(p->nearPlane, d.nearPlane);
  EXPECT_EQ(p->farPlane, d.farPlane);
  EXPECT_EQ(p->up, d.up);
  EXPECT_EQ(p->keyframeEvery, d.keyframeEvery);
}

TEST(CameraPath, RoundTripsThroughJson) {
  auto p = parseCameraPath(kGood, "good.json");
  ASSERT_TRUE(p.ok());
  p->keys[0].eye = glm::dvec3(0.1, 1.0 / 3.0, -1e-7);  // needs full precision
  const std::string text = cameraPathToJson(*p);
  auto q = parseCameraPath(text, "roundtrip.json");
  ASSERT_TRUE(q.ok()) << q.error().message << "\n" << text;
  EXPECT_EQ(q->width, p->width);
  EXPECT_EQ(q->height, p->height);
  EXPECT_EQ(q->fovYDeg, p->fovYDeg);
  EXPECT_EQ(q->nearPlane, p->nearPlane);
  EXPECT_EQ(q->farPlane, p->farPlane);
  EXPECT_EQ(q->up, p->up);
  EXPECT_EQ(q->frames, p->frames);
  EXPECT_EQ(q->keyframeEvery, p->keyframeEvery);
  ASSERT_EQ(q->keys.size(), p->keys.size());
  for (std::size_t i = 0; i < p->keys.size(); ++i) {
    EXPECT_EQ(q->keys[i].eye, p->keys[i].eye);
    EXPECT_EQ(q->keys[i].lookAt, p->keys[i].lookAt);
  }
  EXPECT_EQ(cameraPathToJson(*q), text);
}

TEST(CameraPath, EndsAtFirstAndLastKey) {
  auto p = parseCameraPath(kGood, "good.json");
  ASSERT_TRUE(p.ok());
  const Camera first = p->cameraAt(0), last = p->cameraAt(p->frames - 1);
  EXPECT_NEAR(glm::length(first.eye - p->keys.front().eye), 0.0, 1e-9);
  EXPECT_NEAR(glm::length(last.eye - p->keys.back().eye), 0.0, 1e-9);
  const glm::dvec3 f0 = glm::normalize(p->keys.front().lookAt - p->keys.front().eye);
  const glm::dvec3 f1 = glm::normalize(p->keys.back().lookAt - p->keys.back().eye);
  EXPECT_NEAR(glm::dot(first.forward, f0), 1.0, 1e-9);
  EXPECT_NEAR(glm::dot(last.forward, f1), 1.0, 1e-9);
  EXPECT_EQ(first.width, 320);
  EXPECT_EQ(first.height, 240);
  EXPECT_NEAR(first.fovYRadians, 50 * 3.14159265358979323846 / 180, 1e-12);
  EXPECT_EQ(first.nearPlane, 0.2);
  EXPECT_EQ(first.farPlane, 500);
}

TEST(CameraPath, ConstantSpeedAlongEyeCurve) {
  auto p = parseCameraPath(kGood, "good.json");
  ASSERT_TRUE(p.ok());
  // Key spacing is very uneven (7.2 m, 6.0 m, 9.2 m), so uniform parameter
  // sampling would not pass this.
  std::vector<double> d;
  for (int i = 1; i < p->frames; ++i)
    d.push_back(glm::length(p->cameraAt(i).eye - p->cameraAt(i - 1).eye));
  double lo = 1e30, hi = 0, sum = 0;
  for (double x : d) {
    lo = std::min(lo, x);
    hi = std::max(hi, x);
    sum += x;
  }
  const double mean = sum / d.size();
  EXPECT_GT(mean, 0.1);
  EXPECT_LT((hi - lo) / mean, 0.01) << "min " << lo << " max " << hi;
}

TEST(CameraPath, CameraFramesAreOrthonormalEverywhere) {
  auto p = parseCameraPath(kGood, "good.json");
  ASSERT_TRUE(p.ok());
  for (int i = 0; i < p->frames; ++i) {
    const Camera c = p->cameraAt(i);
    EXPECT_NEAR(glm::length(c.forward), 1.0, 1e-9);
    EXPECT_NEAR(glm::dot(c.forward, c.up), 0.0, 1e-9);
    EXPECT_NEAR(glm::dot(c.right, c.up), 0.0, 1e-9);
    EXPECT_GT(c.up.y, 0.0);  // upright: path keeps the world up
  }
}

TEST(CameraPath, PureRotationUsesLookAtCurve) {
  auto p = parseCameraPath(R"({"keys": [{"eye": [1,2,3], "look_at": [1,2,-2]},
                                        {"eye": [1,2,3], "look_at": [6,2,3]},
                                        {"eye": [1,2,3], "look_at": [1,2,8]}], "frames": 41})",
                           "spin.json");
  ASSERT_TRUE(p.ok()) << p.error().message;
  double prevAngle = 0;
  for (int i = 0; i < p->frames; ++i) {
    const Camera c = p->cameraAt(i);
    EXPECT_EQ(c.eye, glm::dvec3(1, 2, 3));
    if (i > 0) {
      const double a =
          std::acos(std::clamp(glm::dot(c.forward, p->cameraAt(i - 1).forward), -1.0, 1.0));
      if (i > 1) {
        EXPECT_NEAR(a, prevAngle, 0.25 * prevAngle);  // turns steadily, never jumps
      }
      prevAngle = a;
    }
  }
  EXPECT_NEAR(glm::dot(p->cameraAt(40).forward, glm::dvec3(0, 0, 1)), 1.0, 1e-9);
}

TEST(CameraPath, SingleKeyIsStill) {
  auto p = parseCameraPath(R"({"keys": [{"eye": [0,1,0], "look_at": [0,1,-1]}], "frames": 10})",
                           "s.json");
  ASSERT_TRUE(p.ok());
  for (int i = 0; i < 10; ++i) {
    EXPECT_EQ(p->cameraAt(i).eye, glm::dvec3(0, 1, 0));
    EXPECT_NEAR(glm::dot(p->cameraAt(i).forward, glm::dvec3(0, 0, -1)), 1.0, 1e-12);
  }
}

TEST(CameraPath, SamplingNeverAbortsWhenCurveLooksAlongUp) {
  // Keys are valid, but the interpolated look-at passes straight above the eye.
  CameraPath p;
  p.keys = {{{0, 0, 0}, {-1, 1, 0}}, {{0, 0, 0}, {1, 1, 0}}};
  p.frames = 21;
  for (int i = 0; i < p.frames; ++i) {
    const Camera c = p.cameraAt(i);
    EXPECT_TRUE(std::isfinite(c.right.x) && std::isfinite(c.up.y));
    EXPECT_NEAR(glm::length(c.right), 1.0, 1e-9);
  }
}

struct BadCase {
  const char* name;
  std::string json;
  std::string mustContain;  // the key name
};

std::string withKeys(const std::string& extra) {
  return R"({"keys": [{"eye": [0,1.7,0], "look_at": [0,1.7,-5]}], "frames": 10)" + extra + "}";
}

TEST(CameraPath, RejectsMalformedInputNamingTheKey) {
  const std::vector<BadCase> cases = {
      {"not json", "{ \"frames\": 10, ", "byte"},
      {"top level array", "[1, 2]", "top level"},
      {"missing keys", R"({"frames": 10})", "keys"},
      {"missing frames", R"({"keys": [{"eye": [0,0,0], "look_at": [0,0,-1]}]})", "frames"},
      {"unknown key", withKeys(R"(, "fov": 60)"), "fov"},
      {"unknown key in a key",
       R"({"keys": [{"eye": [0,0,0], "look_at": [0,0,-1], "roll": 3}], "frames": 2})",
       "keys[0].roll"},
      {"NaN as a string", withKeys(R"(, "near": "NaN")"), "near"},
      {"frames 0", R"({"keys": [{"eye": [0,0,0], "look_at": [0,0,-1]}], "frames": 0})", "frames"},
      {"frames fractional", R"({"keys": [{"eye": [0,0,0], "look_at": [0,0,-1]}], "frames": 2.5})",
       "frames"},
      {"keyframe_every 0", withKeys(R"(, "keyframe_every": 0)"), "keyframe_every"},
      {"near >= far", withKeys(R"(, "near": 10, "far": 5)"), "far"},
      {"near 0", withKeys(R"(, "near": 0)"), "near"},
      {"fov 0", withKeys(R"(, "fov_y_deg": 0)"), "fov_y_deg"},
      {"fov 180", withKeys(R"(, "fov_y_deg": 180)"), "fov_y_deg"},
      {"width 0", withKeys(R"(, "width": 0)"), "width"},
      {"height too big", withKeys(R"(, "height": 20000)"), "height"},
      {"eye == look_at", R"({"keys": [{"eye": [0,0,0], "look_at": [0,0,-1]},
                                      {"eye": [1,2,3], "look_at": [1,2,3]}], "frames": 2})",
       "keys[1]"},
      {"looking along up", R"({"keys": [{"eye": [0,0,0], "look_at": [0,5,0]}], "frames": 2})",
       "keys[0]"},
      {"eye has 2 numbers", R"({"keys": [{"eye": [0,0], "look_at": [0,0,-1]}], "frames": 2})",
       "keys[0].eye"},
      {"look_at element a string",
       R"({"keys": [{"eye": [0,0,0], "look_at": [0,"x",-1]}], "frames": 2})", "keys[0].look_at[1]"},
      {"missing look_at", R"({"keys": [{"eye": [0,0,0]}], "frames": 2})", "keys[0].look_at"},
      {"keys empty", R"({"keys": [], "frames": 2})", "keys"},
      {"keys not array", R"({"keys": {"eye": [0,0,0]}, "frames": 2})", "keys"},
      {"up zero", withKeys(R"(, "up": [0, 0, 0])"), "up"},
      {"number overflows to inf", withKeys(R"(, "far": 1e400)"), "1e400"},
      // Parsable but past what the renderer and the metrics can handle.
      {"width below SSIM's window", withKeys(R"(, "width": 10)"), "at least 11"},
      {"height 1", withKeys(R"(, "height": 1)"), "height"},
      {"eye at 1e308", R"({"keys": [{"eye": [1e308,0,0], "look_at": [0,0,-1]}], "frames": 2})",
       "keys[0].eye[0]"},
      {"look_at at -1e308", R"({"keys": [{"eye": [0,0,0], "look_at": [0,0,-1e308]}], "frames": 2})",
       "keys[0].look_at[2]"},
      {"up overflows", withKeys(R"(, "up": [1e308, 1e308, 0])"), "up[0]"},
      {"frames INT_MAX", R"({"keys": [{"eye": [0,0,0], "look_at": [0,0,-1]}], "frames": 2147483647})",
       "at most 1000000"},
      {"near subnormal", withKeys(R"(, "near": 5e-324)"), "blank"},
      {"fov 1e-300", withKeys(R"(, "fov_y_deg": 1e-300)"), "fov_y_deg"},
      {"far / near 1e10", withKeys(R"(, "near": 0.00001, "far": 100000)"), "far / near"},
      {"duplicate key", withKeys(R"(, "near": 1, "near": 2)"), "near: duplicate key"},
      {"nested 100 deep", std::string(100, '[') + std::string(100, ']'), "nested deeper"},
  };
  for (const BadCase& c : cases) {
    auto p = parseCameraPath(c.json, "bad.json");
    ASSERT_FALSE(p.ok()) << c.name;
    const std::string& m = p.error().message;
    EXPECT_NE(m.find("bad.json"), std::string::npos) << c.name << ": " << m;
    EXPECT_NE(m.find(c.mustContain), std::string::npos) << c.name << ": " << m;
  }
}

TEST(CameraPath, MessagesSayExpectedAndGot) {
  auto p = parseCameraPath(R"({"keys": [{"eye": [0,0,0], "look_at": [0,0,-1]}], "frames": 0})",
                           "path.json");
  ASSERT_FALSE(p.ok());
  EXPECT_EQ(p.error().message, "path.json: frames: expected an integer >= 1, got 0");
  auto q = parseCameraPath(withKeys(R"(, "near": "NaN")"), "path.json");
  ASSERT_FALSE(q.ok());
  EXPECT_EQ(q.error().message, "path.json: near: expected a number, got string \"NaN\"");
}

TEST(CameraPath, LoadReportsMissingFile) {
  auto p = loadCameraPath("/nonexistent/dir/path.json");
  ASSERT_FALSE(p.ok());
  EXPECT_NE(p.error().message.find("/nonexistent/dir/path.json"), std::string::npos);
}

TEST(CameraPath, CamerasEqualsCameraAtForEveryFrame) {
  // Four keys (moving, then a pure rotation at the end) and one key.
  CameraPath p;
  p.frames = 37;
  p.keys = {{{0, 1, 5}, {0, 1, 0}}, {{2, 1, 3}, {0, 1, -2}}, {{3, 2, 0}, {-1, 1, -4}},
            {{3, 2, 0}, {4, 1, -1}}};
  const std::vector<Camera> all = p.cameras();
  ASSERT_EQ(all.size(), 37u);
  for (int i = 0; i < p.frames; ++i) {
    const Camera c = p.cameraAt(i);
    EXPECT_EQ(all[static_cast<std::size_t>(i)].eye, c.eye) << i;
    EXPECT_EQ(all[static_cast<std::size_t>(i)].forward, c.forward) << i;
    EXPECT_EQ(all[static_cast<std::size_t>(i)].up, c.up) << i;
  }
  EXPECT_NE(all[1].eye, all[0].eye);
  CameraPath still;
  still.frames = 3;
  still.keys = {{{1, 2, 3}, {1, 2, 0}}};
  const std::vector<Camera> s3 = still.cameras();
  ASSERT_EQ(s3.size(), 3u);
  EXPECT_EQ(s3[2].eye, still.cameraAt(2).eye);
}

TEST(CameraPath, LimitsAdmitTheirEdgesAndGiveFiniteCameras) {
  const std::string edge = R"({"width": 11, "height": 11, "fov_y_deg": 0.001, "near": 0.000001,
      "far": 100, "keys": [{"eye": [1e9, 0, 0], "look_at": [-1e9, 0, -1]},
                           {"eye": [-1e9, 0, 0], "look_at": [1e9, 0, -1]}], "frames": 5})";
  auto p = parseCameraPath(edge, "edge.json");
  ASSERT_TRUE(p.ok()) << p.error().message;
  for (const Camera& c : p->cameras()) {
    EXPECT_TRUE(std::isfinite(c.eye.x) && std::isfinite(c.forward.x) && std::isfinite(c.up.y));
    EXPECT_TRUE(std::isfinite(c.fy()));
  }
}

}  // namespace
}  // namespace hw::scenes
