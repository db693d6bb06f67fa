// LOD builder timings (Zheng et al. 1999 §1.2): Δ buffer, binary subdivision,
// corner recovery and the whole build, one thread, on an analytic room
// keyframe (planes, boxes, a sphere) at 512² and 1024² for τ = 2^8 … 2^16.
#include <benchmark/benchmark.h>

#include <map>

#include "keyframe/analytic_scene.h"
#include "keyframe/delta_buffer.h"
#include "keyframe/lod_builder.h"

namespace hw::keyframe {
namespace {

const Keyframe& roomKeyframe(int size) {
  static std::map<int, Keyframe> cache;
  auto it = cache.find(size);
  if (it == cache.end()) {
    it = cache.emplace(size, renderAnalyticKeyframe(makeRoomScene(), makeRoomCamera(size, size)))
             .first;
  }
  return it->second;
}

LodOptions optionsFor(const benchmark::State& state) {
  LodOptions o;
  o.tau = static_cast<double>(1LL << state.range(1));
  o.criterion = state.range(2) == 0 ? DeltaCriterion::FivePoint : DeltaCriterion::PerAxisMax;
  return o;
}

void setLabel(benchmark::State& state, const LodOptions& o) {
  state.SetLabel(std::string("room tau=2^") + std::to_string(state.range(1)) + " " +
                 deltaCriterionName(o.criterion));
}

void BM_DeltaBuffer(benchmark::State& state) {
  const Keyframe& kf = roomKeyframe(static_cast<int>(state.range(0)));
  const auto c = state.range(1) == 0 ? DeltaCriterion::FivePoint : DeltaCriterion::PerAxisMax;
  Image<float> delta(kf.zPrime.width(), kf.zPrime.height());
  for (auto _ : state) {
    computeDeltaBuffer(kf.zPrime.view(), kf.covered.view(), c, delta.view());
    benchmark::DoNotOptimize(delta.data());
    benchmark::ClobberMemory();
  }
  state.SetLabel(deltaCriterionName(c));
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(delta.size()));
}

// Valid mask + Δ buffer (what build() spends before subdividing).
void BM_Prepare(benchmark::State& state) {
  const Keyframe& kf = roomKeyframe(static_cast<int>(state.range(0)));
  const LodOptions o = optionsFor(state);
  LodBuilder b;
  for (auto _ : state) {
    const Status st = b.prepare(kf.zPrime.view(), kf.covered.view(), kf.camera, o);
    benchmark::DoNotOptimize(st.ok());
  }
  setLabel(state, o);
}

void BM_Subdivide(benchmark::State& state) {
  const Keyframe& kf = roomKeyframe(static_cast<int>(state.range(0)));
  const LodOptions o = optionsFor(state);
  LodBuilder b;
  if (!b.prepare(kf.zPrime.view(), kf.covered.view(), kf.camera, o).ok()) {
    state.SkipWithError("prepare failed");
    return;
  }
  for (auto _ : state) benchmark::DoNotOptimize(b.subdivide());
  state.counters["quads"] = static_cast<double>(b.leaves().size());
  setLabel(state, o);
}

void BM_Corners(benchmark::State& state) {
  const Keyframe& kf = roomKeyframe(static_cast<int>(state.range(0)));
  const LodOptions o = optionsFor(state);
  LodBuilder b;
  if (!b.prepare(kf.zPrime.view(), kf.covered.view(), kf.camera, o).ok()) {
    state.SkipWithError("prepare failed");
    return;
  }
  b.subdivide();
  QuadMesh mesh;
  for (auto _ : state) benchmark::DoNotOptimize(b.recoverCorners(&mesh));
  state.counters["quads"] = static_cast<double>(mesh.quads.size());
  state.counters["clamped"] = mesh.stats.clampedCorners;
  setLabel(state, o);
}

void BM_Build(benchmark::State& state) {
  const Keyframe& kf = roomKeyframe(static_cast<int>(state.range(0)));
  const LodOptions o = optionsFor(state);
  LodBuilder b;
  QuadMesh mesh;
  double deltaMs = 0, subdivideMs = 0, cornersMs = 0;
  for (auto _ : state) {
    const Status st = b.build(kf, o, &mesh);
    benchmark::DoNotOptimize(st.ok());
    deltaMs += mesh.stats.deltaMs;
    subdivideMs += mesh.stats.subdivideMs;
    cornersMs += mesh.stats.cornersMs;
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["quads"] = mesh.stats.quads;
  state.counters["onePixel"] = mesh.stats.onePixelLeaves;
  state.counters["delta_ms"] = deltaMs / n;
  state.counters["subdivide_ms"] = subdivideMs / n;
  state.counters["corners_ms"] = cornersMs / n;
  setLabel(state, o);
}

void lodArgs(benchmark::internal::Benchmark* b) {
  b->ArgNames({"size", "tau_log2", "per_axis"});
  for (int size : {512, 1024})
    for (int t : {8, 11, 13, 15, 16}) b->Args({size, t, 0});
  for (int size : {512, 1024}) b->Args({size, 11, 1});
  b->Unit(benchmark::kMillisecond);
}

BENCHMARK(BM_DeltaBuffer)
    ->ArgNames({"size", "per_axis"})
    ->ArgsProduct({{512, 1024}, {0, 1}})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Prepare)->Apply(lodArgs);
BENCHMARK(BM_Subdivide)->Apply(lodArgs);
BENCHMARK(BM_Corners)->Apply(lodArgs);
BENCHMARK(BM_Build)->Apply(lodArgs);

}  // namespace
}  // namespace hw::keyframe

BENCHMARK_MAIN();
