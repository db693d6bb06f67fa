// warp/warp_vertices.h: the warper's vertex data as floats (what `publish`
// writes for the web player).
#include "warp/warp_vertices.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hw::warp {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A 16×8 keyframe whose left half sees a wall at depth 2 (one quad) and whose
// right half saw nothing (sky).
struct Fixture {
  keyframe::Keyframe kf;
  keyframe::QuadMesh mesh;
  Fixture() {
    kf.camera = Camera::lookAt({1, 2, 3}, {1, 2, -7}, {0, 1, 0}, 60 * kPi / 180, 16, 8, 0.1, 100);
    kf.colour.resize(16, 8);
    kf.eyeZ.resize(16, 8);
    kf.covered.resize(16, 8);
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 8; ++x) kf.covered(x, y) = 1;
    mesh.width = 16;
    mesh.height = 8;
    keyframe::Quad q;
    q.rect = {0, 0, 8, 8};
    const glm::dvec2 px[4] = {{0, 0}, {8, 0}, {8, 8}, {0, 8}};
    for (int k = 0; k < 4; ++k) {
      q.pixel[k] = px[k];
      q.eyeZ[k] = 2.0;
      q.world[k] = kf.camera.unproject(px[k].x, px[k].y, 2.0);
    }
    mesh.quads.push_back(q);
  }
};

TEST(WarpVertices, QuadCornersCarryProjectiveTexcoords) {
  Fixture f;
  const WarpVertices v = warpVertices(f.kf, f.mesh);
  ASSERT_EQ(v.quads, 1);
  ASSERT_EQ(v.data.size(), std::size_t(v.quads + v.skyRects) * 4 * kFloatsPerWarpVertex);
  for (int k = 0; k < 4; ++k) {
    const float* p = &v.data[std::size_t(k) * kFloatsPerWarpVertex];
    for (int c = 0; c < 3; ++c) EXPECT_EQ(p[c], static_cast<float>(f.mesh.quads[0].world[k][c]));
    EXPECT_EQ(p[5], 2.0f);
    // Divided per fragment, the texcoord is the corner's keyframe pixel / size.
    EXPECT_NEAR(p[3] / p[5], f.mesh.quads[0].pixel[k].x / 16.0, 1e-7);
    EXPECT_NEAR(p[4] / p[5], f.mesh.quads[0].pixel[k].y / 8.0, 1e-7);
  }
}

TEST(WarpVertices, SkyRectanglesCoverTheEmptyPixelsAsDirections) {
  Fixture f;
  const WarpVertices v = warpVertices(f.kf, f.mesh);
  ASSERT_GE(v.skyRects, 1);
  int area = 0;
  for (int r = 0; r < v.skyRects; ++r) {
    const float* c = &v.data[std::size_t(v.quads + r) * 4 * kFloatsPerWarpVertex];
    double xs[4], ys[4];
    for (int k = 0; k < 4; ++k) {
      const float* p = c + k * kFloatsPerWarpVertex;
      EXPECT_EQ(p[5], 1.0f);
      // A unit-depth direction that projects to the texcoord's pixel.
      const glm::dvec3 d(p[0], p[1], p[2]);
      EXPECT_NEAR(glm::dot(d, f.kf.camera.forward), 1.0, 1e-6);
      const ProjectedPoint pp = f.kf.camera.project(f.kf.camera.eye + d);
      EXPECT_NEAR(pp.u, p[3] * 16.0, 1e-4);
      EXPECT_NEAR(pp.v, p[4] * 8.0, 1e-4);
      xs[k] = p[3] * 16.0;
      ys[k] = p[4] * 8.0;
    }
    EXPECT_GE(xs[0], 8.0 - 1e-9);  // only the empty right half
    area += static_cast<int>(std::lround((xs[1] - xs[0]) * (ys[2] - ys[1])));
  }
  EXPECT_EQ(area, 8 * 8);
  EXPECT_EQ(warpVertices(f.kf, f.mesh, false).skyRects, 0);
}

}  // namespace
}  // namespace hw::warp
