// CPU time (not wall time: the machine was shared) of the CPU stages this
// study adds, at 512²: compose overlay / depth-merge / blend (every pixel both
// layers cover, 70 %, at consistent depth: the blend's worst case), and the
// reprojected fallback (reprojectFrame of a full previous frame + fillHoles)
// with 10 % holes. Build from the repository root after `ninja -C build`:
//   g++ -std=c++20 -O3 -I. docs/results/2026-12-03/blend-fallback/cpu_cost.cpp \
//     build/libhw_gapfill.a build/libhw_warp.a build/libhw_keyframe.a \
//     build/libhw_scenes.a build/libhw_core.a -o /tmp/cpu_cost && /tmp/cpu_cost
#include <time.h>

#include <cstdio>
#include <random>

#include "gapfill/fallback.h"

using namespace hw;

static double cpuMs() {
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

int main() {
  const int n = 512;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  warp::Layer fg, bg;
  for (warp::Layer* l : {&fg, &bg}) {
    l->colour.resize(n, n, Rgba8{120, 90, 60, 255});
    l->coverage.resize(n, n, 0);
    l->eyeZ.resize(n, n, 0.0f);
  }
  for (int by = 0; by < n; by += 8)
    for (int bx = 0; bx < n; bx += 8) {
      const float z = 2.0f + 8.0f * u(rng);
      const bool f = u(rng) < 0.85f, b = u(rng) < 0.82f;
      for (int y = by; y < by + 8; ++y)
        for (int x = bx; x < bx + 8; ++x) {
          if (f) fg.coverage(x, y) = 1, fg.eyeZ(x, y) = z;
          if (b) bg.coverage(x, y) = 1, bg.eyeZ(x, y) = z;
        }
    }
  const Camera cam = Camera::lookAt({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 1.047, n, n, 0.1, 1000);
  const Camera prevCam =
      Camera::lookAt({-0.05, 0, 0.05}, {-0.1, 0, -1}, {0, 1, 0}, 1.047, n, n, 0.1, 1000);
  gapfill::BlendViews views{cam, {-0.3, 0, 0.2}, {0.4, 0, -0.3}};
  gapfill::Frame prev, out;
  gapfill::compose(fg, &bg, nullptr, {}, prev);
  gapfill::layerDepth(fg, &bg, false, prev);
  prev.camera = prevCam;
  const int reps = 50;
  for (auto mode : {gapfill::ComposeMode::Overlay, gapfill::ComposeMode::DepthMerge,
                    gapfill::ComposeMode::Blend}) {
    gapfill::ComposeOptions o;
    o.mode = mode;
    gapfill::compose(fg, &bg, &prev, o, &views, out);
    const double t0 = cpuMs();
    for (int r = 0; r < reps; ++r) gapfill::compose(fg, &bg, &prev, o, &views, out);
    std::printf("compose %-12s %.3f ms CPU (blended %d px, holes %.1f %%)\n",
                gapfill::composeModeName(mode), (cpuMs() - t0) / reps, out.blended,
                100 * out.holeFractionBefore);
  }
  gapfill::Frame rep;
  gapfill::compose(fg, &bg, nullptr, {}, out);
  gapfill::layerDepth(fg, &bg, false, out);
  const gapfill::Frame base = out;
  double total = 0;
  for (int r = 0; r < reps; ++r) {
    out = base;
    const double t0 = cpuMs();
    gapfill::reprojectFrame(prev, cam, rep, &out.valid);
    gapfill::fillHoles(rep, &prev, out);
    total += cpuMs() - t0;
  }
  std::printf("reproject + fill %.3f ms CPU (holes %.1f %%)\n", total / reps,
              100 * base.holeFractionBefore);
}
