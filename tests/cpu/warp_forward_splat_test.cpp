// warp/forward_splat.h: the CPU forward splat the keyframe planner warps its
// probes with.
#include <gtest/gtest.h>

#include <cmath>

#include "warp/forward_splat.h"

namespace hw::warp {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The plane z = 0 seen from (0, 0, eyeZ) looking down −z, every pixel
// covered, each with its own colour.
SplatSource plane(double eyeZ, int size) {
  SplatSource s;
  s.camera = Camera::lookAt({0, 0, eyeZ}, {0, 0, eyeZ - 1}, {0, 1, 0}, 60 * kPi / 180, size, size,
                            0.1, 100);
  s.colour.resize(size, size);
  s.eyeZ.resize(size, size);
  s.covered.resize(size, size);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      s.colour(x, y) = Rgba8{static_cast<std::uint8_t>(x * 7), static_cast<std::uint8_t>(y * 7), 9, 255};
      s.eyeZ(x, y) = static_cast<float>(eyeZ);
      s.covered(x, y) = 1;
      s.point.push_back(s.camera.unproject(x + 0.5, y + 0.5, eyeZ));
    }
  return s;
}

TEST(ForwardSplat, IntoItsOwnCameraCopiesEveryPixel) {
  const SplatSource s = plane(5, 32);
  Layer out;
  const double stretch = forwardSplat(s, s.camera, out);
  EXPECT_NEAR(stretch, 0.0, 1e-6);
  ASSERT_EQ(out.colour.width(), 32);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) {
      ASSERT_EQ(out.coverage(x, y), 1) << x << "," << y;
      EXPECT_EQ(out.colour(x, y), s.colour(x, y)) << x << "," << y;
      EXPECT_NEAR(out.eyeZ(x, y), 5.0, 1e-4);
    }
}

TEST(ForwardSplat, AnEmptyPixelBecomesSky) {
  SplatSource s = plane(5, 32);
  s.covered(3, 4) = 0;
  s.point[4 * 32 + 3] = glm::normalize(s.point[4 * 32 + 3] - s.camera.eye);
  Layer out;
  forwardSplat(s, s.camera, out);
  EXPECT_EQ(out.coverage(3, 4), 1);
  EXPECT_EQ(out.eyeZ(3, 4), kSkyEyeZ);
  EXPECT_NEAR(out.eyeZ(4, 4), 5.0, 1e-4);
}

TEST(ForwardSplat, TwiceAsFarEachPixelCoversAQuarterAndTheRestIsEmpty) {
  const SplatSource s = plane(5, 32);
  const Camera far = plane(10, 32).camera;
  Layer out;
  const double stretch = forwardSplat(s, far, out);
  EXPECT_NEAR(stretch, 2.0, 1e-6);  // |log2(1/4)|
  EXPECT_EQ(out.coverage(0, 0), 0);
  EXPECT_EQ(out.coverage(16, 16), 1);
  EXPECT_NEAR(out.eyeZ(16, 16), 10.0, 1e-4);
}

}  // namespace
}  // namespace hw::warp
