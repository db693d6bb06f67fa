#include "bench/sweep.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

#include "bench/html_report.h"
#include "bench/plot.h"
#include "bench/walk.h"
#include "core/file_io.h"
#include "core/machine.h"
#include "core/timer.h"
#include "keyframe/baseline_mesh.h"
#include "keyframe/keyframe_cache.h"
#include "keyframe/overlay.h"

namespace hw::bench {
namespace {

using nlohmann::json;

double num(const json& j) { return j.is_number() ? j.get<double>() : std::nan(""); }

std::string tauLabel(double tau) {
  const double l = std::log2(tau);
  if (tau > 0 && std::abs(l - std::round(l)) < 1e-9) return "2^" + std::to_string(int(std::lround(l)));
  return fmt(tau, 0);
}

struct Run {
  keyframe::MeshMethod mesh = keyframe::MeshMethod::Lod;
  keyframe::DeltaCriterion criterion = keyframe::DeltaCriterion::FivePoint;
  double tau = 0;
  int tileSize = 0;
  keyframe::Planarity planarity = keyframe::Planarity::Stencil;
  bool mergeStrips = false;
  std::string variant() const {
    std::string v = keyframe::planarityName(planarity);
    if (mergeStrips) v += "+merge";
    return v;
  }
  std::string method() const {
    if (mesh == keyframe::MeshMethod::Lod)
      return std::string("lod ") + keyframe::deltaCriterionName(criterion) +
             (planarity == keyframe::Planarity::Stencil && !mergeStrips ? "" : " " + variant());
    return keyframe::meshMethodName(mesh);
  }
};

}  // namespace

Result<json> runSweep(const scenes::Scene& scene, const std::string& sceneLabel,
                      const scenes::CameraPath& path, const SweepOptions& opt) {
  if (opt.outDir.empty()) return makeError("sweep: an output directory is required");
  std::vector<double> taus = opt.taus;
  if (taus.empty())
    for (int e = 6; e <= 16; ++e) taus.push_back(std::ldexp(1.0, e));
  for (double t : taus)
    if (!std::isfinite(t) || t < 0) return makeError("sweep: tau must be finite and >= 0, got " + fmt(t));

  const int frames = opt.maxFrames > 0 ? std::min(opt.maxFrames, path.frames) : path.frames;
  int overlayFrame = opt.overlayFrame;
  if (overlayFrame < 0) {
    overlayFrame = (frames / 2) / path.keyframeEvery * path.keyframeEvery;
  } else if (overlayFrame >= frames) {
    return makeError("sweep: overlay frame " + std::to_string(overlayFrame) + " is past the last frame " +
                     std::to_string(frames - 1));
  }
  HW_TRY(ensureWritableDir(opt.outDir));
  HW_TRY(ensureWritableDir(opt.outDir + "/overlays"));

  // The overlay keyframe: one render, one mesh per τ.
  keyframe::RenderOptions ropt;
  ropt.depthMode = opt.depthMode;
  auto renderer = keyframe::GeometryRenderer::create(scene, ropt);
  if (!renderer) return renderer.error();
  keyframe::Keyframe overlayKf;
  HW_TRY((*renderer)->renderKeyframe(path.cameraAt(overlayFrame), overlayKf));

  std::vector<Run> runs;
  using keyframe::Planarity;
  for (double tau : taus) {
    runs.push_back({keyframe::MeshMethod::Lod, keyframe::DeltaCriterion::FivePoint, tau, 0});
    if (opt.bothCriteria)
      runs.push_back({keyframe::MeshMethod::Lod, keyframe::DeltaCriterion::PerAxisMax, tau, 0});
    if (opt.variants) {  // issue #9's edge-strip variants, five-point
      runs.push_back({keyframe::MeshMethod::Lod, keyframe::DeltaCriterion::FivePoint, tau, 0,
                      Planarity::RegionLocal, false});
      runs.push_back({keyframe::MeshMethod::Lod, keyframe::DeltaCriterion::FivePoint, tau, 0,
                      Planarity::Stencil, true});
      runs.push_back({keyframe::MeshMethod::Lod, keyframe::DeltaCriterion::FivePoint, tau, 0,
                      Planarity::RegionLocal, true});
    }
  }
  json rows = json::array();
  std::set<int> tileSizesDone;
  Stopwatch all;
  auto progress = [&](std::size_t done, std::size_t total, const std::string& what) {
    if (!opt.progress) return;
    const double el = all.ms() / 1000.0;
    std::fprintf(stderr, "\rsweep: run %zu/%zu (%s) elapsed %.0f s, ETA %.0f s        ", done + 1,
                 total, what.c_str(), el, done > 0 ? el / done * (total - done) : 0.0);
    std::fflush(stderr);
  };

  auto runOne = [&](const Run& r) -> Result<json> {
    WalkOptions w;
    w.lod.tau = r.tau;
    w.lod.criterion = r.criterion;
    w.lod.planarity = r.planarity;
    w.lod.mergeStrips = r.mergeStrips;
    w.mesh = r.mesh;
    w.tileSize = r.tileSize;
    w.depthMode = opt.depthMode;
    w.maxFrames = frames;
    w.progress = false;
    w.strips = 0;
    w.glRenderer = opt.glRenderer;
    w.glVersion = opt.glVersion;
    auto res = runWalk(scene, sceneLabel, path, w);
    if (!res) return res.error();
    const json& s = res->report["summary"];
    json row = {{"method", r.method()},
                {"mesh", keyframe::meshMethodName(r.mesh)},
                {"criterion", r.mesh == keyframe::MeshMethod::Lod ? json(keyframe::deltaCriterionName(r.criterion)) : json(nullptr)},
                {"variant", r.mesh == keyframe::MeshMethod::Lod ? json(r.variant()) : json(nullptr)},
                {"tau", r.mesh == keyframe::MeshMethod::Lod ? json(r.tau) : json(nullptr)},
                {"tile_size", r.mesh == keyframe::MeshMethod::UniformTiles ? json(r.tileSize) : json(nullptr)},
                {"quads_per_keyframe", s["quads_per_keyframe"]},
                {"one_pixel_leaves_per_keyframe", s["one_pixel_leaves_per_keyframe"]},
                {"lod_build_ms", s["lod_build_ms"]},
                {"in_between_ms", s["in_between_ms"]},
                {"reference_ms", s["reference_ms"]},
                {"psnr", s["psnr"]},
                {"ssim", s["ssim"]},
                {"holes_before_fallback", s["holes_before_fallback"]}};
    return row;
  };

  // Total is known only after the five-point runs fix the tile sizes; count
  // the baselines as one per τ plus per-pixel.
  const std::size_t total = runs.size() + (opt.baselines ? taus.size() + 1 : 0);
  std::size_t done = 0;
  for (const Run& r : runs) {
    progress(done, total, r.method() + " tau " + tauLabel(r.tau));
    auto row = runOne(r);
    if (!row) return row.error();
    rows.push_back(*row);
    ++done;
  }
  if (opt.baselines) {
    // Uniform tiles at the quad count of each five-point τ (median per keyframe).
    for (const json& row : std::vector<json>(rows.begin(), rows.end())) {
      if (row["criterion"] != "five-point" || row["variant"] != "stencil") continue;
      const double q = num(row["quads_per_keyframe"]["median"]);
      const int ts = keyframe::tileSizeForQuadCount(overlayKf, static_cast<long long>(std::llround(q)));
      if (tileSizesDone.count(ts)) {
        ++done;
        continue;
      }
      tileSizesDone.insert(ts);
      Run r{keyframe::MeshMethod::UniformTiles, keyframe::DeltaCriterion::FivePoint, 0, ts};
      progress(done, total, "uniform tiles " + std::to_string(ts) + " px");
      auto br = runOne(r);
      if (!br) return br.error();
      (*br)["matched_to_tau"] = row["tau"];
      rows.push_back(*br);
      ++done;
    }
    progress(done, total, "per-pixel");
    auto pr = runOne(Run{keyframe::MeshMethod::PerPixel, keyframe::DeltaCriterion::FivePoint, 0, 1});
    if (!pr) return pr.error();
    rows.push_back(*pr);
    ++done;
  }
  if (opt.progress) std::fprintf(stderr, "\rsweep: %zu runs in %.0f s%40s\n", done, all.ms() / 1000.0, "");

  // Overlays, one per τ (five-point), on the same keyframe.
  json overlays = json::array();
  keyframe::LodBuilder builder;
  for (double tau : taus) {
    keyframe::QuadMesh mesh;
    keyframe::LodOptions lo;
    lo.tau = tau;
    HW_TRY(builder.build(overlayKf, lo, &mesh));
    const std::string name = "overlays/overlay_tau_" + fmt(tau, 0) + ".png";
    HW_TRY(writePng(opt.outDir + "/" + name, keyframe::drawQuadOverlay(overlayKf.colour, mesh)));
    overlays.push_back({{"tau", tau}, {"file", name}, {"quads", mesh.stats.quads},
                        {"one_pixel_leaves", mesh.stats.onePixelLeaves}});
  }

  // Plots.
  std::vector<std::string> methods;
  for (const json& r : rows) {
    const std::string m = r["method"].get<std::string>();
    if (std::find(methods.begin(), methods.end(), m) == methods.end()) methods.push_back(m);
  }
  auto seriesBy = [&](const char* xKey, const char* xStat, const char* yKey, const char* yStat,
                      bool lodOnly) {
    std::vector<Series> out;
    for (const std::string& m : methods) {
      Series s;
      s.label = m;
      std::vector<std::pair<double, double>> pts;
      for (const json& r : rows) {
        if (r["method"] != m) continue;
        if (lodOnly && r["mesh"] != "lod") continue;
        const double x = xStat ? num(r[xKey][xStat]) : num(r[xKey]);
        const double y = yStat ? num(r[yKey][yStat]) : num(r[yKey]);
        pts.push_back({x, y});
      }
      if (pts.empty()) continue;
      std::sort(pts.begin(), pts.end());
      for (auto [x, y] : pts) {
        s.x.push_back(x);
        s.y.push_back(y);
      }
      out.push_back(s);
    }
    return out;
  };
  PlotOptions po;
  po.title = "Run time against error: " + sceneLabel + " (" + std::to_string(path.width) + "x" +
             std::to_string(path.height) + ")";
  po.xLabel = "in-between frame ms (median)";
  po.yLabel = "PSNR dB (median)";
  po.logX = true;
  HW_TRY(writePlot(opt.outDir + "/pareto.png", seriesBy("in_between_ms", "median", "psnr", "median", false), po));
  po.title = "Quads per keyframe vs tau";
  po.xLabel = "tau (z' units)";
  po.yLabel = "quads per keyframe (median)";
  po.logX = po.logY = true;
  HW_TRY(writePlot(opt.outDir + "/quads_vs_tau.png", seriesBy("tau", nullptr, "quads_per_keyframe", "median", true), po));
  po.title = "PSNR vs tau";
  po.yLabel = "PSNR dB (median)";
  po.logY = false;
  HW_TRY(writePlot(opt.outDir + "/psnr_vs_tau.png", seriesBy("tau", nullptr, "psnr", "median", true), po));

  json doc = {{"scene", {{"name", sceneLabel}, {"triangles", scene.triangleCount()}}},
              {"resolution", {path.width, path.height}},
              {"frames", frames},
              {"keyframe_every", path.keyframeEvery},
              {"depth_mode", depthModeName(opt.depthMode)},
              {"overlay_frame", overlayFrame},
              {"rows", rows},
              {"overlays", overlays},
              {"plots", {"pareto.png", "quads_vs_tau.png", "psnr_vs_tau.png"}},
              {"machine", machineInfo(opt.glRenderer, opt.glVersion)}};

  std::string csv =
      "method,criterion,variant,tau,tile_size,quads_per_keyframe,lod_build_ms,in_between_ms_median,"
      "in_between_ms_p95,psnr_median,psnr_p5,ssim_median,ssim_p5,holes_before_median\n";
  std::vector<std::vector<std::string>> table;
  for (const json& r : rows) {
    const std::string crit = r["criterion"].is_string() ? r["criterion"].get<std::string>() : "";
    const std::string variant = r["variant"].is_string() ? r["variant"].get<std::string>() : "";
    const std::string tau = r["tau"].is_number() ? fmt(num(r["tau"]), 0) : "";
    const std::string tile = r["tile_size"].is_number() ? std::to_string(r["tile_size"].get<int>()) : "";
    const std::vector<std::string> cells = {
        r["mesh"].get<std::string>(), crit, variant, tau, tile,
        fmt(num(r["quads_per_keyframe"]["median"]), 0), fmt(num(r["lod_build_ms"]["median"])),
        fmt(num(r["in_between_ms"]["median"])), fmt(num(r["in_between_ms"]["p95"])),
        fmt(num(r["psnr"]["median"])), fmt(num(r["psnr"]["p5"])), fmt(num(r["ssim"]["median"]), 4),
        fmt(num(r["ssim"]["p5"]), 4), fmt(100 * num(r["holes_before_fallback"]["median"]), 3)};
    table.push_back(cells);
    for (std::size_t i = 0; i < cells.size(); ++i) csv += cells[i] + (i + 1 < cells.size() ? "," : "\n");
  }
  HW_TRY(writeFileAtomic(opt.outDir + "/sweep.csv", csv));
  HW_TRY(writeFileAtomic(opt.outDir + "/sweep.json", doc.dump(1)));

  HtmlReport page("hybridwalk sweep: " + sceneLabel);
  page.paragraph("Scene " + sceneLabel + " (" + std::to_string(scene.triangleCount()) +
                 " triangles), " + std::to_string(path.width) + "x" + std::to_string(path.height) +
                 ", " + std::to_string(frames) + " frames, a keyframe every " +
                 std::to_string(path.keyframeEvery) + ", depth " + depthModeName(opt.depthMode) +
                 ". Every row is the same walk; quality is PSNR/SSIM of the in-between frames "
                 "against the geometry renderer at the same camera. Machine: " +
                 doc["machine"]["cpu"].get<std::string>() + ", " + opt.glRenderer +
                 ". Times are wall-clock on a shared VM: they move by tens of percent between "
                 "runs.");
  page.heading("Run time against error");
  page.images({"pareto.png"}, {"median PSNR vs median in-between ms, one curve per method"});
  page.images({"quads_vs_tau.png", "psnr_vs_tau.png"});
  page.heading("Table");
  page.table({"mesh", "criterion", "variant", "tau", "tile px", "quads/keyframe", "LOD build ms",
              "in-between ms", "p95 ms", "PSNR dB", "PSNR p5", "SSIM", "SSIM p5", "holes %"},
             table);
  page.heading("Quad meshes of frame " + std::to_string(overlayFrame) + " (five-point)");
  std::vector<std::string> srcs, caps;
  for (const json& o : overlays) {
    srcs.push_back(o["file"].get<std::string>());
    caps.push_back("tau " + tauLabel(num(o["tau"])) + ": " + std::to_string(o["quads"].get<int>()) +
                   " quads (" + std::to_string(o["one_pixel_leaves"].get<int>()) + " one-pixel)");
  }
  page.images(srcs, caps, 384);
  HW_TRY(page.write(opt.outDir + "/index.html"));
  return doc;
}

}  // namespace hw::bench
