// Baseline meshes (uniform tiles with empty-tile removal, after Yang & Crawfis'
// Rail-Track viewer; one quad per pixel) and LodBuilder::buildFromRects, on
// analytic keyframes (no GL).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "keyframe/analytic_scene.h"
#include "keyframe/baseline_mesh.h"
#include "keyframe/lod_builder.h"

namespace hw::keyframe {
namespace {

constexpr double kPi = 3.141592653589793;

bool validPixel(const Keyframe& kf, int x, int y) {
  return kf.covered(x, y) != 0 && std::isfinite(kf.zPrime(x, y));
}

long long validCount(const Keyframe& kf) {
  long long n = 0;
  for (int y = 0; y < kf.zPrime.height(); ++y)
    for (int x = 0; x < kf.zPrime.width(); ++x) n += validPixel(kf, x, y);
  return n;
}

// The room's furniture without the room: objects against an empty background,
// so tiles along silhouettes are mixed. A few covered pixels get a non-finite
// z', which every path must treat as empty.
Keyframe objectsKeyframe(int w, int h) {
  AnalyticScene s = makeRoomScene();
  s.boxes.erase(s.boxes.begin());
  Keyframe kf = renderAnalyticKeyframe(s, makeRoomCamera(w, h));
  int poisoned = 0;
  for (int y = h / 3; y < h && poisoned < 3; y += 7)
    for (int x = w / 3; x < w && poisoned < 3; x += 5)
      if (kf.covered(x, y) != 0) {
        kf.zPrime(x, y) = poisoned % 2 == 0 ? std::numeric_limits<double>::quiet_NaN()
                                            : std::numeric_limits<double>::infinity();
        ++poisoned;
      }
  EXPECT_EQ(poisoned, 3);
  return kf;
}

Camera frontCamera(int w, int h) {
  return Camera::lookAt({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, kPi / 3, w, h, 0.1, 100.0);
}

Keyframe planeKeyframe(int w, int h, const glm::dvec3& point, const glm::dvec3& normal) {
  AnalyticScene s;
  s.planes.push_back({point, glm::normalize(normal)});
  return renderAnalyticKeyframe(s, frontCamera(w, h));
}

// Every valid pixel in exactly one quad, no empty pixel in any.
void expectExactTiling(const QuadMesh& mesh, const Keyframe& kf) {
  const int w = kf.zPrime.width(), h = kf.zPrime.height();
  ASSERT_EQ(mesh.width, w);
  ASSERT_EQ(mesh.height, h);
  ASSERT_EQ(mesh.stats.quads, static_cast<int>(mesh.quads.size()));
  Image<int> count(w, h, 0);
  for (const Quad& q : mesh.quads) {
    const PixelRect& r = q.rect;
    ASSERT_TRUE(r.x0 >= 0 && r.y0 >= 0 && r.x1 <= w && r.y1 <= h && r.x0 < r.x1 && r.y0 < r.y1)
        << r.x0 << "," << r.y0 << "," << r.x1 << "," << r.y1;
    for (int y = r.y0; y < r.y1; ++y)
      for (int x = r.x0; x < r.x1; ++x) ++count(x, y);
  }
  long long bad = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (count(x, y) != (validPixel(kf, x, y) ? 1 : 0) && ++bad < 5)
        ADD_FAILURE() << "pixel " << x << "," << y << " in " << count(x, y) << " quads";
  EXPECT_EQ(bad, 0);
  EXPECT_EQ(mesh.stats.emptyPixels, static_cast<long long>(w) * h - validCount(kf));
}

// The uniform mesh's structure: each quad lies in one tile; a full tile is one
// quad; in a mixed tile, each row of a quad is a maximal run within the tile,
// and no quad continues straight into another below it.
void expectTileStructure(const QuadMesh& mesh, const Keyframe& kf, int s) {
  const int w = kf.zPrime.width(), h = kf.zPrime.height();
  std::set<std::array<int, 3>> tops;  // (x0, x1, y0) of every quad
  for (const Quad& q : mesh.quads) tops.insert({q.rect.x0, q.rect.x1, q.rect.y0});
  for (const Quad& q : mesh.quads) {
    const PixelRect& r = q.rect;
    const int tx0 = r.x0 / s * s, ty0 = r.y0 / s * s;
    const int tx1 = std::min(tx0 + s, w), ty1 = std::min(ty0 + s, h);
    ASSERT_LE(r.x1, tx1);
    ASSERT_LE(r.y1, ty1);
    long long tileValid = 0;
    for (int y = ty0; y < ty1; ++y)
      for (int x = tx0; x < tx1; ++x) tileValid += validPixel(kf, x, y);
    if (tileValid == static_cast<long long>(tx1 - tx0) * (ty1 - ty0)) {
      EXPECT_TRUE(r.x0 == tx0 && r.y0 == ty0 && r.x1 == tx1 && r.y1 == ty1);
      continue;
    }
    for (int y = r.y0; y < r.y1; ++y) {
      if (r.x0 > tx0) {
        EXPECT_FALSE(validPixel(kf, r.x0 - 1, y)) << r.x0 << "," << y;
      }
      if (r.x1 < tx1) {
        EXPECT_FALSE(validPixel(kf, r.x1, y)) << r.x1 << "," << y;
      }
    }
    if (r.y1 < ty1) {
      EXPECT_EQ(tops.count({r.x0, r.x1, r.y1}), 0u)
          << "quad at " << r.x0 << "," << r.y0 << " not merged with the one below";
    }
  }
}

// Corners finite, in front of the eye, on the rays through the rectangle's
// corners (reprojection within 0.5 px), with the expected pixel coordinates.
void expectCornersOnRays(const QuadMesh& mesh, const Camera& cam) {
  for (const Quad& q : mesh.quads) {
    const PixelRect& r = q.rect;
    const double us[4] = {double(r.x0), double(r.x1), double(r.x1), double(r.x0)};
    const double vs[4] = {double(r.y0), double(r.y0), double(r.y1), double(r.y1)};
    for (int i = 0; i < 4; ++i) {
      ASSERT_TRUE(std::isfinite(q.world[i].x) && std::isfinite(q.world[i].y) &&
                  std::isfinite(q.world[i].z));
      ASSERT_TRUE(std::isfinite(q.eyeZ[i]));
      ASSERT_GT(q.eyeZ[i], 0.0);
      EXPECT_EQ(q.pixel[i].x, us[i]);
      EXPECT_EQ(q.pixel[i].y, vs[i]);
      const ProjectedPoint p = cam.project(q.world[i]);
      EXPECT_NEAR(p.u, us[i], 0.5);
      EXPECT_NEAR(p.v, vs[i], 0.5);
      EXPECT_NEAR(p.zEye, q.eyeZ[i], 1e-9 * q.eyeZ[i]);
    }
  }
}

void expectMaxDelta(const QuadMesh& mesh, const Image<float>& delta) {
  for (const Quad& q : mesh.quads) {
    float m = 0;
    for (int y = q.rect.y0; y < q.rect.y1; ++y)
      for (int x = q.rect.x0; x < q.rect.x1; ++x) m = std::max(m, delta(x, y));
    ASSERT_EQ(q.maxDelta, m);
  }
}

QuadMesh uniformChecked(const Keyframe& kf, int s, LodBuilder* builder = nullptr) {
  Result<QuadMesh> mesh = buildUniformTiles(kf, s, builder);
  EXPECT_TRUE(mesh.ok()) << (mesh.ok() ? "" : mesh.error().message);
  if (!mesh.ok()) return {};
  expectExactTiling(*mesh, kf);
  EXPECT_EQ(static_cast<long long>(mesh->quads.size()), uniformTileQuadCount(kf, s));
  return std::move(mesh).value();
}

TEST(UniformTiles, CoverEveryCoveredPixelOnceAndNoEmptyOne) {
  for (auto [w, h] : {std::pair{203, 151}, std::pair{256, 256}}) {
    const Keyframe kf = objectsKeyframe(w, h);
    const long long valid = validCount(kf);
    ASSERT_GT(valid, w * h / 20);
    ASSERT_LT(valid, static_cast<long long>(w) * h);
    LodBuilder builder;
    for (int s : {1, 3, 8, 64}) {
      SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h) + " tile " + std::to_string(s));
      const QuadMesh mesh = uniformChecked(kf, s, &builder);
      expectTileStructure(mesh, kf, s);
      expectCornersOnRays(mesh, kf.camera);
      expectMaxDelta(mesh, builder.delta());
      EXPECT_EQ(mesh.stats.subdivideMs, 0.0);
      EXPECT_EQ(mesh.stats.criterion, DeltaCriterion::FivePoint);
    }
  }
}

TEST(UniformTiles, TileSizeOneIsThePerPixelMesh) {
  const Keyframe kf = objectsKeyframe(203, 151);
  const QuadMesh tiles = uniformChecked(kf, 1);
  Result<QuadMesh> pixels = buildPerPixel(kf);
  ASSERT_TRUE(pixels.ok()) << pixels.error().message;
  expectExactTiling(*pixels, kf);
  const long long valid = validCount(kf);
  EXPECT_EQ(static_cast<long long>(tiles.quads.size()), valid);
  EXPECT_EQ(static_cast<long long>(pixels->quads.size()), valid);
  EXPECT_EQ(pixels->stats.onePixelLeaves, pixels->stats.quads);
  // Same 1×1 rectangles (in row-major order for the per-pixel mesh) and
  // the same corners, since both go through the same fit.
  ASSERT_EQ(tiles.quads.size(), pixels->quads.size());
  for (std::size_t k = 0; k < tiles.quads.size(); ++k) {
    const Quad &a = tiles.quads[k], &b = pixels->quads[k];
    ASSERT_TRUE(a.rect.x0 == b.rect.x0 && a.rect.y0 == b.rect.y0);
    if (k > 0) {
      const PixelRect& p = pixels->quads[k - 1].rect;
      EXPECT_TRUE(p.y0 < b.rect.y0 || (p.y0 == b.rect.y0 && p.x0 < b.rect.x0));
    }
    for (int i = 0; i < 4; ++i) {
      EXPECT_EQ(a.world[i], b.world[i]);
      EXPECT_EQ(a.eyeZ[i], b.eyeZ[i]);
    }
  }
}

TEST(PerPixel, CornersAreThePixelDepthAtItsEdges) {
  const Keyframe kf = objectsKeyframe(160, 120);
  LodBuilder builder;
  LodOptions o;
  o.criterion = DeltaCriterion::PerAxisMax;
  Result<QuadMesh> mesh = buildPerPixel(kf, &builder, o);
  ASSERT_TRUE(mesh.ok()) << mesh.error().message;
  expectExactTiling(*mesh, kf);
  expectCornersOnRays(*mesh, kf.camera);
  expectMaxDelta(*mesh, builder.delta());
  EXPECT_EQ(mesh->stats.criterion, DeltaCriterion::PerAxisMax);
  const double n = kf.camera.nearPlane, f = kf.camera.farPlane;
  for (const Quad& q : mesh->quads) {
    const double z = eyeZFromZPrime(kf.zPrime(q.rect.x0, q.rect.y0), n, f);
    for (int i = 0; i < 4; ++i) EXPECT_EQ(q.eyeZ[i], z);
  }
  EXPECT_EQ(mesh->stats.clampedCorners, 0);
}

TEST(UniformTiles, FullyCoveredImageHasOneQuadPerTile) {
  for (auto [w, h] : {std::pair{203, 151}, std::pair{128, 96}}) {
    const Keyframe kf = renderAnalyticKeyframe(makeRoomScene(), makeRoomCamera(w, h));
    ASSERT_EQ(validCount(kf), static_cast<long long>(w) * h);
    for (int s : {1, 3, 8, 64, 150, 500}) {
      SCOPED_TRACE("tile " + std::to_string(s));
      const QuadMesh mesh = uniformChecked(kf, s);
      EXPECT_EQ(static_cast<long long>(mesh.quads.size()),
                static_cast<long long>((w + s - 1) / s) * ((h + s - 1) / s));
      EXPECT_EQ(mesh.stats.emptyPixels, 0);
      expectCornersOnRays(mesh, kf.camera);
    }
  }
}

TEST(UniformTiles, PlanarTilesHaveCornersOnThePlane) {
  const glm::dvec3 p0(0, 0, -6), nrm = glm::normalize(glm::dvec3(0.4, 0.6, 1.0));
  const Keyframe kf = planeKeyframe(203, 151, p0, nrm);
  ASSERT_EQ(validCount(kf), 203LL * 151);
  for (int s : {1, 3, 8, 64}) {
    SCOPED_TRACE("tile " + std::to_string(s));
    const QuadMesh mesh = uniformChecked(kf, s);
    expectCornersOnRays(mesh, kf.camera);
    EXPECT_EQ(mesh.stats.clampedCorners, 0);
    // A 1×1 quad is flat in z' (fronto-parallel through the pixel centre), so
    // only larger tiles recover the plane; from 24-bit depth within 1e-4.
    for (const Quad& q : mesh.quads) {
      if (q.rect.width() > 1 && q.rect.height() > 1) {
        for (const glm::dvec3& p : q.world) EXPECT_NEAR(glm::dot(p - p0, nrm), 0.0, 1e-4);
      }
    }
  }
}

TEST(UniformTiles, TileSizeForQuadCountMatchesBruteForce) {
  for (auto [w, h] : {std::pair{97, 61}, std::pair{64, 64}}) {
    const Keyframe kf = objectsKeyframe(w, h);
    const int maxSize = std::max(w, h);
    std::vector<long long> counts(maxSize + 1);
    for (int s = 1; s <= maxSize; ++s) {
      Result<QuadMesh> mesh = buildUniformTiles(kf, s);
      ASSERT_TRUE(mesh.ok());
      counts[s] = static_cast<long long>(mesh->quads.size());
      ASSERT_EQ(uniformTileQuadCount(kf, s), counts[s]);
    }
    std::vector<long long> targets = {-5, 0, 1, 2, 7, 40, 100, 1000000, counts[1], counts[1] + 3};
    for (int s : {2, 3, 5, 8, 13, 30})
      targets.insert(targets.end(),
                     {counts[s], counts[s] - 1, counts[s] + 1, (counts[s] + counts[s + 1]) / 2});
    for (long long t : targets) {
      int best = 1;
      for (int s = 2; s <= maxSize; ++s)
        if (std::llabs(counts[s] - t) < std::llabs(counts[best] - t)) best = s;
      EXPECT_EQ(tileSizeForQuadCount(kf, t), best) << "target " << t;
    }
  }
}

TEST(BuildFromRects, ReproducesTheSubdivisionsOwnQuads) {
  const Keyframe kf = renderAnalyticKeyframe(makeRoomScene(), makeRoomCamera(200, 150));
  for (DeltaCriterion c : {DeltaCriterion::FivePoint, DeltaCriterion::PerAxisMax}) {
    LodOptions o;
    o.criterion = c;
    o.tau = 32768.0;
    LodBuilder lod;
    QuadMesh ref;
    ASSERT_TRUE(lod.build(kf, o, &ref).ok());
    const std::vector<PixelRect> leaves = lod.leaves();
    LodBuilder builder;
    QuadMesh mesh;
    const Status st = builder.buildFromRects(kf, leaves, o, &mesh);
    ASSERT_TRUE(st.ok()) << st.error().message;
    ASSERT_EQ(mesh.quads.size(), ref.quads.size());
    for (std::size_t k = 0; k < ref.quads.size(); ++k) {
      const Quad &a = mesh.quads[k], &b = ref.quads[k];
      EXPECT_EQ(a.maxDelta, b.maxDelta);
      for (int i = 0; i < 4; ++i) {
        EXPECT_EQ(a.world[i], b.world[i]);
        EXPECT_EQ(a.eyeZ[i], b.eyeZ[i]);
      }
    }
    EXPECT_EQ(mesh.stats.quads, ref.stats.quads);
    EXPECT_EQ(mesh.stats.onePixelLeaves, ref.stats.onePixelLeaves);
    EXPECT_EQ(mesh.stats.emptyPixels, ref.stats.emptyPixels);
    EXPECT_EQ(mesh.stats.clampedCorners, ref.stats.clampedCorners);
    EXPECT_EQ(mesh.stats.criterion, c);
    EXPECT_EQ(mesh.stats.tauZPrime, o.tau);
    EXPECT_EQ(builder.leaves().size(), leaves.size());
  }
}

TEST(BuildFromRects, RejectsRectsOutsideTheImageOrOverEmptyPixels) {
  const Keyframe kf = objectsKeyframe(97, 61);
  int ex = -1, ey = -1;
  for (int y = 0; y < 61 && ex < 0; ++y)
    for (int x = 0; x < 97 && ex < 0; ++x)
      if (!validPixel(kf, x, y)) ex = x, ey = y;
  ASSERT_GE(ex, 0);
  int cx = -1, cy = -1;
  for (int y = 0; y < 61 && cx < 0; ++y)
    for (int x = 0; x < 97 && cx < 0; ++x)
      if (validPixel(kf, x, y)) cx = x, cy = y;
  ASSERT_GE(cx, 0);
  const PixelRect good{cx, cy, cx + 1, cy + 1};
  const std::vector<std::vector<PixelRect>> bad = {
      {good, PixelRect{-1, 0, 1, 1}}, {PixelRect{90, 0, 98, 1}, good},
      {PixelRect{0, 60, 1, 62}},      {PixelRect{5, 5, 5, 6}},
      {PixelRect{5, 6, 6, 5}},        {good, PixelRect{ex, ey, ex + 1, ey + 1}},
      {PixelRect{0, 0, 97, 61}},
  };
  LodBuilder builder;
  for (const std::vector<PixelRect>& rects : bad) {
    QuadMesh mesh;
    mesh.quads.resize(3);
    const Status st = builder.buildFromRects(kf, rects, LodOptions{}, &mesh);
    ASSERT_FALSE(st.ok());
    EXPECT_NE(st.error().message.find("rectangle"), std::string::npos) << st.error().message;
    EXPECT_TRUE(mesh.quads.empty());
    EXPECT_EQ(mesh.stats.quads, 0);
  }
  // A poisoned (non-finite z') covered pixel is empty too.
  for (int y = 0; y < 61; ++y)
    for (int x = 0; x < 97; ++x)
      if (kf.covered(x, y) != 0 && !std::isfinite(kf.zPrime(x, y))) {
        QuadMesh mesh;
        const std::vector<PixelRect> one = {PixelRect{x, y, x + 1, y + 1}};
        EXPECT_FALSE(builder.buildFromRects(kf, one, LodOptions{}, &mesh).ok());
      }
  QuadMesh mesh;
  const std::vector<PixelRect> ok = {good};
  EXPECT_TRUE(builder.buildFromRects(kf, ok, LodOptions{}, &mesh).ok());
  EXPECT_EQ(mesh.quads.size(), 1u);
}

TEST(Baselines, RejectBadInput) {
  const Keyframe kf = objectsKeyframe(64, 48);
  EXPECT_FALSE(buildUniformTiles(kf, 0).ok());
  EXPECT_FALSE(buildUniformTiles(kf, -3).ok());
  Keyframe wrong = kf;
  wrong.colour.resize(10, 10);
  EXPECT_FALSE(buildUniformTiles(wrong, 8).ok());
  EXPECT_FALSE(buildPerPixel(wrong).ok());
  Keyframe mismatched = kf;
  mismatched.covered.resize(10, 10);
  EXPECT_FALSE(buildUniformTiles(mismatched, 8).ok());
  EXPECT_FALSE(buildPerPixel(mismatched).ok());
  LodOptions o;
  o.tau = -1.0;
  EXPECT_FALSE(buildUniformTiles(kf, 8, nullptr, o).ok());
  QuadMesh mesh;
  EXPECT_FALSE(LodBuilder().buildFromRects(wrong, {}, LodOptions{}, &mesh).ok());
}

}  // namespace
}  // namespace hw::keyframe
