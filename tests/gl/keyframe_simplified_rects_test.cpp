// RenderOptions::simplifiedRects: hole rectangles drawn from the simplified
// copy of the scene show the same surfaces as the scene's own triangles
// (pixels differ only by the rasteriser's rounding along the new edges) and
// cost fewer triangles; the full-frame renders do not use the copy.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "core/memory_budget.h"
#include "gl_fixture.h"
#include "keyframe/geometry_renderer.h"
#include "scenes/procedural.h"

namespace hw {
namespace {

class SimplifiedRectsTest : public test::GlTest {};

TEST_F(SimplifiedRectsTest, SameSurfacesFewerTriangles) {
  const scenes::Scene scene = scenes::makeIndoorScene(400000);
  keyframe::RenderOptions own, simplified;
  simplified.simplifiedRects = true;
  auto a = keyframe::GeometryRenderer::create(scene, own);
  auto b = keyframe::GeometryRenderer::create(scene, simplified);
  ASSERT_TRUE(a.ok());
  ASSERT_TRUE(b.ok());
  const keyframe::PixelRect rects[3] = {{0, 0, 256, 256}, {40, 100, 120, 180}, {200, 10, 250, 60}};
  long long pixels = 0, differ = 0, farOff = 0, notSky = 0;
  std::size_t trianglesOwn = 0, trianglesSimplified = 0;
  for (int f : {10, 40, 80}) {
    Camera cam = scenes::defaultIndoorPath().cameraAt(f);
    cam.width = cam.height = 256;
    Image<Rgba8> pa[3], pb[3];
    keyframe::RenderStats sa, sb;
    ASSERT_TRUE((*a)->renderColourRects(cam, rects, 3, pa, &sa).ok());
    ASSERT_TRUE((*b)->renderColourRects(cam, rects, 3, pb, &sb).ok());
    trianglesOwn += sa.trianglesDrawn;
    trianglesSimplified += sb.trianglesDrawn;
    for (int k = 0; k < 3; ++k) {
      ASSERT_EQ(pa[k].size(), pb[k].size());
      for (std::size_t p = 0; p < pa[k].size(); ++p) {
        const Rgba8 x = pa[k].data()[p], y = pb[k].data()[p];
        const int d = std::max({std::abs(x.r - y.r), std::abs(x.g - y.g), std::abs(x.b - y.b)});
        ++pixels;
        differ += d > 0;
        farOff += d > 48;
      }
    }
    // The full image is the scene's own: identical between the two renderers.
    Image<Rgba8> fa, fb;
    ASSERT_TRUE((*a)->renderColour(cam, fa).ok());
    ASSERT_TRUE((*b)->renderColour(cam, fb).ok());
    EXPECT_EQ(std::memcmp(fa.data(), fb.data(), fa.size() * sizeof(Rgba8)), 0) << "frame " << f;
    for (std::size_t p = 0; p < fa.size(); ++p)
      notSky += fa.data()[p].r != fa.data()[0].r || fa.data()[p].b != fa.data()[0].b;
  }
  std::printf("triangles %zu -> %zu; pixels differing %lld, by more than 48: %lld, of %lld\n",
              trianglesOwn, trianglesSimplified, differ, farOff, pixels);
  EXPECT_GT(notSky, 10000);  // the views show the rooms
  EXPECT_LT(trianglesSimplified * 3, trianglesOwn) << trianglesOwn << " vs " << trianglesSimplified;
  // Texture filtering and edge rounding move a few pixels a little; a
  // missing or misplaced surface would move many a lot.
  EXPECT_LT(differ, pixels / 100) << differ << " of " << pixels;
  EXPECT_LT(farOff, pixels / 10000) << farOff << " of " << pixels;
}

TEST_F(SimplifiedRectsTest, TheCopyIsChargedToTheMemoryBudget) {
  const scenes::Scene scene = scenes::makeIndoorScene(200000);
  keyframe::RenderOptions simplified;
  simplified.simplifiedRects = true;
  const std::uint64_t before = memoryCharged();
  setMemoryBudget(before + (4u << 20));  // the scene's own upload is not charged here
  auto r = keyframe::GeometryRenderer::create(scene, simplified);
  setMemoryBudget(0);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("--simplify-holes"), std::string::npos) << r.error().message;
  EXPECT_EQ(memoryCharged(), before);
  // With room it is made, and what it charged is given back.
  auto ok = keyframe::GeometryRenderer::create(scene, simplified);
  ASSERT_TRUE(ok.ok()) << ok.error().message;
  EXPECT_EQ(memoryCharged(), before);
}

TEST_F(SimplifiedRectsTest, AnIndexOutOfRangeIsAnErrorNotACrash) {
  scenes::Scene scene = scenes::makeIndoorScene(20000);
  ASSERT_FALSE(scene.meshes.empty());
  scenes::Mesh& m = scene.meshes.back();
  m.indices[m.indices.size() / 2] = static_cast<std::uint32_t>(m.vertices.size()) + 7;
  keyframe::RenderOptions simplified;
  simplified.simplifiedRects = true;
  auto r = keyframe::GeometryRenderer::create(scene, simplified);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find(">= vertex count"), std::string::npos) << r.error().message;
}

}  // namespace
}  // namespace hw
