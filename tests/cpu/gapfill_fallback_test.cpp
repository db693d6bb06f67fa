// The reprojected fallback (gapfill/fallback.h): the previous frame moved to
// the new camera by its depth, checked against the motion a plane must show.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "gapfill/fallback.h"

namespace hw::gapfill {
namespace {

constexpr int kW = 48, kH = 32;

Camera camera(glm::dvec3 eye) {
  return Camera::lookAt(eye, eye + glm::dvec3(0, 0, -1), {0, 1, 0}, 1.0471975511965976, kW, kH,
                        0.1, 1000.0);
}

// A frame of distinct colours (x, y coded) at depth z everywhere.
Frame planeFrame(const Camera& cam, float z) {
  Frame f;
  f.colour.resize(kW, kH);
  f.valid.resize(kW, kH, 1);
  f.holesBefore.resize(kW, kH, 0);
  f.eyeZ.resize(kW, kH, z);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      f.colour(x, y) = Rgba8{static_cast<std::uint8_t>(x * 5), static_cast<std::uint8_t>(y * 7), 9, 255};
  f.camera = cam;
  return f;
}

TEST(ReprojectFrame, SameCameraIsTheIdentity) {
  const Camera cam = camera({0, 0, 0});
  Frame prev = planeFrame(cam, 5.0f);
  prev.valid(3, 4) = 0;  // an unfilled pixel is not carried
  Frame out;
  reprojectFrame(prev, cam, out);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      if (x == 3 && y == 4) continue;
      ASSERT_EQ(out.valid(x, y), 1) << x << "," << y;
      EXPECT_EQ(out.colour(x, y), prev.colour(x, y));
      EXPECT_NEAR(out.eyeZ(x, y), 5.0f, 1e-5f);
    }
  // The gap is a crack inside written pixels: closed from a neighbour (2),
  // unless the caller does not want that pixel.
  EXPECT_EQ(out.valid(3, 4), 2);
  Image<std::uint8_t> wanted(kW, kH, 1);
  reprojectFrame(prev, cam, out, &wanted);
  EXPECT_EQ(out.valid(3, 4), 0);
  EXPECT_EQ(out.camera.eye, cam.eye);
}

TEST(ReprojectFrame, SidewaysMotionShiftsAPlaneByItsParallax) {
  const Camera a = camera({0, 0, 0});
  const double z = 5.0;
  const double dx = 2.0 * z / a.fx();  // 2 pixels of parallax
  const Camera b = camera({dx, 0, 0});
  const Frame prev = planeFrame(a, static_cast<float>(z));
  Frame out;
  reprojectFrame(prev, b, out);
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x + 2 < kW; ++x) {
      ASSERT_EQ(out.valid(x, y), 1) << x << "," << y;
      EXPECT_EQ(out.colour(x, y), prev.colour(x + 2, y)) << x << "," << y;
    }
    // What came into view on the right was not in the previous frame.
    EXPECT_EQ(out.valid(kW - 1, y), 0);
    EXPECT_EQ(out.valid(kW - 2, y), 0);
  }
}

TEST(ReprojectFrame, SkyMovesWithRotationOnly) {
  const Camera a = camera({0, 0, 0});
  Frame prev = planeFrame(a, warp::kSkyEyeZ);
  Frame out;
  reprojectFrame(prev, camera({3, 1, -2}), out);  // translated: points at infinity stay
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      EXPECT_EQ(out.colour(x, y), prev.colour(x, y));
      EXPECT_EQ(out.eyeZ(x, y), warp::kSkyEyeZ);
    }
  // Turned by one pixel's angle at the centre: the sky moves by about one pixel.
  const double yaw = std::atan(1.0 / a.fx());
  const Camera turned = Camera::lookAt({0, 0, 0}, {std::sin(yaw), 0, -std::cos(yaw)}, {0, 1, 0},
                                       a.fovYRadians, kW, kH, 0.1, 1000.0);
  reprojectFrame(prev, turned, out);
  EXPECT_EQ(out.colour(kW / 2, kH / 2), prev.colour(kW / 2 + 1, kH / 2));
}

TEST(ReprojectFrame, NearerPointWinsWhereTwoLand) {
  // Left half near (z 2), right half far (z 20); moving left shifts the near
  // half right by 4 px and the far one by 0.4 px: the near half covers the
  // far one's first columns.
  const Camera a = camera({0, 0, 0});
  Frame prev = planeFrame(a, 20.0f);
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW / 2; ++x) {
      prev.eyeZ(x, y) = 2.0f;
      prev.colour(x, y) = Rgba8{255, 0, 0, 255};
    }
  const double dx = -4.0 * 2.0 / a.fx();
  Frame out;
  reprojectFrame(prev, camera({dx, 0, 0}), out);
  for (int y = 0; y < kH; ++y)
    for (int x = kW / 2; x < kW / 2 + 4; ++x) {
      EXPECT_EQ(out.colour(x, y), (Rgba8{255, 0, 0, 255})) << x << "," << y;
      EXPECT_NEAR(out.eyeZ(x, y), 2.0f, 1e-4f);
    }
  EXPECT_NE(out.colour(kW / 2 + 6, kH / 2), (Rgba8{255, 0, 0, 255}));
}

TEST(ReprojectFrame, MovingForwardLeavesNoCracks) {
  const Camera a = camera({0, 0, 0});
  const Frame prev = planeFrame(a, 5.0f);
  Frame out;
  reprojectFrame(prev, camera({0, 0, -0.5}), out);  // 11 % magnification
  int empty = 0;
  for (int y = 2; y < kH - 2; ++y)
    for (int x = 2; x < kW - 2; ++x) empty += out.valid(x, y) == 0;
  EXPECT_EQ(empty, 0);
  EXPECT_NEAR(out.eyeZ(kW / 2, kH / 2), 4.5f, 1e-4f);
}

TEST(ReprojectFrame, BehindTheEyeIsDropped) {
  const Camera a = camera({0, 0, 0});
  const Frame prev = planeFrame(a, 5.0f);
  Frame out;
  reprojectFrame(prev, camera({0, 0, -10}), out);  // walked through the plane
  for (std::size_t i = 0; i < out.valid.size(); ++i) ASSERT_EQ(out.valid.data()[i], 0);
}

TEST(FillHoles, ReprojectedFirstThenTheSamePixel) {
  Frame out;
  out.colour.resize(4, 1, kUnfilledColour);
  out.valid.resize(4, 1, 0);
  out.holesBefore.resize(4, 1, 1);
  out.eyeZ.resize(4, 1, 0.0f);
  out.valid(0, 0) = 1;  // a layer pixel: untouched
  out.holesBefore(0, 0) = 0;
  out.colour(0, 0) = Rgba8{1, 1, 1, 255};
  out.unfilled = 3;
  Frame rep;
  rep.colour.resize(4, 1, Rgba8{2, 2, 2, 255});
  rep.valid.resize(4, 1, 0);
  rep.eyeZ.resize(4, 1, 7.0f);
  rep.valid(0, 0) = rep.valid(1, 0) = 1;
  Frame same;
  same.colour.resize(4, 1, Rgba8{3, 3, 3, 255});
  same.valid.resize(4, 1, 1);
  same.valid(3, 0) = 0;
  const FillStats fs = fillHoles(rep, &same, out);
  EXPECT_EQ(fs.reprojected, 1);
  EXPECT_EQ(fs.copied, 1);
  EXPECT_EQ(out.colour(0, 0), (Rgba8{1, 1, 1, 255}));
  EXPECT_EQ(out.colour(1, 0), (Rgba8{2, 2, 2, 255}));
  EXPECT_EQ(out.eyeZ(1, 0), 7.0f);
  EXPECT_EQ(out.colour(2, 0), (Rgba8{3, 3, 3, 255}));
  EXPECT_EQ(out.eyeZ(2, 0), 0.0f);
  EXPECT_EQ(out.colour(3, 0), kUnfilledColour);
  EXPECT_EQ(out.valid(3, 0), 0);
  EXPECT_EQ(out.fromPrevious, 2);
  EXPECT_EQ(out.unfilled, 1);
  EXPECT_DOUBLE_EQ(out.holeFractionAfter, 0.25);
}

TEST(LayerDepth, OverlayTakesTheForegroundMergeTheNearer) {
  warp::Layer fg, bg;
  for (warp::Layer* l : {&fg, &bg}) {
    l->colour.resize(4, 1);
    l->coverage.resize(4, 1, 0);
    l->eyeZ.resize(4, 1, 0.0f);
  }
  fg.coverage(0, 0) = fg.coverage(1, 0) = 1;
  fg.eyeZ(0, 0) = fg.eyeZ(1, 0) = 9.0f;
  bg.coverage(1, 0) = bg.coverage(2, 0) = 1;
  bg.eyeZ(1, 0) = bg.eyeZ(2, 0) = 4.0f;
  Frame out;
  layerDepth(fg, &bg, false, out);
  EXPECT_EQ(out.eyeZ(0, 0), 9.0f);
  EXPECT_EQ(out.eyeZ(1, 0), 9.0f);
  EXPECT_EQ(out.eyeZ(2, 0), 4.0f);
  EXPECT_EQ(out.eyeZ(3, 0), 0.0f);
  layerDepth(fg, &bg, true, out);
  EXPECT_EQ(out.eyeZ(1, 0), 4.0f);
}

TEST(ReprojectFrame, SecondCallDoesNotReallocate) {
  const Camera a = camera({0, 0, 0});
  const Frame prev = planeFrame(a, 5.0f);
  Frame out;
  reprojectFrame(prev, camera({0.1, 0, 0}), out);
  const Rgba8* c = out.colour.data();
  const float* z = out.eyeZ.data();
  reprojectFrame(prev, camera({0.2, 0, 0}), out);
  EXPECT_EQ(out.colour.data(), c);
  EXPECT_EQ(out.eyeZ.data(), z);
}

TEST(Fallback, NamesRoundTrip) {
  for (Fallback f : {Fallback::Copy, Fallback::Reproject}) {
    Fallback parsed{};
    ASSERT_TRUE(parseFallback(fallbackName(f), &parsed));
    EXPECT_EQ(parsed, f);
  }
  Fallback parsed{};
  EXPECT_FALSE(parseFallback("nearest", &parsed));
  EXPECT_FALSE(parseFallback(nullptr, &parsed));
}

}  // namespace
}  // namespace hw::gapfill
