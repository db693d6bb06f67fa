// hybridwalk embedded headless: a small scene built from our own meshes,
// 30 frames along a circle drawn the hybrid way through the library, each
// checked against the library's geometry frame at the same camera.
// Exit 1 when the median in-between PSNR falls under kMinPsnrDb.
#include <hybridwalk/hybridwalk.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

using namespace hybridwalk;

constexpr double kMinPsnrDb = 25.0;

// An axis-aligned box, 4 vertices per face, counter-clockwise seen from
// outside (inward = seen from inside: the room's walls).
MeshDesc box(Vec3 lo, Vec3 hi, int material, bool inward = false) {
  MeshDesc m;
  m.material = material;
  const double l[3] = {lo.x, lo.y, lo.z}, h[3] = {hi.x, hi.y, hi.z};
  for (int axis = 0; axis < 3; ++axis)
    for (int sign : {-1, 1}) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;  // u x v = axis
      const auto base = static_cast<std::uint32_t>(m.positions.size() / 3);
      const int cu[4] = {0, 1, 1, 0}, cv[4] = {0, 0, 1, 1};
      for (int k = 0; k < 4; ++k) {
        double p[3];
        p[axis] = sign > 0 ? h[axis] : l[axis];
        p[u] = cu[k] ? h[u] : l[u];
        p[v] = cv[k] ? h[v] : l[v];
        float n[3] = {0, 0, 0};
        n[axis] = static_cast<float>(inward ? -sign : sign);
        for (int c = 0; c < 3; ++c) m.positions.push_back(static_cast<float>(p[c]));
        m.normals.insert(m.normals.end(), n, n + 3);
        m.uvs.push_back(static_cast<float>(cu[k] ? h[u] - l[u] : 0.0));
        m.uvs.push_back(static_cast<float>(cv[k] ? h[v] - l[v] : 0.0));
      }
      const bool ccw = (sign > 0) != inward;
      const std::uint32_t a[6] = {0, 1, 2, 0, 2, 3}, b[6] = {0, 2, 1, 0, 3, 2};
      for (std::uint32_t i : ccw ? a : b) m.indices.push_back(base + i);
    }
  return m;
}

SceneDesc smallRoom() {
  SceneDesc d;
  d.name = "small room";
  TextureDesc checker{"checker", 64, 64, {}};
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      const std::uint8_t c = ((x / 8 + y / 8) % 2) ? 230 : 70;
      checker.rgba.insert(checker.rgba.end(), {c, c, c, 255});
    }
  d.textures.push_back(checker);
  MaterialDesc walls{"walls", {0.9f, 0.85f, 0.7f, 1}, 0};
  MaterialDesc red{"red", {0.8f, 0.2f, 0.2f, 1}}, blue{"blue", {0.2f, 0.3f, 0.8f, 1}};
  d.materials = {walls, red, blue};
  d.meshes.push_back(box({-6, 0, -6}, {6, 3, 6}, 0, /*inward=*/true));
  d.meshes.push_back(box({-1, 0, -1}, {1, 1.5, 1}, 1));
  d.meshes.push_back(box({2.5, 0, -3}, {3.5, 2.2, -2}, 2));
  d.meshes.push_back(box({-3.5, 0, 2}, {-2, 0.8, 3.5}, 2));
  return d;
}

int main() {
  auto scene = Scene::build(smallRoom());
  if (!scene) return std::fprintf(stderr, "error: %s\n", scene.error().message.c_str()), 1;
  // Half a circle around the room's centre in 30 frames, a keyframe every 5.
  RendererDesc desc;
  desc.path.keyframeEvery = 5;
  for (int i = 0; i < 30; ++i) {
    const double a = 3.14159265358979 * i / 29.0;
    auto cam = Camera::lookAt({4 * std::cos(a), 1.6, 4 * std::sin(a)}, {0, 0.8, 0}, {0, 1, 0}, 1.0,
                              320, 240, 0.1, 100.0);
    if (!cam) return std::fprintf(stderr, "error: %s\n", cam.error().message.c_str()), 1;
    desc.path.cameras.push_back(*cam);
  }
  auto renderer = Renderer::create(*scene, desc);
  if (!renderer) return std::fprintf(stderr, "error: %s\n", renderer.error().message.c_str()), 1;
  std::printf("%s: %zu triangles, %s\n", scene->name().c_str(), scene->triangleCount(),
              renderer->glRenderer().c_str());
  Frame frame, reference;
  std::vector<double> psnrs;
  while (renderer->frameIndex() < renderer->frameCount()) {
    const Camera& cam = desc.path.cameras[static_cast<std::size_t>(renderer->frameIndex())];
    if (auto st = renderer->renderNext(frame); !st)
      return std::fprintf(stderr, "error: %s\n", st.error().message.c_str()), 1;
    if (auto st = renderer->renderGeometry(cam, reference); !st)
      return std::fprintf(stderr, "error: %s\n", st.error().message.c_str()), 1;
    const FrameStats& s = frame.stats;
    const double p = psnr(frame, reference);
    const bool warped = s.kind == FrameKind::Warped;
    if (warped) psnrs.push_back(p);
    std::printf("frame %2d  %-8s  quads %5d  holes %.4f  %6.2f ms  PSNR %6.2f dB\n", s.index,
                warped ? "warped" : "keyframe", s.quads, s.holeFraction, s.totalMs, p);
  }
  std::sort(psnrs.begin(), psnrs.end());
  const double median = psnrs.empty() ? 0 : psnrs[psnrs.size() / 2];
  std::printf("in-between frames: %zu, PSNR median %.2f dB, min %.2f dB (threshold %.1f dB)\n",
              psnrs.size(), median, psnrs.empty() ? 0 : psnrs.front(), kMinPsnrDb);
  return median >= kMinPsnrDb ? 0 : 1;
}
