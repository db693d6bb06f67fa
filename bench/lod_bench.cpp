// LOD builder timings (Zheng et al. 1999 §1.2): Δ buffer, binary subdivision,
// corner recovery and the whole build, one thread, at 512² and 1024² for
// τ = 2^8 … 2^16, on keyframes of the built-in indoor and outdoor scenes
// (rendered on OSMesa, frame 50 of their default paths, 100k triangles) and on
// an analytic room (planes, boxes, a sphere; no GL).
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>

#include "core/gl/context.h"
#include "keyframe/analytic_scene.h"
#include "keyframe/geometry_renderer.h"
#include "scenes/procedural.h"
#include "keyframe/delta_buffer.h"
#include "keyframe/lod_builder.h"

namespace hw::keyframe {
namespace {

const char* kSceneNames[3] = {"room", "indoor", "outdoor"};

Keyframe renderedKeyframe(int scene, int size) {
  static std::unique_ptr<gl::Context> ctx;
  if (!ctx) {
    auto c = gl::createHeadlessContext();
    if (!c) {
      std::fprintf(stderr, "lod_bench: %s\n", c.error().message.c_str());
      std::exit(1);
    }
    ctx = std::move(*c);
  }
  const scenes::Scene s = scene == 1 ? scenes::makeIndoorScene(100000) : scenes::makeOutdoorScene(100000);
  Camera cam = (scene == 1 ? scenes::defaultIndoorPath() : scenes::defaultOutdoorPath()).cameraAt(50);
  cam.width = cam.height = size;
  auto r = GeometryRenderer::create(s);
  Keyframe kf;
  if (!r || !(*r)->renderKeyframe(cam, kf).ok()) {
    std::fprintf(stderr, "lod_bench: cannot render the %s keyframe\n", kSceneNames[scene]);
    std::exit(1);
  }
  return kf;
}

// scene: 0 analytic room, 1 indoor, 2 outdoor.
const Keyframe& keyframeFor(int scene, int size) {
  static std::map<std::pair<int, int>, Keyframe> cache;
  auto it = cache.find({scene, size});
  if (it == cache.end()) {
    Keyframe kf = scene == 0 ? renderAnalyticKeyframe(makeRoomScene(), makeRoomCamera(size, size))
                             : renderedKeyframe(scene, size);
    it = cache.emplace(std::make_pair(scene, size), std::move(kf)).first;
  }
  return it->second;
}

const Keyframe& roomKeyframe(const benchmark::State& state) {
  return keyframeFor(static_cast<int>(state.range(3)), static_cast<int>(state.range(0)));
}

LodOptions optionsFor(const benchmark::State& state) {
  LodOptions o;
  o.tau = static_cast<double>(1LL << state.range(1));
  o.criterion = state.range(2) == 0 ? DeltaCriterion::FivePoint : DeltaCriterion::PerAxisMax;
  return o;
}

void setLabel(benchmark::State& state, const LodOptions& o) {
  state.SetLabel(std::string(kSceneNames[state.range(3)]) + " tau=2^" + std::to_string(state.range(1)) + " " +
                 deltaCriterionName(o.criterion));
}

void BM_DeltaBuffer(benchmark::State& state) {
  const Keyframe& kf = keyframeFor(static_cast<int>(state.range(2)), static_cast<int>(state.range(0)));
  const auto c = state.range(1) == 0 ? DeltaCriterion::FivePoint : DeltaCriterion::PerAxisMax;
  Image<float> delta(kf.zPrime.width(), kf.zPrime.height());
  for (auto _ : state) {
    computeDeltaBuffer(kf.zPrime.view(), kf.covered.view(), c, delta.view());
    benchmark::DoNotOptimize(delta.data());
    benchmark::ClobberMemory();
  }
  state.SetLabel(std::string(kSceneNames[state.range(2)]) + " " + deltaCriterionName(c));
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(delta.size()));
}

// Valid mask + Δ buffer (what build() spends before subdividing).
void BM_Prepare(benchmark::State& state) {
  const Keyframe& kf = roomKeyframe(state);
  const LodOptions o = optionsFor(state);
  LodBuilder b;
  for (auto _ : state) {
    const Status st = b.prepare(kf.zPrime.view(), kf.covered.view(), kf.camera, o);
    benchmark::DoNotOptimize(st.ok());
  }
  setLabel(state, o);
}

void BM_Subdivide(benchmark::State& state) {
  const Keyframe& kf = roomKeyframe(state);
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
  const Keyframe& kf = roomKeyframe(state);
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
  const Keyframe& kf = roomKeyframe(state);
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

// The robust depth gradient of LodOptions::tauGradient, alone.
void BM_DepthGradient(benchmark::State& state) {
  const Keyframe& kf = keyframeFor(static_cast<int>(state.range(1)), static_cast<int>(state.range(0)));
  Image<float> g(kf.zPrime.width(), kf.zPrime.height());
  for (auto _ : state) {
    computeDepthGradient(kf.zPrime.view(), kf.covered.view(), &g);
    benchmark::DoNotOptimize(g.data());
    benchmark::ClobberMemory();
  }
  state.SetLabel(kSceneNames[state.range(1)]);
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(g.size()));
}

// Whole build at τ = 2^3 with tauGradient 0 or the suggested value, both
// planarities: what the variant adds (Δ pass: the gradient; subdivision:
// the per-pixel threshold).
void BM_BuildGradTol(benchmark::State& state) {
  const Keyframe& kf = keyframeFor(static_cast<int>(state.range(3)), static_cast<int>(state.range(0)));
  LodOptions o;
  o.tau = 8;
  o.tauGradient = state.range(1) != 0 ? suggestedTauGradient() : 0.0;
  o.planarity = state.range(2) != 0 ? Planarity::RegionLocal : Planarity::Stencil;
  LodBuilder b;
  QuadMesh mesh;
  double deltaMs = 0, subdivideMs = 0;
  for (auto _ : state) {
    const Status st = b.build(kf, o, &mesh);
    benchmark::DoNotOptimize(st.ok());
    deltaMs += mesh.stats.deltaMs;
    subdivideMs += mesh.stats.subdivideMs;
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["quads"] = mesh.stats.quads;
  state.counters["delta_ms"] = deltaMs / n;
  state.counters["subdivide_ms"] = subdivideMs / n;
  state.SetLabel(std::string(kSceneNames[state.range(3)]) + " " + planarityName(o.planarity) +
                 (o.tauGradient > 0 ? " tauGradient" : " fixed"));
}

void lodArgs(benchmark::internal::Benchmark* b) {
  b->ArgNames({"size", "tau_log2", "per_axis", "scene"});
  for (int scene : {1, 2, 0})
    for (int size : {512, 1024}) {
      for (int t : {8, 11, 13, 15, 16}) b->Args({size, t, 0, scene});
      b->Args({size, 11, 1, scene});
    }
  b->Unit(benchmark::kMillisecond);
}

BENCHMARK(BM_DeltaBuffer)
    ->ArgNames({"size", "per_axis", "scene"})
    ->ArgsProduct({{512, 1024}, {0, 1}, {1, 2, 0}})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DepthGradient)
    ->ArgNames({"size", "scene"})
    ->ArgsProduct({{512, 1024}, {1, 2, 0}})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BuildGradTol)
    ->ArgNames({"size", "grad", "local", "scene"})
    ->ArgsProduct({{512}, {0, 1}, {0, 1}, {1, 2}})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Prepare)->Apply(lodArgs);
BENCHMARK(BM_Subdivide)->Apply(lodArgs);
BENCHMARK(BM_Corners)->Apply(lodArgs);
BENCHMARK(BM_Build)->Apply(lodArgs);

}  // namespace
}  // namespace hw::keyframe

BENCHMARK_MAIN();
