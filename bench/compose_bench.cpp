// Cost of the per-frame CPU stages after warping: composition (Zheng et al.
// 1999 §2.2, both modes) and the quality metrics (PSNR, SSIM) at 512² and
// 1024². Layers are synthetic with realistic coverage (fg ~85 %, bg ~70 %).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdint>
#include <random>

#include "core/metrics.h"
#include "gapfill/compose.h"

namespace {

using hw::Image;
using hw::Rgba8;

Image<Rgba8> noiseImage(int w, int h, std::uint32_t seed) {
  std::mt19937 rng(seed);
  Image<Rgba8> im(w, h);
  for (Rgba8& p : im.pixels()) {
    const std::uint32_t v = rng();
    p = Rgba8{static_cast<std::uint8_t>(v), static_cast<std::uint8_t>(v >> 8),
              static_cast<std::uint8_t>(v >> 16), 255};
  }
  return im;
}

// Coverage in blocks (as quads give), so branch patterns are not pure noise.
hw::warp::Layer makeLayer(int w, int h, double coverFraction, float zBase, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  hw::warp::Layer l;
  l.colour = noiseImage(w, h, seed + 1);
  l.coverage.resize(w, h, 0);
  l.eyeZ.resize(w, h, 0.0f);
  constexpr int kBlock = 8;
  for (int by = 0; by < h; by += kBlock) {
    for (int bx = 0; bx < w; bx += kBlock) {
      if (u(rng) >= coverFraction) continue;
      const float z = zBase * static_cast<float>(0.5 + u(rng));
      for (int y = by; y < std::min(h, by + kBlock); ++y) {
        for (int x = bx; x < std::min(w, bx + kBlock); ++x) {
          l.coverage(x, y) = 1;
          l.eyeZ(x, y) = z;
        }
      }
    }
  }
  return l;
}

void composeBench(benchmark::State& state, hw::gapfill::ComposeMode mode) {
  const int n = static_cast<int>(state.range(0));
  const hw::warp::Layer fg = makeLayer(n, n, 0.85, 10.0f, 1);
  const hw::warp::Layer bg = makeLayer(n, n, 0.70, 10.0f, 2);
  hw::gapfill::Frame frames[2];
  hw::gapfill::ComposeOptions options;
  options.mode = mode;
  hw::gapfill::compose(fg, &bg, nullptr, options, frames[0]);
  frames[0].valid.fill(1);  // a previous frame with no holes of its own
  int i = 0;
  for (auto _ : state) {
    // Ping-pong, as a walkthrough does: last frame is `previous`.
    hw::gapfill::compose(fg, &bg, &frames[i], options, frames[1 - i]);
    benchmark::DoNotOptimize(frames[1 - i].colour.data());
    i = 1 - i;
  }
  state.counters["holesAfter"] = frames[i].holeFractionAfter;
  state.SetItemsProcessed(state.iterations() * n * n);
}

void BM_ComposeOverlay(benchmark::State& state) {
  composeBench(state, hw::gapfill::ComposeMode::Overlay);
}
void BM_ComposeDepthMerge(benchmark::State& state) {
  composeBench(state, hw::gapfill::ComposeMode::DepthMerge);
}

// Reference vs a lightly perturbed copy, as a frame vs its reference.
void metricPair(int n, Image<Rgba8>* a, Image<Rgba8>* b) {
  *a = noiseImage(n, n, 7);
  *b = *a;
  std::mt19937 rng(8);
  for (Rgba8& p : b->pixels()) p.g = static_cast<std::uint8_t>(p.g + (rng() % 5) - 2);
}

void BM_Psnr(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  Image<Rgba8> a, b;
  metricPair(n, &a, &b);
  for (auto _ : state) benchmark::DoNotOptimize(hw::psnr(a, b));
  state.SetItemsProcessed(state.iterations() * n * n);
}

void BM_Ssim(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  Image<Rgba8> a, b;
  metricPair(n, &a, &b);
  for (auto _ : state) benchmark::DoNotOptimize(hw::ssim(a, b));
  state.SetItemsProcessed(state.iterations() * n * n);
}

BENCHMARK(BM_ComposeOverlay)->Arg(512)->Arg(1024)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ComposeDepthMerge)->Arg(512)->Arg(1024)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Psnr)->Arg(512)->Arg(1024)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Ssim)->Arg(512)->Arg(1024)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
