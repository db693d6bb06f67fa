// Near objects drawn directly (Zheng et al. 1999 §3): a keyframe
// that leaves out the clusters near its eye, plus those clusters drawn by
// renderNear and composed by depth, is the full picture again; and the near
// pass draws far fewer triangles by cluster than by whole mesh.
#include <gtest/gtest.h>

#include "core/metrics.h"
#include "gl_fixture.h"
#include "keyframe/geometry_renderer.h"
#include "scenes/procedural.h"

namespace hw {
namespace {

class NearTest : public test::GlTest {};

TEST_F(NearTest, ExcludedKeyframePlusNearGeometryIsTheFullFrame) {
  const scenes::Scene scene = scenes::makeIndoorScene(20000);
  const scenes::CameraPath path = scenes::defaultIndoorPath();
  auto full = keyframe::GeometryRenderer::create(scene);
  ASSERT_TRUE(full.ok()) << full.error().message;
  keyframe::RenderOptions ro;
  ro.keyframeExcludeNear = 1.5;
  auto part = keyframe::GeometryRenderer::create(scene, ro);
  ASSERT_TRUE(part.ok()) << part.error().message;
  int framesWithNear = 0;
  for (int f : {0, 25, 30}) {
    Camera cam = path.cameraAt(f);
    cam.width = cam.height = 160;
    keyframe::Keyframe whole, without;
    keyframe::RenderStats sw, sp;
    ASSERT_TRUE((*full)->renderKeyframe(cam, whole, &sw).ok());
    ASSERT_TRUE((*part)->renderKeyframe(cam, without, &sp).ok());
    ASSERT_LE(sp.trianglesDrawn, sw.trianglesDrawn);
    Image<Rgba8> nearColour;
    Image<float> nearZ;
    Image<std::uint8_t> nearCovered;
    keyframe::RenderStats sn;
    ASSERT_TRUE((*part)->renderNear(cam, &cam.eye, 1, 1.5, nearColour, nearZ, nearCovered, &sn).ok());
    // Every triangle is drawn by exactly one of the two passes.
    EXPECT_EQ(sp.trianglesDrawn + sn.trianglesDrawn, sw.trianglesDrawn) << f;
    EXPECT_EQ(sp.clustersDrawn + sn.clustersDrawn, sw.clustersDrawn) << f;
    if (sn.trianglesDrawn == 0) continue;
    ++framesWithNear;
    EXPECT_LT(psnr(without.colour, whole.colour), 40.0) << "leaving near meshes out changed nothing";
    Image<Rgba8> composed = without.colour;
    for (std::size_t p = 0; p < composed.size(); ++p)
      if (nearCovered.data()[p] &&
          (!without.covered.data()[p] || nearZ.data()[p] < without.eyeZ.data()[p]))
        composed.data()[p] = nearColour.data()[p];
    EXPECT_GE(psnr(composed, whole.colour), 45.0) << f;
  }
  EXPECT_GT(framesWithNear, 0) << "no frame had a mesh within 1.5 m: weak test";
}

// The same near pass by cluster and by whole mesh: the clusters' triangles
// are a subset of the meshes', and a small one.
TEST_F(NearTest, NearPassByClusterDrawsASubsetOfTheMeshes) {
  const scenes::Scene scene = scenes::makeIndoorScene(60000);
  const scenes::CameraPath path = scenes::defaultIndoorPath();
  keyframe::RenderOptions byMesh;
  byMesh.clusterCulling = false;
  auto rMesh = keyframe::GeometryRenderer::create(scene, byMesh);
  auto rCluster = keyframe::GeometryRenderer::create(scene);
  ASSERT_TRUE(rMesh.ok() && rCluster.ok());
  std::size_t trisMesh = 0, trisCluster = 0;
  for (int f = 0; f < path.frames; f += 5) {
    Camera cam = path.cameraAt(f);
    cam.width = cam.height = 128;
    Image<Rgba8> cm, cc;
    Image<float> zm, zc;
    Image<std::uint8_t> vm, vc;
    keyframe::RenderStats sm, sc;
    ASSERT_TRUE((*rMesh)->renderNear(cam, &cam.eye, 1, 1.5, cm, zm, vm, &sm).ok());
    ASSERT_TRUE((*rCluster)->renderNear(cam, &cam.eye, 1, 1.5, cc, zc, vc, &sc).ok());
    EXPECT_LE(sc.trianglesDrawn, sm.trianglesDrawn) << f;
    // What the cluster pass covers, the mesh pass covers too, with the same depth.
    int extra = 0;
    for (std::size_t p = 0; p < vc.size(); ++p)
      extra += vc.data()[p] && (!vm.data()[p] || zc.data()[p] < zm.data()[p]);
    EXPECT_EQ(extra, 0) << f;
    trisMesh += sm.trianglesDrawn;
    trisCluster += sc.trianglesDrawn;
  }
  ASSERT_GT(trisCluster, 0u) << "nothing within 1.5 m of the path: weak test";
  EXPECT_LT(4 * trisCluster, trisMesh);
}

}  // namespace
}  // namespace hw
