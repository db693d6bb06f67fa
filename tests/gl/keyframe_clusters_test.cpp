// Culling by cluster (scenes/clusters.h) leaves the geometry renderer's
// image bit for bit as it is without any culling, in every depth mode, while
// drawing fewer triangles than culling by whole mesh; visibleTriangles counts
// what a render draws.
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "gl_fixture.h"
#include "keyframe/geometry_renderer.h"
#include "scenes/procedural.h"

namespace hw {
namespace {

class ClusterCullTest : public test::GlTest {};

template <typename T>
bool sameBits(const Image<T>& a, const Image<T>& b) {
  return a.width() == b.width() && a.height() == b.height() &&
         std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

struct Case {
  const char* name;
  scenes::Scene scene;
  scenes::CameraPath path;
};

TEST_F(ClusterCullTest, CulledRenderIsBitIdenticalToTheUnculledOne) {
  const Case cases[] = {{"indoor", scenes::makeIndoorScene(60000), scenes::defaultIndoorPath()},
                        {"outdoor", scenes::makeOutdoorScene(60000), scenes::defaultOutdoorPath()}};
  for (const Case& c : cases) {
    for (DepthMode mode : {DepthMode::Fixed24, DepthMode::Float32Reversed}) {
      keyframe::RenderOptions none, byMesh, byCluster;
      none.frustumCulling = false;
      byMesh.clusterCulling = false;
      none.depthMode = byMesh.depthMode = byCluster.depthMode = mode;
      auto rNone = keyframe::GeometryRenderer::create(c.scene, none);
      auto rMesh = keyframe::GeometryRenderer::create(c.scene, byMesh);
      auto rCluster = keyframe::GeometryRenderer::create(c.scene, byCluster);
      ASSERT_TRUE(rNone.ok() && rMesh.ok() && rCluster.ok());
      EXPECT_GT((*rCluster)->sceneClusters(), c.scene.meshes.size()) << c.name;
      std::size_t trisMesh = 0, trisCluster = 0;
      for (int f = 0; f < c.path.frames; f += c.path.frames / 12) {
        Camera cam = c.path.cameraAt(f);
        cam.width = cam.height = 192;
        keyframe::Keyframe kn, km, kc;
        keyframe::RenderStats sn, sm, sc;
        ASSERT_TRUE((*rNone)->renderKeyframe(cam, kn, &sn).ok());
        ASSERT_TRUE((*rMesh)->renderKeyframe(cam, km, &sm).ok());
        ASSERT_TRUE((*rCluster)->renderKeyframe(cam, kc, &sc).ok());
        const std::string at = std::string(c.name) + " frame " + std::to_string(f) + " mode " +
                               std::to_string(static_cast<int>(mode));
        EXPECT_TRUE(sameBits(kc.colour, kn.colour)) << at;
        EXPECT_TRUE(sameBits(kc.zPrime, kn.zPrime)) << at;
        EXPECT_TRUE(sameBits(km.colour, kn.colour)) << at;
        EXPECT_EQ(sn.trianglesDrawn, c.scene.triangleCount()) << at;
        EXPECT_LE(sc.trianglesDrawn, sm.trianglesDrawn) << at;
        // Counted without drawing, by the same culling.
        EXPECT_EQ((*rNone)->visibleTriangles(cam), sn.trianglesDrawn) << at;
        EXPECT_EQ((*rMesh)->visibleTriangles(cam), sm.trianglesDrawn) << at;
        EXPECT_EQ((*rCluster)->visibleTriangles(cam), sc.trianglesDrawn) << at;
        trisMesh += sm.trianglesDrawn;
        trisCluster += sc.trianglesDrawn;
      }
      // Culling by cluster must leave out something culling by mesh keeps.
      EXPECT_LT(trisCluster, trisMesh) << c.name;
    }
  }
}

TEST_F(ClusterCullTest, ColourRectMatchesTheFullImage) {
  const scenes::Scene scene = scenes::makeIndoorScene(60000);
  auto r = keyframe::GeometryRenderer::create(scene);
  ASSERT_TRUE(r.ok());
  Camera cam = scenes::defaultIndoorPath().cameraAt(40);
  cam.width = cam.height = 160;
  Image<Rgba8> full, part;
  ASSERT_TRUE((*r)->renderColour(cam, full).ok());
  const keyframe::PixelRect rect{13, 101, 77, 150};
  ASSERT_TRUE((*r)->renderColourRect(cam, rect, part).ok());
  ASSERT_EQ(part.width(), rect.width());
  int bad = 0;
  for (int y = rect.y0; y < rect.y1; ++y)
    for (int x = rect.x0; x < rect.x1; ++x) {
      const Rgba8 a = full(x, y), b = part(x - rect.x0, y - rect.y0);
      bad += a.r != b.r || a.g != b.g || a.b != b.b;
    }
  EXPECT_EQ(bad, 0);
}

TEST_F(ClusterCullTest, SeveralColourRectsInOnePassMatchTheFullImage) {
  const scenes::Scene scene = scenes::makeIndoorScene(60000);
  auto r = keyframe::GeometryRenderer::create(scene);
  ASSERT_TRUE(r.ok());
  Camera cam = scenes::defaultIndoorPath().cameraAt(40);
  cam.width = cam.height = 160;
  Image<Rgba8> full;
  ASSERT_TRUE((*r)->renderColour(cam, full).ok());
  // A strip along the top, a column on the right, a tile in the middle, and
  // one overlapping the strip.
  const keyframe::PixelRect rects[4] = {
      {0, 0, 160, 16}, {144, 16, 160, 160}, {64, 80, 80, 96}, {30, 8, 50, 40}};
  Image<Rgba8> parts[4];
  keyframe::RenderStats st;
  ASSERT_TRUE((*r)->renderColourRects(cam, rects, 4, parts, &st).ok());
  EXPECT_GT(st.trianglesDrawn, 0u);
  EXPECT_LT(st.trianglesDrawn, 4 * scene.triangleCount());
  int bad = 0, differentFromSky = 0;
  for (int k = 0; k < 4; ++k) {
    const keyframe::PixelRect& rect = rects[k];
    ASSERT_EQ(parts[k].width(), rect.width());
    ASSERT_EQ(parts[k].height(), rect.height());
    for (int y = rect.y0; y < rect.y1; ++y)
      for (int x = rect.x0; x < rect.x1; ++x) {
        const Rgba8 a = full(x, y), b = parts[k](x - rect.x0, y - rect.y0);
        bad += a.r != b.r || a.g != b.g || a.b != b.b;
        differentFromSky += b.r != full(0, 0).r || b.g != full(0, 0).g || b.b != full(0, 0).b;
      }
  }
  EXPECT_EQ(bad, 0);
  EXPECT_GT(differentFromSky, 100);  // not a blank image
  // An invalid rectangle among them: an error, nothing drawn.
  const keyframe::PixelRect badRects[2] = {{0, 0, 8, 8}, {150, 150, 170, 160}};
  EXPECT_FALSE((*r)->renderColourRects(cam, badRects, 2, parts).ok());
}

}  // namespace
}  // namespace hw
