// Geometry frames culled by cluster against by whole mesh, in one process:
// each camera of a path drawn by both renderers in turn (same image, bit for
// bit; scenes/clusters.h), so that the ratio of their medians holds on a
// shared machine. Usage: cluster_cull_bench SCENE [PATH.json]
#include <algorithm>
#include <cstdio>
#include <vector>

#include "core/gl/context.h"
#include "keyframe/geometry_renderer.h"
#include "scenes/camera_path.h"
#include "scenes/loader.h"

namespace {

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  using namespace hw;
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s SCENE [PATH.json]\n", argv[0]);
    return 2;
  }
  auto scene = scenes::loadScene(argv[1]);
  if (!scene) return std::fprintf(stderr, "%s\n", scene.error().message.c_str()), 1;
  auto path = argc > 2 ? scenes::loadCameraPath(argv[2]) : scenes::defaultPathFor(argv[1]);
  if (!path) return std::fprintf(stderr, "%s\n", path.error().message.c_str()), 1;
  auto ctx = gl::createHeadlessContext();
  if (!ctx) return std::fprintf(stderr, "%s\n", ctx.error().message.c_str()), 1;
  keyframe::RenderOptions byMesh, byCluster;
  byMesh.clusterCulling = false;
  auto rm = keyframe::GeometryRenderer::create(*scene, byMesh);
  auto rc = keyframe::GeometryRenderer::create(*scene, byCluster);
  if (!rm || !rc) return std::fprintf(stderr, "renderer\n"), 1;
  std::vector<double> msMesh, msCluster, triMesh, triCluster, ratio;
  Image<Rgba8> a, b;
  int differ = 0;
  for (int f = 0; f < path->frames; ++f) {
    const Camera cam = path->cameraAt(f);
    keyframe::RenderStats sm, sc;
    if (!(*rm)->renderColour(cam, a, &sm).ok() || !(*rc)->renderColour(cam, b, &sc).ok()) return 1;
    differ += !(a.size() == b.size() && std::equal(a.data(), a.data() + a.size(), b.data(),
                                                   [](const Rgba8& x, const Rgba8& y) {
                                                     return x.r == y.r && x.g == y.g && x.b == y.b && x.a == y.a;
                                                   }));
    if (f == 0) continue;  // first draws warm up textures
    msMesh.push_back(sm.drawMs);
    msCluster.push_back(sc.drawMs);
    ratio.push_back(sc.drawMs / sm.drawMs);
    triMesh.push_back(double(sm.trianglesDrawn));
    triCluster.push_back(double(sc.trianglesDrawn));
  }
  std::printf("%s: %zu triangles, %zu meshes, %zu clusters; %d frames, %d differ\n", argv[1],
              scene->triangleCount(), scene->meshes.size(), (*rc)->sceneClusters(), path->frames,
              differ);
  std::printf("  draw ms median: by mesh %.2f, by cluster %.2f; per-frame ratio median %.3f\n",
              median(msMesh), median(msCluster), median(ratio));
  std::printf("  triangles drawn median: by mesh %.0f, by cluster %.0f\n", median(triMesh),
              median(triCluster));
  return differ == 0 ? 0 : 1;
}
