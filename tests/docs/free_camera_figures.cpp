// The figure docs/api.md gives for cameras fed one at a time: the built-in
// indoor scene's default path through Renderer::render(camera) with the
// default options, each frame measured against renderGeometry at the same
// camera. Prints one line that scripts/docs_figures.py reads: "free camera:
// SCENE, N frames WxH, K keyframes built, one every F frames, warped W, PSNR
// median P dB".
#include <hybridwalk/hybridwalk.h>

#include <algorithm>
#include <cstdio>
#include <vector>

using namespace hybridwalk;

int main(int argc, char** argv) {
  const char* spec = argc > 1 ? argv[1] : "indoor";
  auto scene = Scene::load(spec);
  if (!scene) return std::fprintf(stderr, "error: %s\n", scene.error().message.c_str()), 1;
  auto path = scene->defaultPath();
  if (!path) return std::fprintf(stderr, "error: %s\n", path.error().message.c_str()), 1;
  if (path->cameras.empty())
    return std::fprintf(stderr, "error: %s: empty default path\n", spec), 1;
  auto renderer = Renderer::create(*scene, RendererDesc{});
  if (!renderer) return std::fprintf(stderr, "error: %s\n", renderer.error().message.c_str()), 1;
  Frame frame, reference;
  std::vector<double> psnrs;
  int built = 0;
  for (const Camera& cam : path->cameras) {
    if (auto st = renderer->render(cam, frame); !st)
      return std::fprintf(stderr, "error: %s\n", st.error().message.c_str()), 1;
    if (auto st = renderer->renderGeometry(cam, reference); !st)
      return std::fprintf(stderr, "error: %s\n", st.error().message.c_str()), 1;
    built += frame.stats.keyframesBuilt;
    if (frame.stats.kind == FrameKind::Warped) psnrs.push_back(psnr(frame, reference));
  }
  if (psnrs.empty() || built == 0)
    return std::fprintf(stderr, "error: %s: no frame warped (%d keyframes built)\n", spec, built),
           1;
  std::sort(psnrs.begin(), psnrs.end());
  const std::size_t n = path->cameras.size();
  std::printf(
      "free camera: %s, %zu frames %dx%d, %d keyframes built, one every %.1f frames, "
      "warped %zu, PSNR median %.1f dB\n",
      spec, n, path->cameras[0].width, path->cameras[0].height, built,
      static_cast<double>(n) / built, psnrs.size(), psnrs[psnrs.size() / 2]);
  return 0;
}
