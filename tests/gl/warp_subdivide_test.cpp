// Subdivision of large quads at upload (paper §2.1): at the
// keyframe's own camera every variant still reproduces the keyframe, and only
// the adaptive one leaves flat quads alone. Layer::largeQuad (the pixels large
// leaves drew, where the modes differ) lies only where those leaves project,
// and marking them leaves the pixels unchanged.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>

#include "core/metrics.h"
#include "gl_fixture.h"
#include "keyframe/geometry_renderer.h"
#include "keyframe/lod_builder.h"
#include "scenes/procedural.h"
#include "warp/warper.h"

namespace hw {
namespace {

class SubdivideTest : public test::GlTest {};

TEST_F(SubdivideTest, EveryVariantReproducesTheKeyframeAtItsOwnCamera) {
  const scenes::Scene scene = scenes::makeIndoorScene(20000);
  Camera cam = scenes::defaultIndoorPath().cameraAt(30);
  cam.width = cam.height = 192;
  auto r = keyframe::GeometryRenderer::create(scene);
  ASSERT_TRUE(r.ok()) << r.error().message;
  keyframe::Keyframe kf;
  ASSERT_TRUE((*r)->renderKeyframe(cam, kf).ok());
  keyframe::LodOptions lo;
  lo.tau = 2048;
  auto mesh = keyframe::buildQuadMesh(kf, lo);
  ASSERT_TRUE(mesh.ok());
  int drawn[3] = {0, 0, 0};
  double affinePsnr[3] = {0, 0, 0};
  const warp::Subdivision modes[3] = {warp::Subdivision::None, warp::Subdivision::Uniform,
                                      warp::Subdivision::Adaptive};
  for (int m = 0; m < 3; ++m) {
    for (warp::TexcoordMode tc : {warp::TexcoordMode::Projective, warp::TexcoordMode::Affine}) {
      warp::WarpOptions wo;
      wo.subdivision = modes[m];
      wo.subdivideCellPx = 8;
      wo.texcoords = tc;
      auto w = warp::Warper::create(wo);
      ASSERT_TRUE(w.ok()) << w.error().message;
      warp::WarpStats us;
      auto src = (*w)->upload(kf, *mesh, &us);
      ASSERT_TRUE(src.ok()) << src.error().message;
      warp::Layer layer;
      warp::WarpStats ws;
      ASSERT_TRUE((*w)->warp(**src, cam, layer, &ws).ok());
      EXPECT_EQ(ws.uncovered, 0) << warp::subdivisionName(modes[m]);
      const double p = psnr(layer.colour, kf.colour);
      // Projective texcoords are exact at the keyframe's camera with or without
      // cells; affine ones (the paper's era) are not, and cells reduce their error.
      if (tc == warp::TexcoordMode::Projective) {
        EXPECT_GE(p, 50.0) << warp::subdivisionName(modes[m]);
      } else {
        affinePsnr[m] = p;
      }
      drawn[m] = us.drawnQuads;
      if (modes[m] == warp::Subdivision::None) {
        EXPECT_EQ(us.subdividedQuads, 0);
      }
    }
  }
  EXPECT_EQ(drawn[0], mesh->stats.quads);
  EXPECT_GT(drawn[1], drawn[0]);      // uniform cuts every quad wider than a cell
  EXPECT_LE(drawn[2], drawn[1]);      // adaptive cuts a subset of those
  EXPECT_GE(drawn[2], drawn[0]);
  EXPECT_GT(affinePsnr[1], affinePsnr[0] + 1.0) << "uniform cells did not reduce affine distortion";
  EXPECT_GE(affinePsnr[2], affinePsnr[0]);
}

// Pixel centres of `cam` inside the projection of a leaf of `mesh` larger
// than one `cell` (nx·ny > 1), dilated by one pixel (rounding at the edges);
// a leaf with a corner behind the eye counts as covering everything.
Image<std::uint8_t> largeLeafFootprint(const keyframe::QuadMesh& mesh, int cell, const Camera& cam) {
  Image<std::uint8_t> in(cam.width, cam.height);
  in.fill(0);
  for (const keyframe::Quad& q : mesh.quads) {
    const int nx = (q.rect.width() + cell - 1) / cell, ny = (q.rect.height() + cell - 1) / cell;
    if (nx * ny <= 1) continue;
    ProjectedPoint p[4];
    bool behind = false;
    double u0 = 1e30, u1 = -1e30, v0 = 1e30, v1 = -1e30;
    for (int k = 0; k < 4; ++k) {
      p[k] = cam.project(q.world[static_cast<std::size_t>(k)]);
      behind |= !(p[k].zEye > 0);
      u0 = std::min(u0, p[k].u), u1 = std::max(u1, p[k].u);
      v0 = std::min(v0, p[k].v), v1 = std::max(v1, p[k].v);
    }
    if (behind) {
      in.fill(1);
      return in;
    }
    const int x0 = std::max(0, static_cast<int>(u0) - 1), x1 = std::min(cam.width - 1, static_cast<int>(u1) + 1);
    const int y0 = std::max(0, static_cast<int>(v0) - 1), y1 = std::min(cam.height - 1, static_cast<int>(v1) + 1);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        // Inside a convex quad: the centre is on one side of all four edges.
        int pos = 0, neg = 0;
        for (int k = 0; k < 4; ++k) {
          const ProjectedPoint& a = p[k];
          const ProjectedPoint& b = p[(k + 1) % 4];
          const double c = (b.u - a.u) * (y + 0.5 - a.v) - (b.v - a.v) * (x + 0.5 - a.u);
          pos += c >= 0, neg += c <= 0;
        }
        if (pos == 4 || neg == 4) in(x, y) = 1;
      }
  }
  Image<std::uint8_t> out(cam.width, cam.height);
  out.fill(0);
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int xx = x + dx, yy = y + dy;
          if (xx >= 0 && yy >= 0 && xx < cam.width && yy < cam.height && in(xx, yy)) out(x, y) = 1;
        }
  return out;
}

int countOn(const Image<std::uint8_t>& m) {
  int n = 0;
  for (std::size_t i = 0; i < m.size(); ++i) n += m.data()[i] != 0;
  return n;
}

template <class T>
bool sameBytes(const Image<T>& a, const Image<T>& b) {
  return a.width() == b.width() && a.height() == b.height() &&
         std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

// Two indoor keyframes along the default path and a camera between them,
// nearer the first (its leaves stretched by the motion).
struct Pair {
  keyframe::Keyframe kf[2];
  keyframe::QuadMesh mesh[2];
  Camera target;
};

Pair indoorPair(int size) {
  const scenes::Scene scene = scenes::makeIndoorScene(20000);
  const scenes::CameraPath path = scenes::defaultIndoorPath();
  Pair p;
  auto r = keyframe::GeometryRenderer::create(scene);
  EXPECT_TRUE(r.ok()) << r.error().message;
  keyframe::LodOptions lo;
  lo.tau = 2048;
  lo.planarity = keyframe::Planarity::RegionLocal;
  lo.mergeStrips = true;
  const int frames[2] = {30, 38};
  for (int k = 0; k < 2; ++k) {
    Camera c = path.cameraAt(frames[k]);
    c.width = c.height = size;
    EXPECT_TRUE((*r)->renderKeyframe(c, p.kf[k]).ok());
    auto m = keyframe::buildQuadMesh(p.kf[k], lo);
    EXPECT_TRUE(m.ok());
    p.mesh[k] = std::move(*m);
  }
  p.target = path.cameraAt(33);
  p.target.width = p.target.height = size;
  return p;
}

TEST_F(SubdivideTest, LargeQuadMaskLiesWhereLargeLeavesProjectAndLeavesPixelsUnchanged) {
  const Pair pair = indoorPair(160);
  const int cell = 16;
  const Image<std::uint8_t> fgFoot = largeLeafFootprint(pair.mesh[0], cell, pair.target);
  const Image<std::uint8_t> bgFoot = largeLeafFootprint(pair.mesh[1], cell, pair.target);
  for (warp::Subdivision mode :
       {warp::Subdivision::None, warp::Subdivision::Uniform, warp::Subdivision::Adaptive}) {
    for (warp::Primitives prim : {warp::Primitives::Independent, warp::Primitives::Indexed,
                                  warp::Primitives::Shared, warp::Primitives::Points}) {
      for (warp::TexcoordMode tc : {warp::TexcoordMode::Projective, warp::TexcoordMode::Affine}) {
        const std::string what = std::string(warp::subdivisionName(mode)) + "/" +
                                 warp::primitivesName(prim) + "/" + warp::texcoordModeName(tc);
        warp::Layer pairs[2], singles[2];
        for (int marked = 0; marked < 2; ++marked) {
          warp::WarpOptions wo;
          wo.subdivision = mode;
          wo.subdivideCellPx = cell;
          wo.primitives = prim;
          wo.texcoords = tc;
          wo.markLargeQuads = marked == 1;
          auto w = warp::Warper::create(wo);
          ASSERT_TRUE(w.ok()) << w.error().message;
          auto fg = (*w)->upload(pair.kf[0], pair.mesh[0]);
          auto bg = (*w)->upload(pair.kf[1], pair.mesh[1]);
          ASSERT_TRUE(fg.ok() && bg.ok());
          // The background is drawn even where nothing is left to fill.
          ASSERT_TRUE((*w)->warpPair(**fg, bg->get(), pair.target, pairs[marked], false).ok());
          ASSERT_TRUE((*w)->warp(**fg, pair.target, singles[marked]).ok());
        }
        // Identical pixels with and without the marks.
        EXPECT_TRUE(sameBytes(pairs[0].colour, pairs[1].colour)) << what;
        EXPECT_TRUE(sameBytes(pairs[0].coverage, pairs[1].coverage)) << what;
        EXPECT_TRUE(sameBytes(pairs[0].eyeZ, pairs[1].eyeZ)) << what;
        EXPECT_TRUE(sameBytes(singles[0].colour, singles[1].colour)) << what;
        EXPECT_TRUE(sameBytes(singles[0].coverage, singles[1].coverage)) << what;
        EXPECT_TRUE(sameBytes(singles[0].eyeZ, singles[1].eyeZ)) << what;
        EXPECT_EQ(pairs[0].largeQuad.size(), 0u) << what;
        // Marked pixels: covered, and inside the projection of a large leaf
        // of the layer that drew them.
        const warp::Layer& lp = pairs[1];
        const warp::Layer& ls = singles[1];
        ASSERT_EQ(lp.largeQuad.width(), pair.target.width);
        ASSERT_EQ(ls.largeQuad.width(), pair.target.width);
        int outside = 0, uncovered = 0, fromBg = 0;
        for (int y = 0; y < pair.target.height; ++y)
          for (int x = 0; x < pair.target.width; ++x) {
            if (ls.largeQuad(x, y)) {
              uncovered += ls.coverage(x, y) == 0;
              outside += fgFoot(x, y) == 0;
            }
            if (!lp.largeQuad(x, y)) continue;
            const int c = lp.coverage(x, y);
            uncovered += c == 0;
            fromBg += c == 2;
            outside += c == 1 ? fgFoot(x, y) == 0 : bgFoot(x, y) == 0;
            // The fused foreground equals the single-layer warp.
            if (c == 1) {
              EXPECT_EQ(ls.largeQuad(x, y), 1) << what << " at " << x << "," << y;
            }
          }
        EXPECT_EQ(outside, 0) << what;
        EXPECT_EQ(uncovered, 0) << what;
        const int marked = countOn(lp.largeQuad);
        EXPECT_GT(marked, pair.target.width * pair.target.height / 20) << what;
        EXPECT_GT(fromBg, 0) << what << ": no background pixel of a large leaf";
        EXPECT_GT(countOn(ls.largeQuad), 0) << what;
      }
    }
  }
}

TEST_F(SubdivideTest, NoLargeLeafGivesAnEmptyMask) {
  const Pair pair = indoorPair(128);
  // Cells larger than the keyframe: every leaf fits in one.
  warp::WarpOptions wo;
  wo.subdivision = warp::Subdivision::Uniform;
  wo.subdivideCellPx = 256;
  auto w = warp::Warper::create(wo);
  ASSERT_TRUE(w.ok()) << w.error().message;
  warp::WarpStats us;
  auto fg = (*w)->upload(pair.kf[0], pair.mesh[0], &us);
  auto bg = (*w)->upload(pair.kf[1], pair.mesh[1]);
  ASSERT_TRUE(fg.ok() && bg.ok());
  EXPECT_EQ(us.subdividedQuads, 0);
  warp::Layer lp, ls;
  ASSERT_TRUE((*w)->warpPair(**fg, bg->get(), pair.target, lp, false).ok());
  ASSERT_TRUE((*w)->warp(**fg, pair.target, ls).ok());
  ASSERT_EQ(lp.largeQuad.width(), pair.target.width);
  ASSERT_EQ(ls.largeQuad.width(), pair.target.width);
  EXPECT_EQ(countOn(lp.largeQuad), 0);
  EXPECT_EQ(countOn(ls.largeQuad), 0);
  EXPECT_GT(countOn(lp.coverage), 0);
  // The same keyframe with 16-pixel cells has large leaves.
  wo.subdivideCellPx = 16;
  auto w16 = warp::Warper::create(wo);
  ASSERT_TRUE(w16.ok());
  auto fg16 = (*w16)->upload(pair.kf[0], pair.mesh[0], &us);
  ASSERT_TRUE(fg16.ok());
  EXPECT_GT(us.subdividedQuads, 0);
  ASSERT_TRUE((*w16)->warp(**fg16, pair.target, ls).ok());
  EXPECT_GT(countOn(ls.largeQuad), 0);
}

}  // namespace
}  // namespace hw
