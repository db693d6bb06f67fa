// Frame-timing benchmark (not a test): geometry render time of the built-in
// scenes against their triangle count, and hybrid in-between frame time and
// quality against the geometry frame at the same camera, at the paper's two
// thresholds. Writes JSON + CSV (+ PNG plots) to --out (default out/bench).
//   frame_timing_bench [--out DIR] [--quick] [--sizes 10k,100k,1M,4M]
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/plot.h"
#include "bench/walk.h"
#include "core/file_io.h"
#include "core/gl/context.h"
#include "core/machine.h"
#include "core/timer.h"
#include "scenes/loader.h"
#include "scenes/procedural.h"

namespace {

using namespace hw;  // NOLINT
using nlohmann::json;

std::vector<std::size_t> parseSizes(const std::string& s) {
  std::vector<std::size_t> out;
  std::size_t start = 0;
  while (start < s.size()) {
    std::size_t end = s.find(',', start);
    if (end == std::string::npos) end = s.size();
    std::string t = s.substr(start, end - start);
    double mul = 1;
    if (!t.empty() && (t.back() == 'k' || t.back() == 'K')) mul = 1e3, t.pop_back();
    if (!t.empty() && (t.back() == 'm' || t.back() == 'M')) mul = 1e6, t.pop_back();
    out.push_back(static_cast<std::size_t>(std::stod(t) * mul));
    start = end + 1;
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  std::string outDir = "out/bench";
  std::string sizesS = "10k,100k,1M,4M", walkSizesS = "100k,1M";
  int renderFrames = 20, walkFrames = 41;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "frame_timing_bench: %s needs a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--out") outDir = next();
    else if (a == "--sizes") sizesS = next();
    else if (a == "--walk-sizes") walkSizesS = next();
    else if (a == "--quick") sizesS = "10k,100k", walkSizesS = "100k", renderFrames = 6, walkFrames = 21;
    else {
      std::fprintf(stderr,
                   "usage: frame_timing_bench [--out DIR] [--quick] [--sizes LIST] [--walk-sizes LIST]\n"
                   "  LIST: triangle targets like 10k,100k,1M,4M\n");
      return a == "--help" || a == "-h" ? 0 : 2;
    }
  }
  if (auto s = ensureWritableDir(outDir); !s) {
    std::fprintf(stderr, "frame_timing_bench: error: %s\n", s.error().message.c_str());
    return 1;
  }
  auto ctx = gl::createHeadlessContext();
  if (!ctx) {
    std::fprintf(stderr, "frame_timing_bench: error: %s\n", ctx.error().message.c_str());
    return 1;
  }
  json renderRows = json::array(), walkRows = json::array();
  std::string csv = "kind,scene,target_triangles,triangles,tau,median_ms,p95_ms,reference_median_ms,"
                    "reference_p95_ms,psnr_median,quads_per_keyframe,speedup_median\n";
  const char* names[2] = {"indoor", "outdoor"};
  for (const char* name : names) {
    for (std::size_t target : parseSizes(sizesS)) {
      Stopwatch gen;
      scenes::Scene scene = std::strcmp(name, "indoor") == 0 ? scenes::makeIndoorScene(target)
                                                              : scenes::makeOutdoorScene(target);
      const double genMs = gen.ms();
      const scenes::CameraPath path = std::strcmp(name, "indoor") == 0
                                          ? scenes::defaultIndoorPath()
                                          : scenes::defaultOutdoorPath();
      auto r = keyframe::GeometryRenderer::create(scene);
      if (!r) {
        std::fprintf(stderr, "error: %s\n", r.error().message.c_str());
        return 1;
      }
      std::vector<double> ms;
      Image<Rgba8> img;
      for (int k = 0; k < renderFrames; ++k) {
        keyframe::RenderStats st;
        const int f = k * (path.frames - 1) / std::max(1, renderFrames - 1);
        if (auto s = (*r)->renderColour(path.cameraAt(f), img, &st); !s) {
          std::fprintf(stderr, "error: %s\n", s.error().message.c_str());
          return 1;
        }
        if (k > 0) ms.push_back(st.drawMs + st.readbackMs);  // first frame warms up
      }
      const double med = median(ms), p95 = percentile(ms, 95);
      std::fprintf(stderr, "render %-7s %8zu tris: median %7.2f ms  p95 %7.2f ms  (generated in %.0f ms)\n",
                   name, scene.triangleCount(), med, p95, genMs);
      renderRows.push_back({{"scene", name}, {"target_triangles", target},
                            {"triangles", scene.triangleCount()}, {"frames", ms.size()},
                            {"median_ms", med}, {"p95_ms", p95}, {"generate_ms", genMs}});
      csv += std::string("render,") + name + "," + std::to_string(target) + "," +
             std::to_string(scene.triangleCount()) + ",," + std::to_string(med) + "," +
             std::to_string(p95) + ",,,,,\n";
      r->reset();
      bool walkThis = false;
      for (std::size_t w : parseSizes(walkSizesS)) walkThis |= w == target;
      if (!walkThis) continue;
      for (double tau : {2048.0, 32768.0}) {
        bench::WalkOptions o;
        o.lod.tau = tau;
        o.maxFrames = walkFrames;
        o.progress = false;
        o.glRenderer = (*ctx)->renderer();
        o.glVersion = (*ctx)->version();
        auto res = bench::runWalk(scene, name, path, o);
        if (!res) {
          std::fprintf(stderr, "error: %s\n", res.error().message.c_str());
          return 1;
        }
        const json& s = res->report["summary"];
        json row = {{"scene", name},
                    {"target_triangles", target},
                    {"triangles", scene.triangleCount()},
                    {"tau", tau},
                    {"frames", walkFrames},
                    {"in_between_ms", s["in_between_ms"]},
                    {"reference_ms", s["reference_ms"]},
                    {"psnr", s["psnr"]},
                    {"ssim", s["ssim"]},
                    {"holes_before_fallback", s["holes_before_fallback"]},
                    {"quads_per_keyframe", s["quads_per_keyframe"]},
                    {"keyframe_build_ms", s["keyframe_build_ms"]},
                    {"speedup", s["speedup_reference_over_in_between"]}};
        auto num = [](const json& j) { return j.is_number() ? j.get<double>() : -1.0; };
        std::fprintf(stderr,
                     "walk   %-7s %8zu tris tau %6.0f: in-between %6.2f ms (p95 %6.2f) vs geometry "
                     "%7.2f ms (p95 %7.2f), speedup %5.1fx, PSNR %.2f dB, %5.0f quads/keyframe\n",
                     name, scene.triangleCount(), tau, num(s["in_between_ms"]["median"]),
                     num(s["in_between_ms"]["p95"]), num(s["reference_ms"]["median"]),
                     num(s["reference_ms"]["p95"]),
                     num(s["speedup_reference_over_in_between"]["median"]),
                     num(s["psnr"]["median"]), num(s["quads_per_keyframe"]["median"]));
        walkRows.push_back(row);
        csv += std::string("walk,") + name + "," + std::to_string(target) + "," +
               std::to_string(scene.triangleCount()) + "," + std::to_string(tau) + "," +
               std::to_string(num(s["in_between_ms"]["median"])) + "," +
               std::to_string(num(s["in_between_ms"]["p95"])) + "," +
               std::to_string(num(s["reference_ms"]["median"])) + "," +
               std::to_string(num(s["reference_ms"]["p95"])) + "," +
               std::to_string(num(s["psnr"]["median"])) + "," +
               std::to_string(num(s["quads_per_keyframe"]["median"])) + "," +
               std::to_string(num(s["speedup_reference_over_in_between"]["median"])) + "\n";
      }
    }
  }
  json out = {{"resolution", {512, 512}},
              {"render", renderRows},
              {"walk", walkRows},
              {"machine", machineInfo((*ctx)->renderer(), (*ctx)->version())},
              {"note", "times are wall-clock ms on a shared 2-vCPU VM with llvmpipe; they move "
                       "±30-50% between runs (NOTES-GL.md). Ratios within one run are steadier."}};
  if (auto s = writeFileAtomic(outDir + "/frame_timing.json", out.dump(1)); !s) {
    std::fprintf(stderr, "error: %s\n", s.error().message.c_str());
    return 1;
  }
  if (auto s = writeFileAtomic(outDir + "/frame_timing.csv", csv); !s) {
    std::fprintf(stderr, "error: %s\n", s.error().message.c_str());
    return 1;
  }
  // Plots: geometry ms vs triangles (log-log), with the in-between frame ms
  // of each walk, one series per scene and τ.
  std::vector<bench::Series> series;
  for (const char* name : names) {
    bench::Series g;
    g.label = std::string("geometry, ") + name;
    for (const json& r : renderRows)
      if (r["scene"] == name) {
        g.x.push_back(r["triangles"].get<double>());
        g.y.push_back(r["median_ms"].get<double>());
      }
    series.push_back(g);
    for (double tau : {2048.0, 32768.0}) {
      bench::Series h;
      h.label = std::string("hybrid in-between, ") + name + (tau < 4096 ? ", tau 2^11" : ", tau 2^15");
      for (const json& r : walkRows)
        if (r["scene"] == name && r["tau"].get<double>() == tau && r["in_between_ms"]["median"].is_number()) {
          h.x.push_back(r["triangles"].get<double>());
          h.y.push_back(r["in_between_ms"]["median"].get<double>());
        }
      if (!h.x.empty()) series.push_back(h);
    }
  }
  bench::PlotOptions po;
  po.title = "Frame time vs scene size (512x512, median)";
  po.xLabel = "triangles";
  po.yLabel = "ms per frame";
  po.logX = po.logY = true;
  po.width = 900;
  po.height = 560;
  if (auto s = bench::writePlot(outDir + "/frame_time_vs_triangles.png", series, po); !s) {
    std::fprintf(stderr, "error: %s\n", s.error().message.c_str());
    return 1;
  }
  std::printf("wrote %s/frame_timing.json, .csv and frame_time_vs_triangles.png\n", outDir.c_str());
  return 0;
}
