// Quad validation (keyframe/quad_validation.h) and the LOD builder's
// splitMisfit on analytic keyframes (no GL): a leaf whose plane does not fit
// its pixels is caught, planar scenes flag nothing, and the split fixes it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "keyframe/analytic_scene.h"
#include "keyframe/lod_builder.h"
#include "keyframe/quad_validation.h"

namespace hw::keyframe {
namespace {

constexpr double kPi = 3.141592653589793;

// The LOD settings of the default preset (session/presets.cpp), spelt out
// here because the keyframe module does not see the session's presets.
LodOptions defaultLikeLod(bool splitMisfit) {
  LodOptions o;
  o.tauParallaxPx = 0.125;
  o.planarity = Planarity::RegionLocal;
  o.mergeStrips = true;
  o.splitMisfit = splitMisfit;
  return o;
}

QuadMesh build(const Keyframe& kf, const LodOptions& o, LodBuilder* b = nullptr) {
  LodBuilder own;
  LodBuilder& builder = b ? *b : own;
  QuadMesh mesh;
  const Status st = builder.build(kf, o, &mesh);
  EXPECT_TRUE(st.ok()) << (st.ok() ? "" : st.error().message);
  return mesh;
}

Camera moved(const Camera& c, const glm::dvec3& offset) {
  Camera t = c;
  t.eye += offset;
  return t;
}

// A viewer walking past a big ball standing just to its right (a pillar
// beside the viewer): the ball fills a third of the image.
AnalyticScene ballBesideTheViewer() {
  AnalyticScene s;
  s.planes.push_back({{0, 0, -20}, {0, 0, 1}, {200, 200, 200, 255}});  // far wall
  s.spheres.push_back({{0.9, 0.0, -2.2}, 0.8, {90, 140, 200, 255}});
  return s;
}

Camera viewer(int w, int h) {
  return Camera::lookAt({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, kPi / 3, w, h, 0.1, 100.0);
}

std::vector<Camera> walkTargets(const Camera& c) {
  // A step forward and a step sideways, as the in-between frames of a walk.
  return {moved(c, {0, 0, -0.5}), moved(c, {0.3, 0, 0}), moved(c, {-0.3, 0, -0.3})};
}

TEST(QuadValidation, NoErrorAtTheKeyframesOwnView) {
  // Pixel and quad points lie on one keyframe ray: they project to the same
  // keyframe position whatever the quad's depth is.
  const Camera cam = viewer(160, 120);
  const Keyframe kf = renderAnalyticKeyframe(ballBesideTheViewer(), cam);
  LodOptions paper;
  paper.tau = 32768.0;
  const QuadMesh mesh = build(kf, paper);
  const std::vector<Camera> self{cam};
  const QuadValidation v = validateQuads(kf, mesh, self);
  EXPECT_EQ(v.flagged, 0);
  EXPECT_LT(v.maxErrorPx, 1e-6);
  EXPECT_GT(v.checkedPixels, 0);
}

TEST(QuadValidation, PlanarRoomFlagsNothing) {
  // A box room (floor, walls, ceiling) and a box in it: every surface is a
  // plane, so every leaf fits its pixels, with the paper's settings and the
  // default ones.
  AnalyticScene s;
  s.boxes.push_back({{-3.0, -1.6, -8.0}, {3.0, 1.4, 0.5}, {210, 205, 190, 255}});
  s.boxes.push_back({{0.4, -1.6, -3.5}, {1.2, -0.4, -2.7}, {120, 150, 90, 255}});
  const Camera cam = viewer(200, 150);
  const Keyframe kf = renderAnalyticKeyframe(s, cam);
  const std::vector<Camera> targets = walkTargets(cam);
  LodOptions paper;
  for (const LodOptions& o : {paper, defaultLikeLod(false), defaultLikeLod(true)}) {
    const QuadMesh mesh = build(kf, o);
    const QuadValidation v = validateQuads(kf, mesh, targets);
    EXPECT_EQ(v.flagged, 0) << "worst " << v.maxErrorPx << " px at quad " << v.worstQuad;
    EXPECT_LT(v.maxErrorPx, 1.0);
    EXPECT_GT(v.checkedPixels, 0);
    EXPECT_EQ(v.quads.size(), mesh.quads.size());
  }
}

TEST(QuadValidation, CurvedSurfacePassingTheDeltaTestIsFlagged) {
  // The ball's |Δ²z'| per pixel is far below τ, so it is cut only at its
  // silhouette: its big leaves are planes cutting through the ball, which
  // warp sideways and enlarged. Without the split that is flagged.
  const Camera cam = viewer(200, 150);
  const Keyframe kf = renderAnalyticKeyframe(ballBesideTheViewer(), cam);
  const std::vector<Camera> targets = walkTargets(cam);
  LodOptions paper;
  for (const LodOptions& o : {paper, defaultLikeLod(false)}) {
    LodBuilder b;
    const QuadMesh mesh = build(kf, o, &b);
    // The premise: some leaf larger than a pixel passes the Δ² test but
    // departs from its own pixels by more than the fit tolerance.
    const QuadValidation v = validateQuads(kf, mesh, targets);
    EXPECT_GT(v.flagged, 0);
    EXPECT_GT(v.maxErrorPx, 2.0);
    ASSERT_GE(v.worstQuad, 0);
    const QuadCheck& worst = v.quads[static_cast<std::size_t>(v.worstQuad)];
    EXPECT_TRUE(worst.flagged);
    EXPECT_GT(worst.badPixels, 0);
    EXPECT_GT(worst.parallaxPxPerUnit, 1.0);
    // The worst pixel is on the ball (right half of the image).
    EXPECT_GT(worst.worstX, cam.width / 2);
    EXPECT_EQ(b.misfitSplits(), 0);
  }
}

TEST(QuadValidation, SplitMisfitLeavesFitAndFlagNothing) {
  const Camera cam = viewer(200, 150);
  const Keyframe kf = renderAnalyticKeyframe(ballBesideTheViewer(), cam);
  const std::vector<Camera> targets = walkTargets(cam);
  LodOptions paperSplit;
  paperSplit.splitMisfit = true;
  for (const LodOptions& o : {paperSplit, defaultLikeLod(true)}) {
    LodBuilder b;
    const QuadMesh mesh = build(kf, o, &b);
    EXPECT_GT(b.misfitSplits(), 0);
    const QuadValidation v = validateQuads(kf, mesh, targets);
    EXPECT_EQ(v.flagged, 0) << "worst " << v.maxErrorPx << " px at quad " << v.worstQuad;
    EXPECT_LT(v.maxErrorPx, 1.0);
    // Every leaf fits its pixels within the tolerance, in z' units.
    const double tol = b.misfitToleranceZPrime();
    for (const Quad& q : mesh.quads) {
      const PixelRect& r = q.rect;
      if (r.area() <= 2) continue;
      for (int y = r.y0; y < r.y1; ++y)
        for (int x = r.x0; x < r.x1; ++x) {
          const double zq = quadEyeZAt(q, x + 0.5, y + 0.5);
          const double zpQuad = zPrimeFromEyeZ(zq, cam.nearPlane, cam.farPlane);
          ASSERT_LE(std::fabs(zpQuad - kf.zPrime(x, y)), tol + 1.0)
              << "pixel " << x << "," << y << " of leaf " << r.x0 << "," << r.y0 << "-" << r.x1
              << "," << r.y1;
        }
    }
  }
}

TEST(QuadValidation, SplitMisfitLeavesAPlaneAlone) {
  // On one plane every leaf fits: the same leaves with and without the split.
  AnalyticScene s;
  s.planes.push_back({{0, 0, -9}, glm::normalize(glm::dvec3{0.3, 0.2, 1})});
  const Camera cam = viewer(128, 96);
  const Keyframe kf = renderAnalyticKeyframe(s, cam);
  LodOptions paper;
  for (const LodOptions& base : {paper, defaultLikeLod(false)}) {
    for (bool merge : {false, true}) {
      LodOptions a = base, b = base;
      a.mergeStrips = b.mergeStrips = merge;
      b.splitMisfit = true;
      LodBuilder bb;
      const QuadMesh ma = build(kf, a), mb = build(kf, b, &bb);
      EXPECT_EQ(bb.misfitSplits(), 0);
      ASSERT_EQ(ma.quads.size(), mb.quads.size());
      for (std::size_t i = 0; i < ma.quads.size(); ++i) {
        EXPECT_EQ(ma.quads[i].rect.x0, mb.quads[i].rect.x0);
        EXPECT_EQ(ma.quads[i].rect.y0, mb.quads[i].rect.y0);
        EXPECT_EQ(ma.quads[i].rect.x1, mb.quads[i].rect.x1);
        EXPECT_EQ(ma.quads[i].rect.y1, mb.quads[i].rect.y1);
      }
    }
  }
}

TEST(QuadValidation, RegionLocalCreaseCornersAreSplit) {
  // A floor meeting an oblique wall: region-local planarity never tests a
  // region's corner pixels, so a leaf may end with a corner pixel on the
  // other plane. With the split, every leaf of 2+ pixels fits its pixels
  // within the tolerance.
  AnalyticScene s;
  s.planes.push_back({{0, -1.6, 0}, {0, 1, 0}});
  s.planes.push_back({{0, 0, -9}, glm::normalize(glm::dvec3{0.3, 0, 1})});
  const Camera cam = viewer(128, 96);
  const Keyframe kf = renderAnalyticKeyframe(s, cam);
  auto worstResidual = [&](const QuadMesh& m) {
    double worst = 0;
    for (const Quad& q : m.quads)
      for (int y = q.rect.y0; y < q.rect.y1; ++y)
        for (int x = q.rect.x0; x < q.rect.x1; ++x) {
          const double zq = zPrimeFromEyeZ(quadEyeZAt(q, x + 0.5, y + 0.5), cam.nearPlane,
                                           cam.farPlane);
          worst = std::max(worst, std::fabs(zq - kf.zPrime(x, y)));
        }
    return worst;
  };
  LodBuilder b0, b1;
  const QuadMesh before = build(kf, defaultLikeLod(false), &b0);
  const QuadMesh after = build(kf, defaultLikeLod(true), &b1);
  EXPECT_GT(worstResidual(before), 2.0 * b0.mergeToleranceZPrime());
  EXPECT_LE(worstResidual(after), b1.misfitToleranceZPrime() + 1.0);
  EXPECT_GT(b1.misfitSplits(), 0);
}

TEST(QuadValidation, SyntheticBentLeafIsFlaggedUnlessSplit) {
  // z' bent along x with Δ²ₓ = τ/8 everywhere: every pixel passes the
  // paper's test, so the whole image is one leaf, whose plane misses the
  // middle and the edges by thousands of z' units.
  const int w = 64, h = 48;
  Keyframe kf;
  kf.camera = viewer(w, h);
  kf.colour.resize(w, h, Rgba8{128, 128, 128, 255});
  kf.zPrime.resize(w, h);
  kf.covered.resize(w, h, 1);
  const double tau = 2048.0, k = tau / 4;  // Δ²ₓ = 2·k/4 = τ/8
  const double zMid = zPrimeFromEyeZ(1.0, kf.camera.nearPlane, kf.camera.farPlane);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      kf.zPrime(x, y) = std::round(zMid + k * 64 - k * (x - w / 2.0) * (x - w / 2.0) / 4.0);
  LodOptions paper;
  paper.tau = tau;
  const QuadMesh one = build(kf, paper);
  ASSERT_EQ(one.quads.size(), 1u);
  const std::vector<Camera> targets{moved(kf.camera, {1.0, 0, 0})};
  const QuadValidation bad = validateQuads(kf, one, targets);
  EXPECT_EQ(bad.flagged, 1);
  EXPECT_GT(bad.quads[0].badPixels, 0);

  paper.splitMisfit = true;
  LodBuilder b;
  const QuadMesh split = build(kf, paper, &b);
  EXPECT_GT(split.quads.size(), 1u);
  EXPECT_GT(b.misfitSplits(), 0);
  const QuadValidation good = validateQuads(kf, split, targets);
  EXPECT_EQ(good.flagged, 0) << "worst " << good.maxErrorPx;
}

TEST(QuadValidation, ToleranceAndMinBadPixelsSelectTheFlags) {
  const Camera cam = viewer(200, 150);
  const Keyframe kf = renderAnalyticKeyframe(ballBesideTheViewer(), cam);
  const std::vector<Camera> targets = walkTargets(cam);
  const QuadMesh mesh = build(kf, defaultLikeLod(false));
  const QuadValidation strict = validateQuads(kf, mesh, targets);
  ASSERT_GT(strict.flagged, 0);
  QuadValidationOptions loose;
  loose.tolerancePx = strict.maxErrorPx * 1.01;
  EXPECT_EQ(validateQuads(kf, mesh, targets, loose).flagged, 0);
  QuadValidationOptions many;
  many.minBadPixels = 1 << 30;
  EXPECT_EQ(validateQuads(kf, mesh, targets, many).flagged, 0);
  // The counts add up.
  long long bad = 0;
  int flagged = 0;
  for (const QuadCheck& c : strict.quads) {
    bad += c.badPixels;
    flagged += c.flagged;
    EXPECT_LE(c.maxErrorPx, strict.maxErrorPx);
  }
  EXPECT_EQ(bad, strict.badPixels);
  EXPECT_EQ(flagged, strict.flagged);
}

}  // namespace
}  // namespace hw::keyframe
