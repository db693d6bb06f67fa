// The fused pair of warped layers (foreground + background where it left
// pixels empty, with the readback the GL warper needs) drawn by the GL
// warper and by the CPU warper on 1 and 2 threads, in turn, in one process
// (ratios hold on a shared machine): keyframes every `gap` frames of the
// scene's default path at 512², every frame between them warped.
// Usage: warp_cpu_bench SCENE [GAP=10] [FRAMES=60]; ONLY=K in the environment times
// variant K alone (0 GL, 1 CPU 1 thread, 2 CPU 2 threads), for profiling;
// EYEZ=1 makes the layers carry eye z (as blend composition needs).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <memory>
#include <vector>

#include "core/gl/context.h"
#include "core/metrics.h"
#include "core/timer.h"
#include "keyframe/geometry_renderer.h"
#include "keyframe/lod_builder.h"
#include "scenes/camera_path.h"
#include "scenes/loader.h"
#include "warp/cpu_warper.h"
#include "warp/warper.h"

int main(int argc, char** argv) {
  using namespace hw;
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s SCENE [GAP] [FRAMES]\n", argv[0]);
    return 2;
  }
  const int gap = argc > 2 ? std::atoi(argv[2]) : 10;
  const int frames = argc > 3 ? std::atoi(argv[3]) : 60;
  if (gap < 2 || frames < gap) return std::fprintf(stderr, "expected GAP >= 2, FRAMES >= GAP\n"), 2;
  auto scene = scenes::loadScene(argv[1]);
  if (!scene) return std::fprintf(stderr, "%s\n", scene.error().message.c_str()), 1;
  auto path = scenes::defaultPathFor(argv[1]);
  if (!path) return std::fprintf(stderr, "%s\n", path.error().message.c_str()), 1;
  auto ctx = gl::createHeadlessContext();
  if (!ctx) return std::fprintf(stderr, "%s\n", ctx.error().message.c_str()), 1;
  auto renderer = keyframe::GeometryRenderer::create(*scene);
  if (!renderer) return std::fprintf(stderr, "%s\n", renderer.error().message.c_str()), 1;
  struct Variant {
    const char* name;
    std::unique_ptr<warp::Warper> warper;
    std::vector<double> ms, cpu;
    warp::Layer layer;
  };
  std::vector<Variant> v(3);
  v[0].name = "GL (llvmpipe), with readback";
  v[1].name = "CPU, 1 thread";
  v[2].name = "CPU, 2 threads";
  warp::WarpOptions wo;
  wo.writeEyeZ = std::getenv("EYEZ") != nullptr;
  auto gw = warp::Warper::create(wo);
  auto c1 = warp::createCpuWarper(wo, 1), c2 = warp::createCpuWarper(wo, 2);
  if (!gw || !c1 || !c2) return std::fprintf(stderr, "warper\n"), 1;
  v[0].warper = std::move(*gw);
  v[1].warper = std::move(*c1);
  v[2].warper = std::move(*c2);
  keyframe::LodOptions lod;
  lod.planarity = keyframe::Planarity::RegionLocal;
  lod.mergeStrips = true;
  lod.tauParallaxPx = 0.125;  // the walk's default
  keyframe::LodBuilder builder;
  std::vector<double> quads, db1;
  const int last = std::min(frames, path->frames - 1);
  for (int k0 = 0; k0 + gap <= last; k0 += gap) {
    keyframe::Keyframe kf[2];
    keyframe::QuadMesh mesh[2];
    for (int s = 0; s < 2; ++s) {
      Camera c = path->cameraAt(k0 + s * gap);
      if (!(*renderer)->renderKeyframe(c, kf[s]).ok() || !builder.build(kf[s], lod, &mesh[s]).ok())
        return std::fprintf(stderr, "keyframe %d\n", k0 + s * gap), 1;
      quads.push_back(double(mesh[s].quads.size()));
    }
    std::vector<std::unique_ptr<warp::WarpSource>> src[3];
    for (int k = 0; k < 3; ++k)
      for (int s = 0; s < 2; ++s) {
        auto u = v[k].warper->upload(kf[s], mesh[s]);
        if (!u) return std::fprintf(stderr, "%s\n", u.error().message.c_str()), 1;
        src[k].push_back(std::move(*u));
      }
    for (int f = k0 + 1; f < k0 + gap; ++f) {
      const Camera cam = path->cameraAt(f);
      for (int rep = 0; rep < 2; ++rep)  // the first draw of each warms up
        for (int k = 0; k < 3; ++k) {
          if (std::getenv("ONLY") && std::atoi(std::getenv("ONLY")) != k) continue;
          Stopwatch sw;
          timespec t0, t1;
          clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t0);
          if (!v[k].warper->warpPair(*src[k][0], src[k][1].get(), cam, v[k].layer, true).ok())
            return 1;
          clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t1);
          if (rep == 1) v[k].ms.push_back(sw.ms());
          if (rep == 1) v[k].cpu.push_back((t1.tv_sec - t0.tv_sec) * 1e3 + (t1.tv_nsec - t0.tv_nsec) * 1e-6);
        }
      if (!std::getenv("ONLY")) db1.push_back(psnrCapped(v[0].layer.colour, v[1].layer.colour));
    }
  }
  std::printf("%s: %zu in-between frames at %dx%d, keyframes every %d, median %.0f quads per keyframe\n",
              argv[1], v[0].ms.size(), path->width, path->height, gap, median(quads));
  for (const Variant& x : v)
    std::printf("  %-32s median %6.2f ms  (%.2f x GL), calling thread's CPU %.2f ms\n", x.name,
                median(x.ms), median(x.ms) / median(v[0].ms), median(x.cpu));
  if (!db1.empty())
    std::printf("  CPU layer against GL layer: median %.1f dB, worst %.1f dB\n", median(db1),
                *std::min_element(db1.begin(), db1.end()));
  return 0;
}
