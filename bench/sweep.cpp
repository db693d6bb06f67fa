#include "bench/sweep.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <tuple>

#include "report/html_report.h"
#include "core/json_util.h"
#include "report/plot.h"
#include "session/walk.h"
#include "core/file_io.h"
#include "core/machine.h"
#include "core/timer.h"
#include "keyframe/baseline_mesh.h"
#include "keyframe/keyframe_cache.h"
#include "keyframe/overlay.h"

namespace hw::bench {

using namespace report;  // plots, tables and HTML of the studies
using session::WalkOptions;
using session::runWalk;

namespace {

using nlohmann::json;

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
  double tauGradient = 0;  // LodOptions::tauGradient
  std::string variant() const {
    std::string v = keyframe::planarityName(planarity);
    if (mergeStrips) v += "+merge";
    if (tauGradient > 0) {
      char a[32];
      std::snprintf(a, sizeof a, "%g", tauGradient);
      v += std::string("+grad=") + a;
    }
    return v;
  }
  std::string method() const {
    if (mesh == keyframe::MeshMethod::Lod)
      return std::string("lod ") + keyframe::deltaCriterionName(criterion) +
             (planarity == keyframe::Planarity::Stencil && !mergeStrips && tauGradient == 0
                  ? ""
                  : " " + variant());
    return keyframe::meshMethodName(mesh);
  }
};

struct Plan {
  std::vector<double> taus;
  int frames = 0;
  int overlayFrame = 0;
  std::vector<Run> cells;
};

// The sweep's cells in output order: per τ the LOD runs (five-point, per-axis
// max, the three edge-strip variants), then one uniform-tiles cell per τ
// (matched to that τ's five-point quad count), then per-pixel. Every cell is
// independent: a tiles cell finds its tile size itself (see runSweepCells).
Result<Plan> makePlan(const scenes::CameraPath& path, const SweepOptions& opt) {
  Plan p;
  p.taus = opt.taus;
  if (p.taus.empty())
    for (int e = 6; e <= 16; ++e) p.taus.push_back(std::ldexp(1.0, e));
  for (double t : p.taus)
    if (!std::isfinite(t) || t < 0) return makeError("sweep: tau must be finite and >= 0, got " + fmt(t));
  if (!std::isfinite(opt.tauGradient) || opt.tauGradient < 0)
    return makeError("sweep: tau gradient must be finite and >= 0, got " + fmt(opt.tauGradient));
  p.frames = opt.maxFrames > 0 ? std::min(opt.maxFrames, path.frames) : path.frames;
  p.overlayFrame = opt.overlayFrame;
  if (p.overlayFrame < 0) {
    p.overlayFrame = (p.frames / 2) / path.keyframeEvery * path.keyframeEvery;
  } else if (p.overlayFrame >= p.frames) {
    return makeError("sweep: overlay frame " + std::to_string(p.overlayFrame) + " is past the last frame " +
                     std::to_string(p.frames - 1));
  }
  using keyframe::Planarity;
  for (double tau : p.taus) {
    p.cells.push_back({keyframe::MeshMethod::Lod, keyframe::DeltaCriterion::FivePoint, tau, 0});
    if (opt.bothCriteria)
      p.cells.push_back({keyframe::MeshMethod::Lod, keyframe::DeltaCriterion::PerAxisMax, tau, 0});
    if (opt.variants) {  // the edge-strip variants, five-point
      p.cells.push_back({keyframe::MeshMethod::Lod, keyframe::DeltaCriterion::FivePoint, tau, 0,
                         Planarity::RegionLocal, false});
      p.cells.push_back({keyframe::MeshMethod::Lod, keyframe::DeltaCriterion::FivePoint, tau, 0,
                         Planarity::Stencil, true});
      p.cells.push_back({keyframe::MeshMethod::Lod, keyframe::DeltaCriterion::FivePoint, tau, 0,
                         Planarity::RegionLocal, true});
    }
    if (opt.tauGradient > 0)  // the gradient-following tolerance
      p.cells.push_back({keyframe::MeshMethod::Lod, keyframe::DeltaCriterion::FivePoint, tau, 0,
                         Planarity::RegionLocal, true, opt.tauGradient});
  }
  if (opt.baselines) {
    // tileSize 0 = "matched to tau", resolved when the cell runs.
    for (double tau : p.taus)
      p.cells.push_back({keyframe::MeshMethod::UniformTiles, keyframe::DeltaCriterion::FivePoint, tau, 0});
    p.cells.push_back({keyframe::MeshMethod::PerPixel, keyframe::DeltaCriterion::FivePoint, 0, 1});
  }
  return p;
}

// The walk every run starts from (SweepOptions::preset).
WalkOptions sweepBase(const SweepOptions& opt) {
  WalkOptions w = session::presetOptions(opt.preset);
  w.mode = session::FrameMode::Hybrid;
  w.lod.tauParallaxPx = 0;
  w.asyncKeyframes = false;
  return w;
}

// The five-point stencil LOD options of the base pipeline at τ (the row the
// uniform tiles are matched to, and the overlays).
keyframe::LodOptions fivePointLod(const SweepOptions& opt, double tau) {
  keyframe::LodOptions lo = sweepBase(opt).lod;
  lo.tau = tau;
  lo.criterion = keyframe::DeltaCriterion::FivePoint;
  lo.planarity = keyframe::Planarity::Stencil;
  lo.mergeStrips = false;
  lo.tauGradient = 0;
  return lo;
}

// An overlay with a caption band above it.
Image<Rgba8> captioned(const Image<Rgba8>& im, const std::string& text) {
  const int band = captionHeight() + 8;
  Image<Rgba8> out(im.width(), im.height() + band);
  out.fill({255, 255, 255, 255});
  for (int y = 0; y < im.height(); ++y)
    for (int x = 0; x < im.width(); ++x) out(x, y + band) = im(x, y);
  drawCaption(out, text, 4, 4, {20, 20, 20, 255});
  return out;
}

bool isFivePointStencil(const Run& r) {
  return r.mesh == keyframe::MeshMethod::Lod && r.criterion == keyframe::DeltaCriterion::FivePoint &&
         r.planarity == keyframe::Planarity::Stencil && !r.mergeStrips && r.tauGradient == 0;
}

}  // namespace

std::string sweepPipeline(const SweepOptions& opt) {
  if (opt.preset == session::Preset::Paper)
    return "the paper's pipeline (--preset paper: Zheng et al. 1999, every frame warped, holes "
           "from the previous frame); without --preset paper the sweep runs the default pipeline";
  return "the default pipeline (--preset default: misfit leaves split, larger holes drawn by the "
         "geometry renderer) with every frame warped (--mode hybrid), tau in z' units and "
         "keyframes built when needed; each run sets tau, the criterion, planarity and merging. "
         "--preset paper sweeps the paper's pipeline";
}

Result<int> sweepCellCount(const scenes::CameraPath& path, const SweepOptions& opt) {
  auto p = makePlan(path, opt);
  if (!p) return p.error();
  return static_cast<int>(p->cells.size());
}

Result<json> runSweepCells(const scenes::Scene& scene, const std::string& sceneLabel,
                           const scenes::CameraPath& path, const SweepOptions& opt, int first, int last,
                           SweepCellLog* log) {
  auto planR = makePlan(path, opt);
  if (!planR) return planR.error();
  const Plan& plan = *planR;
  HW_CHECK(first >= 0 && first <= last && last <= static_cast<int>(plan.cells.size()));
  const int frames = plan.frames;
  keyframe::RenderOptions ropt;
  ropt.depthMode = opt.depthMode;
  auto renderer = keyframe::GeometryRenderer::create(scene, ropt);
  if (!renderer) return renderer.error();
  std::optional<keyframe::Keyframe> overlayKf;  // rendered when a tiles cell needs it

  Stopwatch all;
  auto progress = [&](int done, int total, const std::string& what) {
    if (!opt.progress) return;
    const double el = all.ms() / 1000.0;
    std::fprintf(stderr, "\rsweep: cell %d/%d (%s) elapsed %.0f s, ETA %.0f s        ", done + 1, total,
                 what.c_str(), el, done > 0 ? el / done * (total - done) : 0.0);
    std::fflush(stderr);
  };

  auto runOne = [&](const Run& r) -> Result<json> {
    WalkOptions w = sweepBase(opt);
    w.lod.tau = r.tau;
    w.lod.criterion = r.criterion;
    w.lod.planarity = r.planarity;
    w.lod.mergeStrips = r.mergeStrips;
    w.lod.tauGradient = r.tauGradient;
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
    const bool lod = r.mesh == keyframe::MeshMethod::Lod;
    json row = {{"method", r.method()},
                {"mesh", keyframe::meshMethodName(r.mesh)},
                {"criterion", lod ? json(keyframe::deltaCriterionName(r.criterion)) : json(nullptr)},
                {"variant", lod ? json(r.variant()) : json(nullptr)},
                {"tau", lod ? json(r.tau) : json(nullptr)},
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

  // Median five-point quads per keyframe at τ: from this call's five-point
  // row if it ran here, else from the keyframes' meshes (the same numbers the
  // walk's summary takes its median of).
  std::map<double, double> fivePointQuads;
  auto quadsAt = [&](double tau) -> Result<double> {
    if (auto it = fivePointQuads.find(tau); it != fivePointQuads.end()) return it->second;
    keyframe::LodBuilder builder;
    const keyframe::LodOptions lo = fivePointLod(opt, tau);
    keyframe::Keyframe kf;
    keyframe::QuadMesh mesh;
    std::vector<double> quads;
    for (int k : keyframe::KeyframeSchedule{frames, path.keyframeEvery, {}}.keyframes()) {
      HW_TRY((*renderer)->renderKeyframe(path.cameraAt(k), kf));
      HW_TRY(builder.build(kf, lo, &mesh));
      quads.push_back(static_cast<double>(mesh.stats.quads));
    }
    return fivePointQuads[tau] = median(quads);
  };

  json rows = json::array();
  std::set<int> tileSizesDone;
  const int total = last - first;
  int resumed = 0, duplicates = 0;  // rows kept; tiles cells not run (tile size already run)
  for (int c = first; c < last; ++c) {
    Run r = plan.cells[static_cast<std::size_t>(c)];
    if (log)
      if (auto it = log->done.find(c); it != log->done.end()) {
        // Run before: what the cell left for the cells after it, as if run here.
        const json& row = it->second;
        if (row.contains("duplicate_tile_size"))
          tileSizesDone.insert(row["duplicate_tile_size"].get<int>());
        else if (row.value("tile_size", json(nullptr)).is_number())
          tileSizesDone.insert(row["tile_size"].get<int>());
        if (isFivePointStencil(r))
          fivePointQuads[r.tau] = numberOrNan(row["quads_per_keyframe"]["median"]);
        rows.push_back(row);
        ++(row.contains("duplicate_tile_size") ? duplicates : resumed);
        continue;
      }
    if (r.mesh == keyframe::MeshMethod::UniformTiles) {
      if (!overlayKf) {
        overlayKf.emplace();
        HW_TRY((*renderer)->renderKeyframe(path.cameraAt(plan.overlayFrame), *overlayKf));
      }
      auto q = quadsAt(r.tau);
      if (!q) return q.error();
      r.tileSize = keyframe::tileSizeForQuadCount(*overlayKf, static_cast<long long>(std::llround(*q)));
      if (!tileSizesDone.insert(r.tileSize).second) {
        // Same tile size as an earlier τ: one row per tile size (the merge drops repeats too).
        rows.push_back({{"cell", c}, {"duplicate_tile_size", r.tileSize}});
        if (log) HW_TRY(log->append(rows.back()));
        ++duplicates;
        continue;
      }
      progress(c - first, total, "uniform tiles " + std::to_string(r.tileSize) + " px");
    } else {
      progress(c - first, total,
               r.mesh == keyframe::MeshMethod::PerPixel ? std::string("per-pixel") : r.method() + " tau " + tauLabel(r.tau));
    }
    auto row = runOne(r);
    if (!row) return row.error();
    if (r.mesh == keyframe::MeshMethod::UniformTiles) (*row)["matched_to_tau"] = r.tau;
    if (isFivePointStencil(r))
      fivePointQuads[r.tau] = numberOrNan((*row)["quads_per_keyframe"]["median"]);
    (*row)["cell"] = c;
    rows.push_back(*row);
    if (log) HW_TRY(log->append(rows.back()));
  }
  if (opt.progress) {
    const std::string kept =
        resumed > 0 ? " (and " + std::to_string(resumed) + " kept from the interrupted run)" : "";
    const std::string dups =
        duplicates > 0 ? "; " + std::to_string(duplicates) +
                             (duplicates == 1 ? " uniform-tiles cell" : " uniform-tiles cells") +
                             " not run: their tile size ran at an earlier tau"
                       : "";
    const int ran = total - resumed - duplicates;
    std::fprintf(stderr, "\rsweep: %d run%s in %.0f s%s%s%40s\n", ran, ran == 1 ? "" : "s",
                 all.ms() / 1000.0, kept.c_str(), dups.c_str(), "");
  }
  return rows;
}

Result<json> runSweep(const scenes::Scene& scene, const std::string& sceneLabel,
                      const scenes::CameraPath& path, const SweepOptions& opt) {
  auto n = sweepCellCount(path, opt);
  if (!n) return n.error();
  if (opt.outDir.empty()) return makeError("sweep: an output directory is required");
  HW_TRY(ensureWritableDir(opt.outDir));
  auto plan = makePlan(path, opt);
  if (!plan) return plan.error();
  // The header: what identifies the sweep's cells (a resumed run must have
  // the same ones).
  json cells = json::array();
  for (const Run& r : plan->cells)
    cells.push_back({r.method(), r.tau});
  const json header = {{"sweep_row_log", 1}, {"scene", sceneLabel}, {"frames", plan->frames},
                       {"depth", depthModeName(opt.depthMode)},
                       {"preset", session::presetName(opt.preset)}, {"cells", cells}};
  const std::string logPath = opt.outDir + "/" + kSweepRowLog;
  SweepCellLog log;
  if (opt.resume) {
    auto text = readFile(logPath);
    if (!text)
      return makeError("--resume: " + logPath + " not found: there is no interrupted sweep in " +
                       opt.outDir + " to resume");
    std::size_t pos = 0;
    bool first = true;
    while (pos < text->size()) {
      std::size_t end = text->find('\n', pos);
      if (end == std::string::npos) break;  // a line cut by the interruption: run that cell again
      const json j = json::parse(text->substr(pos, end - pos), nullptr, false);
      pos = end + 1;
      if (first) {
        if (j != header)
          return makeError("--resume: " + logPath + " was written by a different sweep (scene, "
                           "frames, depth mode, preset or cells differ); run without --resume to start afresh");
        first = false;
      } else if (!j.is_discarded() && j.contains("cell") && j["cell"].is_number_integer()) {
        log.done[j["cell"].get<int>()] = j;
      }
    }
    if (first)
      return makeError("--resume: " + logPath + " has no header line; run without --resume");
    if (opt.progress)
      std::fprintf(stderr, "sweep: resuming, %zu of %d runs kept\n", log.done.size(), *n);
  }
  // A fresh log (or the kept rows rewritten, dropping a cut line).
  std::string start = header.dump() + "\n";
  for (const auto& [c, row] : log.done) start += row.dump() + "\n";
  HW_TRY(writeFileAtomic(logPath, start));
  log.append = [&logPath](const json& row) -> Status {
    std::FILE* f = std::fopen(logPath.c_str(), "ab");
    if (!f) return makeError("cannot append to " + logPath + ": " + std::strerror(errno));
    const std::string line = row.dump() + "\n";
    const bool ok = std::fwrite(line.data(), 1, line.size(), f) == line.size();
    if (std::fclose(f) != 0 || !ok) return makeError("cannot append to " + logPath);
    return {};
  };
  auto rows = runSweepCells(scene, sceneLabel, path, opt, 0, *n, &log);
  if (!rows) return rows.error();
  auto res = finishSweep(scene, sceneLabel, path, opt, *rows);
  if (res) std::filesystem::remove(logPath);
  return res;
}

Result<json> finishSweep(const scenes::Scene& scene, const std::string& sceneLabel,
                         const scenes::CameraPath& path, const SweepOptions& opt, const json& cellRows) {
  if (opt.outDir.empty()) return makeError("sweep: an output directory is required");
  auto planR = makePlan(path, opt);
  if (!planR) return planR.error();
  const Plan& plan = *planR;
  const std::vector<double>& taus = plan.taus;
  const int frames = plan.frames;
  const int overlayFrame = plan.overlayFrame;
  if (!cellRows.is_array() || cellRows.size() != plan.cells.size())
    return makeError("sweep: merge got " + std::to_string(cellRows.size()) + " cell results, expected " +
                     std::to_string(plan.cells.size()));
  // One row per cell in cell order; uniform tiles once per tile size (the
  // first τ that asks for it), as a single in-process run writes them.
  json rows = json::array();
  std::set<int> tileSizesDone;
  for (std::size_t c = 0; c < cellRows.size(); ++c) {
    json row = cellRows[c];
    if (!row.is_object() || !row.contains("cell") || row["cell"] != c)
      return makeError("sweep: merge: cell result " + std::to_string(c) + " is missing or out of order");
    if (row.contains("duplicate_tile_size")) continue;
    if (row["mesh"] == "uniform-tiles" && !tileSizesDone.insert(row["tile_size"].get<int>()).second) continue;
    row.erase("cell");
    rows.push_back(row);
  }
  HW_TRY(ensureWritableDir(opt.outDir));
  HW_TRY(ensureWritableDir(opt.outDir + "/overlays"));
  keyframe::RenderOptions ropt;
  ropt.depthMode = opt.depthMode;
  auto renderer = keyframe::GeometryRenderer::create(scene, ropt);
  if (!renderer) return renderer.error();
  keyframe::Keyframe overlayKf;
  HW_TRY((*renderer)->renderKeyframe(path.cameraAt(overlayFrame), overlayKf));

  // Overlays, one per τ (five-point), on the same keyframe.
  json overlays = json::array();
  keyframe::LodBuilder builder;
  for (double tau : taus) {
    keyframe::QuadMesh mesh;
    HW_TRY(builder.build(overlayKf, fivePointLod(opt, tau), &mesh));
    const std::string name = "overlays/overlay_tau_" + fmt(tau, 0) + ".png";
    HW_TRY(writePng(opt.outDir + "/" + name,
                    captioned(keyframe::drawQuadOverlay(overlayKf.colour, mesh),
                              "tau " + tauLabel(tau) + ": " + std::to_string(mesh.stats.quads) +
                                  " quads, frame " + std::to_string(overlayFrame))));
    overlays.push_back({{"tau", tau}, {"file", name}, {"quads", mesh.stats.quads},
                        {"one_pixel_leaves", mesh.stats.onePixelLeaves}});
  }

  // Plots.
  std::vector<std::string> methods;
  for (const json& r : rows) {
    const std::string m = r["method"].get<std::string>();
    if (std::find(methods.begin(), methods.end(), m) == methods.end()) methods.push_back(m);
  }
  // One series per method; tauLabels: each point labelled with its τ (a
  // uniform-tiles point with the τ whose quad count it matches).
  auto seriesBy = [&](const char* xKey, const char* xStat, const char* yKey, const char* yStat,
                      bool lodOnly, bool tauLabels = false) {
    std::vector<Series> out;
    for (const std::string& m : methods) {
      Series s;
      s.label = m;
      std::vector<std::tuple<double, double, std::string>> pts;
      for (const json& r : rows) {
        if (r["method"] != m) continue;
        if (lodOnly && r["mesh"] != "lod") continue;
        const double x = xStat ? numberOrNan(r[xKey][xStat]) : numberOrNan(r[xKey]);
        const double y = yStat ? numberOrNan(r[yKey][yStat]) : numberOrNan(r[yKey]);
        const double tau = r["tau"].is_number() ? r["tau"].get<double>()
                                                : numberOrNan(r.value("matched_to_tau", json(nullptr)));
        pts.emplace_back(x, y, std::isfinite(tau) ? tauLabel(tau) : std::string());
      }
      if (pts.empty()) continue;
      std::sort(pts.begin(), pts.end());
      for (const auto& [x, y, label] : pts) {
        s.x.push_back(x);
        s.y.push_back(y);
        if (tauLabels) s.pointLabels.push_back(label);
      }
      out.push_back(s);
    }
    return out;
  };
  PlotOptions po;
  po.title = "Run time against error: " + sceneLabel + " (" + std::to_string(path.width) + "x" +
             std::to_string(path.height) + ", " + session::presetName(opt.preset) + " pipeline)";
  po.xLabel = "in-between frame ms (median, log)";
  po.yLabel = "PSNR dB (median)";
  po.logX = true;
  po.width = 1000;
  po.height = 600;
  std::vector<Series> pareto = seriesBy("in_between_ms", "median", "psnr", "median", false, true);
  // Outliers (a run more than 3x slower than every faster one, e.g. one quad
  // per pixel) would squeeze the others into a corner: the axis breaks
  // before them and they sit at its right end, labelled with their time.
  std::vector<double> xs;
  for (const Series& s : pareto)
    for (double x : s.x)
      if (std::isfinite(x) && x > 0) xs.push_back(x);
  std::sort(xs.begin(), xs.end());
  std::size_t core = xs.size();
  while (core >= 3 && xs[core - 1] > 3 * xs[core - 2]) --core;
  if (core < xs.size()) {
    const double cut = xs[core - 1], edge = cut * 1.5;
    po.xMax = edge * 1.15;
    po.xLabel = "in-between frame ms (median, log); runs slower than " + fmt(cut * 1.25, 0) +
                " ms at the right end";
    for (Series& s : pareto) {
      bool off = false;
      for (std::size_t k = 0; k < s.x.size(); ++k)
        if (s.x[k] > cut) {
          if (s.pointLabels.size() != s.x.size()) s.pointLabels.assign(s.x.size(), "");
          s.pointLabels[k] = fmt(s.x[k], 0) + " ms";
          s.x[k] = edge;
          off = true;
        }
      if (off) s.label += " (off scale, right end)";
    }
  }
  HW_TRY(writePlot(opt.outDir + "/pareto.png", pareto, po));
  po.xMax.reset();
  po.width = 800;
  po.height = 500;
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
              {"preset", session::presetName(opt.preset)},
              {"pipeline", sweepPipeline(opt)},
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
    const std::string tau = r["tau"].is_number() ? fmt(numberOrNan(r["tau"]), 0) : "";
    const std::string tile = r["tile_size"].is_number() ? std::to_string(r["tile_size"].get<int>()) : "";
    const std::vector<std::string> cells = {
        r["mesh"].get<std::string>(),
        crit,
        variant,
        tau,
        tile,
        fmt(numberOrNan(r["quads_per_keyframe"]["median"]), 0),
        fmt(numberOrNan(r["lod_build_ms"]["median"])),
        fmt(numberOrNan(r["in_between_ms"]["median"])),
        fmt(numberOrNan(r["in_between_ms"]["p95"])),
        fmt(numberOrNan(r["psnr"]["median"])),
        fmt(numberOrNan(r["psnr"]["p5"])),
        fmt(numberOrNan(r["ssim"]["median"]), 4),
        fmt(numberOrNan(r["ssim"]["p5"]), 4),
        fmt(100 * numberOrNan(r["holes_before_fallback"]["median"]), 3)};
    table.push_back(cells);
    for (std::size_t i = 0; i < cells.size(); ++i) csv += cells[i] + (i + 1 < cells.size() ? "," : "\n");
  }
  HW_TRY(writeFileAtomic(opt.outDir + "/sweep.csv", csv));

  HtmlReport page("hybridwalk sweep: " + sceneLabel);
  page.paragraph("Scene " + sceneLabel + " (" + std::to_string(scene.triangleCount()) +
                 " triangles), " + std::to_string(path.width) + "x" + std::to_string(path.height) +
                 ", " + std::to_string(frames) + " frames, a keyframe every " +
                 std::to_string(path.keyframeEvery) + ", depth " + depthModeName(opt.depthMode) +
                 ". Every run is " + sweepPipeline(opt) +
                 ". Every row is the same walk; quality is PSNR/SSIM of the in-between frames "
                 "against the geometry renderer at the same camera. Machine: " +
                 doc["machine"]["cpu"].get<std::string>() + ", " + opt.glRenderer +
                 ". Times are wall-clock on a shared VM: they move by tens of percent between "
                 "runs.");
  page.heading("Run time against error");
  page.images({"pareto.png"}, {"median PSNR vs median in-between ms, one curve per method; each point labelled with its tau (uniform tiles: the tau whose quad count they match) where the label has room; a run far slower than the rest sits at the right end of a broken axis, labelled with its time"});
  page.images({"quads_vs_tau.png", "psnr_vs_tau.png"});
  page.heading("Table: " + std::to_string(rows.size()) + " runs");
  page.table({"mesh", "criterion", "variant", "tau", "tile px", "quads/keyframe", "LOD build ms",
              "in-between ms", "p95 ms", "PSNR dB", "PSNR p5", "SSIM", "SSIM p5", "holes %"},
             table);
  page.heading("Quad meshes of frame " + std::to_string(overlayFrame) + " (five-point)");
  std::vector<std::string> srcs, caps;
  for (const json& o : overlays) {
    srcs.push_back(o["file"].get<std::string>());
    caps.push_back("tau " + tauLabel(numberOrNan(o["tau"])) + ": " +
                   std::to_string(o["quads"].get<int>()) + " quads (" +
                   std::to_string(o["one_pixel_leaves"].get<int>()) + " one-pixel)");
  }
  page.images(srcs, caps, 384);
  HW_TRY(page.write(opt.outDir + "/index.html"));
  // Last: a sweep.json is there only when everything it describes is.
  HW_TRY(writeFileAtomic(opt.outDir + "/sweep.json", doc.dump(1)));
  return doc;
}

}  // namespace hw::bench
