// Composition rules (gapfill/compose.h, Zheng et al. 1999 §2.2) on small
// constructed layers whose expected result is known pixel by pixel.
#include <gtest/gtest.h>

#include <cstdint>

#include "gapfill/compose.h"

namespace hw::gapfill {
namespace {

constexpr Rgba8 kFg{200, 0, 0, 255};
constexpr Rgba8 kBg{0, 200, 0, 255};
constexpr Rgba8 kPrev{0, 0, 200, 255};

// Nothing covered; eyeZ 0 (the warper's value where not covered).
warp::Layer makeLayer(int w, int h, Rgba8 colour) {
  warp::Layer l;
  l.colour.resize(w, h, colour);
  l.coverage.resize(w, h, 0);
  l.eyeZ.resize(w, h, 0.0f);
  return l;
}

void cover(warp::Layer& l, int x, int y, float eyeZ) {
  l.coverage(x, y) = 1;
  l.eyeZ(x, y) = eyeZ;
}

// Covers columns [x0, x1) of every row.
void coverColumns(warp::Layer& l, int x0, int x1, float eyeZ) {
  for (int y = 0; y < l.colour.height(); ++y)
    for (int x = x0; x < x1; ++x) cover(l, x, y, eyeZ);
}

Frame makePrevious(int w, int h, Rgba8 colour) {
  Frame f;
  f.colour.resize(w, h, colour);
  f.valid.resize(w, h, 1);
  f.holesBefore.resize(w, h, 0);
  return f;
}

TEST(Compose, ForegroundHasPriorityAndBackgroundFillsTheRest) {
  // 10 columns: fg covers 0..5, bg covers 3..8, column 9 is a hole.
  warp::Layer fg = makeLayer(10, 3, kFg);
  warp::Layer bg = makeLayer(10, 3, kBg);
  coverColumns(fg, 0, 6, 5.0f);
  coverColumns(bg, 3, 9, 1.0f);  // much nearer, but Overlay ignores depth
  Frame out;
  compose(fg, &bg, nullptr, ComposeOptions{}, out);
  for (int y = 0; y < 3; ++y) {
    for (int x = 0; x < 6; ++x) EXPECT_EQ(out.colour(x, y), kFg) << x;
    for (int x = 6; x < 9; ++x) EXPECT_EQ(out.colour(x, y), kBg) << x;
    EXPECT_EQ(out.colour(9, y), kUnfilledColour);
    EXPECT_EQ(out.valid(9, y), 0);
    EXPECT_EQ(out.holesBefore(9, y), 1);
    EXPECT_EQ(out.holesBefore(0, y), 0);
    EXPECT_EQ(out.valid(0, y), 1);
  }
  EXPECT_EQ(out.fromForeground, 18);
  EXPECT_EQ(out.fromBackground, 9);
  EXPECT_EQ(out.fromPrevious, 0);
  EXPECT_EQ(out.unfilled, 3);
}

TEST(Compose, PreviousFrameFillsHolesAndIsCounted) {
  warp::Layer fg = makeLayer(8, 2, kFg);
  warp::Layer bg = makeLayer(8, 2, kBg);
  coverColumns(fg, 0, 4, 2.0f);
  coverColumns(bg, 4, 6, 2.0f);
  Frame prev = makePrevious(8, 2, kPrev);
  prev.valid(7, 1) = 0;  // the previous frame had a hole here too
  Frame out;
  compose(fg, &bg, &prev, ComposeOptions{}, out);
  EXPECT_EQ(out.colour(6, 0), kPrev);
  EXPECT_EQ(out.colour(7, 0), kPrev);
  EXPECT_EQ(out.colour(6, 1), kPrev);
  EXPECT_EQ(out.colour(7, 1), kUnfilledColour);
  EXPECT_EQ(out.valid(6, 0), 1);
  EXPECT_EQ(out.valid(7, 1), 0);
  EXPECT_EQ(out.holesBefore(6, 0), 1);
  EXPECT_EQ(out.fromForeground, 8);
  EXPECT_EQ(out.fromBackground, 4);
  EXPECT_EQ(out.fromPrevious, 3);
  EXPECT_EQ(out.unfilled, 1);
  EXPECT_DOUBLE_EQ(out.holeFractionBefore, 4.0 / 16.0);
  EXPECT_DOUBLE_EQ(out.holeFractionAfter, 1.0 / 16.0);
}

TEST(Compose, FirstFrameLeavesHolesUnfilled) {
  warp::Layer fg = makeLayer(4, 4, kFg);
  cover(fg, 1, 1, 3.0f);
  Frame out;
  compose(fg, nullptr, nullptr, ComposeOptions{}, out);
  EXPECT_EQ(out.colour(1, 1), kFg);
  EXPECT_EQ(out.colour(0, 0), kUnfilledColour);
  EXPECT_EQ(out.fromForeground, 1);
  EXPECT_EQ(out.fromBackground, 0);
  EXPECT_EQ(out.fromPrevious, 0);
  EXPECT_EQ(out.unfilled, 15);
  EXPECT_DOUBLE_EQ(out.holeFractionBefore, 15.0 / 16.0);
  EXPECT_DOUBLE_EQ(out.holeFractionAfter, 15.0 / 16.0);
}

TEST(Compose, HoleFractionsExactOnConstructedMasks) {
  // 16×16; fg covers a 6×6 block, bg an overlapping 8×4 block, previous valid
  // on the left half only.
  constexpr int kW = 16, kH = 16;
  warp::Layer fg = makeLayer(kW, kH, kFg);
  warp::Layer bg = makeLayer(kW, kH, kBg);
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 6; ++x) cover(fg, x, y, 1.0f);
  for (int y = 4; y < 8; ++y)
    for (int x = 2; x < 10; ++x) cover(bg, x, y, 1.0f);
  Frame prev = makePrevious(kW, kH, kPrev);
  for (int y = 0; y < kH; ++y)
    for (int x = kW / 2; x < kW; ++x) prev.valid(x, y) = 0;

  // Union of the blocks: 36 + 32 − overlap (x 2..5, y 4..5 = 8) = 60.
  int expectHoles = 0, expectPrev = 0;
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      const bool covered = fg.coverage(x, y) || bg.coverage(x, y);
      expectHoles += !covered;
      expectPrev += !covered && x < kW / 2;
    }
  }
  ASSERT_EQ(expectHoles, 256 - 60);

  for (ComposeMode mode : {ComposeMode::Overlay, ComposeMode::DepthMerge}) {
    Frame out;
    compose(fg, &bg, &prev, ComposeOptions{mode, 0.02f}, out);
    EXPECT_EQ(out.fromForeground, 36);
    EXPECT_EQ(out.fromBackground, 24);
    EXPECT_EQ(out.fromPrevious, expectPrev);
    EXPECT_EQ(out.unfilled, expectHoles - expectPrev);
    EXPECT_EQ(out.fromForeground + out.fromBackground + out.fromPrevious + out.unfilled, 256);
    EXPECT_DOUBLE_EQ(out.holeFractionBefore, expectHoles / 256.0);
    EXPECT_DOUBLE_EQ(out.holeFractionAfter, (expectHoles - expectPrev) / 256.0);
    int holes = 0, invalid = 0;
    for (int y = 0; y < kH; ++y) {
      for (int x = 0; x < kW; ++x) {
        holes += out.holesBefore(x, y);
        invalid += out.valid(x, y) == 0;
      }
    }
    EXPECT_EQ(holes, expectHoles);
    EXPECT_EQ(invalid, out.unfilled);
  }
}

TEST(Compose, DepthMergeTakesClearlyNearerBackgroundOnly) {
  // Both layers cover all 4 pixels; fg at depth 10 everywhere; bg at:
  //   x=0: 5     (clearly nearer → bg)
  //   x=1: 9.9   (nearer by 1 %, within the 2 % tolerance → fg)
  //   x=2: 9.79  (nearer by 2.1 % → bg)
  //   x=3: 20    (farther → fg)
  warp::Layer fg = makeLayer(4, 1, kFg);
  warp::Layer bg = makeLayer(4, 1, kBg);
  const float bgZ[4] = {5.0f, 9.9f, 9.79f, 20.0f};
  for (int x = 0; x < 4; ++x) {
    cover(fg, x, 0, 10.0f);
    cover(bg, x, 0, bgZ[x]);
  }
  Frame out;
  compose(fg, &bg, nullptr, ComposeOptions{ComposeMode::DepthMerge, 0.02f}, out);
  EXPECT_EQ(out.colour(0, 0), kBg);
  EXPECT_EQ(out.colour(1, 0), kFg);
  EXPECT_EQ(out.colour(2, 0), kBg);
  EXPECT_EQ(out.colour(3, 0), kFg);
  EXPECT_EQ(out.fromForeground, 2);
  EXPECT_EQ(out.fromBackground, 2);

  // Overlay ignores depth: foreground everywhere.
  compose(fg, &bg, nullptr, ComposeOptions{ComposeMode::Overlay, 0.02f}, out);
  EXPECT_EQ(out.fromForeground, 4);
  EXPECT_EQ(out.fromBackground, 0);

  // Zero tolerance: strictly nearer wins.
  compose(fg, &bg, nullptr, ComposeOptions{ComposeMode::DepthMerge, 0.0f}, out);
  EXPECT_EQ(out.colour(1, 0), kBg);
  EXPECT_EQ(out.fromBackground, 3);
}

TEST(Compose, DepthMergeIgnoresDepthWhereOnlyOneLayerCovers) {
  warp::Layer fg = makeLayer(3, 1, kFg);
  warp::Layer bg = makeLayer(3, 1, kBg);
  cover(fg, 0, 0, 100.0f);
  cover(bg, 1, 0, 100.0f);
  fg.eyeZ(1, 0) = 50.0f;  // stale depth under no coverage must not matter
  bg.eyeZ(0, 0) = 1.0f;
  Frame out;
  compose(fg, &bg, nullptr, ComposeOptions{ComposeMode::DepthMerge, 0.02f}, out);
  EXPECT_EQ(out.colour(0, 0), kFg);
  EXPECT_EQ(out.colour(1, 0), kBg);
  EXPECT_EQ(out.colour(2, 0), kUnfilledColour);
}

TEST(Compose, DepthMergeLetsGeometryBeatTheSkyBackdrop) {
  // Sky pixels are covered at warp::kSkyEyeZ (finite, huge): any real surface
  // of the other layer is nearer; sky against sky stays foreground.
  warp::Layer fg = makeLayer(3, 1, kFg);
  warp::Layer bg = makeLayer(3, 1, kBg);
  cover(fg, 0, 0, warp::kSkyEyeZ);
  cover(bg, 0, 0, 50.0f);
  cover(fg, 1, 0, warp::kSkyEyeZ);
  cover(bg, 1, 0, warp::kSkyEyeZ);
  cover(fg, 2, 0, 50.0f);
  cover(bg, 2, 0, warp::kSkyEyeZ);
  Frame out;
  compose(fg, &bg, nullptr, ComposeOptions{ComposeMode::DepthMerge, 0.02f}, out);
  EXPECT_EQ(out.colour(0, 0), kBg);
  EXPECT_EQ(out.colour(1, 0), kFg);
  EXPECT_EQ(out.colour(2, 0), kFg);
}

TEST(Compose, SecondCallDoesNotReallocate) {
  warp::Layer fg = makeLayer(32, 16, kFg);
  warp::Layer bg = makeLayer(32, 16, kBg);
  coverColumns(fg, 0, 10, 1.0f);
  coverColumns(bg, 5, 20, 2.0f);
  Frame prev = makePrevious(32, 16, kPrev);
  Frame out;
  compose(fg, &bg, &prev, ComposeOptions{}, out);
  const Rgba8* colour = out.colour.data();
  const std::uint8_t* holes = out.holesBefore.data();
  const std::uint8_t* valid = out.valid.data();
  for (ComposeMode mode : {ComposeMode::Overlay, ComposeMode::DepthMerge}) {
    compose(fg, &bg, &prev, ComposeOptions{mode, 0.02f}, out);
    EXPECT_EQ(out.colour.data(), colour);
    EXPECT_EQ(out.holesBefore.data(), holes);
    EXPECT_EQ(out.valid.data(), valid);
  }
  // Ping-pong: the last frame becomes `previous` of the next.
  Frame next;
  compose(fg, nullptr, &out, ComposeOptions{}, next);
  EXPECT_EQ(next.fromPrevious, 32 * 16 - 10 * 16);
  EXPECT_EQ(next.colour(15, 3), kBg);
}

// Blend on a 3×3 frame whose centre pixel looks straight down W (the default
// camera: eye at the origin, W = −z); both layers cover every pixel.
struct BlendCase {
  warp::Layer fg = makeLayer(3, 3, kFg);
  warp::Layer bg = makeLayer(3, 3, kBg);
  BlendViews views;
  BlendCase(float zFg, float zBg, glm::dvec3 fgEye, glm::dvec3 bgEye) {
    coverColumns(fg, 0, 3, zFg);
    coverColumns(bg, 0, 3, zBg);
    views.camera.width = views.camera.height = 3;
    views.foregroundEye = fgEye;
    views.backgroundEye = bgEye;
  }
  Frame run(float softness = 0.05f) {
    ComposeOptions o;
    o.mode = ComposeMode::Blend;
    o.blendSoftness = softness;
    Frame out;
    compose(fg, &bg, nullptr, o, &views, out);
    return out;
  }
};

TEST(ComposeBlend, SymmetricViewsGiveTheMean) {
  BlendCase c(5.0f, 5.0f, {-1, 0, 0}, {1, 0, 0});
  const Frame out = c.run();
  EXPECT_EQ(out.colour(1, 1), (Rgba8{100, 100, 0, 255}));
  EXPECT_EQ(out.blended, 9);
  EXPECT_EQ(out.fromForeground + out.fromBackground, 9);
  EXPECT_EQ(out.unfilled, 0);
}

TEST(ComposeBlend, TheViewFromTheFramesEyeDominates) {
  // Foreground keyframe at the frame's eye: no penalty; the background one
  // 1 unit aside sees the point at 5 units 0.2 rad off: weight
  // 1/(1 + e^(0.2/0.05)) ≈ 0.02.
  BlendCase c(5.0f, 5.0f, {0, 0, 0}, {1, 0, 0});
  const Frame out = c.run();
  EXPECT_GE(out.colour(1, 1).r, 194);
  EXPECT_LE(out.colour(1, 1).g, 6);
  EXPECT_GT(out.colour(1, 1).g, 0);  // blended, not picked
  EXPECT_EQ(out.fromForeground, 9);
  // Roles swapped: the background now has the frame's view.
  BlendCase d(5.0f, 5.0f, {1, 0, 0}, {0, 0, 0});
  EXPECT_GE(d.run().colour(1, 1).g, 194);
}

TEST(ComposeBlend, WeightFallsWithAngleAndMagnification) {
  const glm::vec3 ray{0, 0, -5};
  float last = 0.5f;
  for (float off : {0.25f, 0.5f, 1.0f, 2.0f}) {
    const float w = blendBackgroundWeight(ray, {0, 0, 0}, {off, 0, 0}, 0.05f);
    EXPECT_LT(w, last) << off;
    last = w;
  }
  // On the ray, farther from the point = more magnified = less weight; a
  // keyframe nearer to the point than the frame is not penalised.
  EXPECT_LT(blendBackgroundWeight(ray, {0, 0, 0}, {0, 0, 2}, 0.05f), 0.01f);
  EXPECT_GT(blendBackgroundWeight(ray, {0, 0, 2}, {0, 0, 0}, 0.05f), 0.99f);
  EXPECT_FLOAT_EQ(blendBackgroundWeight(ray, {0, 0, -1}, {0, 0, -2}, 0.05f), 0.5f);
  // Softer = closer to the mean.
  EXPECT_GT(blendBackgroundWeight(ray, {0, 0, 0}, {1, 0, 0}, 0.5f),
            blendBackgroundWeight(ray, {0, 0, 0}, {1, 0, 0}, 0.05f));
}

TEST(ComposeBlend, InconsistentDepthTakesTheNearerAndSkyIsMixedEvenly) {
  BlendCase nearBg(10.0f, 5.0f, {0, 0, 0}, {1, 0, 0});
  Frame out = nearBg.run();
  EXPECT_EQ(out.colour(1, 1), kBg);
  EXPECT_EQ(out.blended, 0);
  EXPECT_EQ(out.fromBackground, 9);
  BlendCase nearFg(5.0f, 10.0f, {1, 0, 0}, {0, 0, 0});
  out = nearFg.run();
  EXPECT_EQ(out.colour(1, 1), kFg);
  BlendCase sky(warp::kSkyEyeZ, warp::kSkyEyeZ, {0, 0, 0}, {50, 0, 0});
  out = sky.run();
  EXPECT_EQ(out.colour(1, 1), (Rgba8{100, 100, 0, 255}));
  BlendCase skyBg(5.0f, warp::kSkyEyeZ, {0, 0, 0}, {1, 0, 0});
  EXPECT_EQ(skyBg.run().colour(0, 0), kFg);
}

TEST(ComposeBlend, OneLayerPixelsHolesAndCountsAsOtherModes) {
  warp::Layer fg = makeLayer(10, 3, kFg);
  warp::Layer bg = makeLayer(10, 3, kBg);
  coverColumns(fg, 0, 6, 5.0f);
  coverColumns(bg, 3, 9, 5.0f);
  Frame prev = makePrevious(10, 3, kPrev);
  BlendViews views;
  views.camera.width = 10;
  views.camera.height = 3;
  views.foregroundEye = {-0.5, 0, 0};
  views.backgroundEye = {0.5, 0, 0};
  ComposeOptions o;
  o.mode = ComposeMode::Blend;
  Frame out;
  compose(fg, &bg, &prev, o, &views, out);
  EXPECT_EQ(out.blended, 9);  // columns 3..5
  EXPECT_EQ(out.colour(0, 0), kFg);
  EXPECT_EQ(out.colour(7, 1), kBg);
  EXPECT_EQ(out.colour(9, 2), kPrev);
  EXPECT_EQ(out.fromPrevious, 3);
  EXPECT_EQ(out.fromForeground + out.fromBackground + out.fromPrevious + out.unfilled, 30);
  EXPECT_EQ(out.holesBefore(9, 0), 1);
  const Rgba8 m = out.colour(4, 1);
  EXPECT_GT(m.r, 0);
  EXPECT_GT(m.g, 0);
  EXPECT_NEAR(int(m.r) + int(m.g), 200, 1);
  // Without a background the blend is the overlay.
  Frame one;
  compose(fg, nullptr, &prev, o, nullptr, one);
  EXPECT_EQ(one.fromForeground, 18);
  EXPECT_EQ(one.blended, 0);
}

TEST(Compose, ModeNamesRoundTrip) {
  for (ComposeMode m : {ComposeMode::Overlay, ComposeMode::DepthMerge, ComposeMode::Blend}) {
    ComposeMode parsed{};
    ASSERT_TRUE(parseComposeMode(composeModeName(m), &parsed));
    EXPECT_EQ(parsed, m);
  }
  ComposeMode parsed{};
  EXPECT_FALSE(parseComposeMode("zbuffer", &parsed));
  EXPECT_FALSE(parseComposeMode(nullptr, &parsed));
}

TEST(ChooseForeground, NearerEyeWins) {
  const glm::dvec3 a{0, 0, 0}, b{10, 0, 0};
  EXPECT_EQ(chooseForeground({1, 0, 0}, a, b), 0);
  EXPECT_EQ(chooseForeground({9, 0, 0}, a, b), 1);
  EXPECT_EQ(chooseForeground({5.001, 0, 0}, a, b), 1);
  EXPECT_EQ(chooseForeground({4.999, 3, 0}, a, b), 0);
  EXPECT_EQ(chooseForeground(b, a, b), 1);
}

TEST(ChooseForeground, TieGoesToTheEarlierKeyframe) {
  const glm::dvec3 a{0.1, 0.2, 0.3}, b{1.7, -0.4, 2.9};
  const glm::dvec3 mid = 0.5 * (a + b);
  EXPECT_EQ(chooseForeground(mid, a, b), 0);
  // Swapping the roles: the first argument still wins the tie.
  EXPECT_EQ(chooseForeground(mid, b, a), 0);
  // A rounding-level difference is still a tie.
  const glm::dvec3 nudged = mid + 1e-12 * (b - a);
  EXPECT_EQ(chooseForeground(nudged, a, b), 0);
  EXPECT_EQ(chooseForeground(mid - 1e-12 * (b - a), b, a), 0);
  // Off the segment, equidistant points are ties too.
  const glm::dvec3 perpendicular = glm::cross(b - a, glm::dvec3(0, 0, 1));
  EXPECT_EQ(chooseForeground(mid + 3.0 * perpendicular, a, b), 0);
  EXPECT_EQ(chooseForeground(mid + 3.0 * perpendicular, b, a), 0);
  // Degenerate: all three equal.
  EXPECT_EQ(chooseForeground(a, a, a), 0);
}

using ComposeDeathTest = ::testing::Test;

TEST_F(ComposeDeathTest, PreconditionsAreChecked) {
  warp::Layer fg = makeLayer(4, 4, kFg);
  warp::Layer bg = makeLayer(4, 5, kBg);
  Frame out;
  EXPECT_DEATH(compose(fg, &bg, nullptr, ComposeOptions{}, out), "CHECK failed");
  Frame prev = makePrevious(4, 4, kPrev);
  EXPECT_DEATH(compose(fg, nullptr, &prev, ComposeOptions{}, prev), "CHECK failed");
  Frame small = makePrevious(3, 4, kPrev);
  EXPECT_DEATH(compose(fg, nullptr, &small, ComposeOptions{}, out), "CHECK failed");
  warp::Layer noDepth = makeLayer(4, 4, kBg);
  noDepth.eyeZ = Image<float>();
  EXPECT_DEATH(compose(fg, &noDepth, nullptr, ComposeOptions{ComposeMode::DepthMerge, 0.02f}, out),
               "CHECK failed");
  warp::Layer bg4 = makeLayer(4, 4, kBg);
  EXPECT_DEATH(compose(fg, &bg4, nullptr, ComposeOptions{ComposeMode::Blend, 0.02f}, out),
               "CHECK failed");  // no views
  BlendViews wrongSize;  // a 512×512 camera for 4×4 layers
  EXPECT_DEATH(
      compose(fg, &bg4, nullptr, ComposeOptions{ComposeMode::Blend, 0.02f}, &wrongSize, out),
      "CHECK failed");
}

}  // namespace
}  // namespace hw::gapfill
