#include "bench/bench_suite.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "report/html_report.h"
#include "core/json_util.h"
#include "report/plot.h"
#include "bench/skip_study.h"
#include "session/frame_engine.h"
#include "session/walk.h"
#include "core/file_io.h"
#include "core/machine.h"
#include "core/timer.h"
#include "keyframe/geometry_renderer.h"
#include "scenes/procedural.h"

namespace hw::bench {

using namespace report;  // plots, tables and HTML of the studies
using session::WalkOptions;
using session::runWalk;

namespace {

using nlohmann::json;

std::string sizeLabel(std::size_t n) {
  if (n >= 1000000 && n % 1000000 == 0) return std::to_string(n / 1000000) + "M";
  if (n >= 1000 && n % 1000 == 0) return std::to_string(n / 1000) + "k";
  return std::to_string(n);
}

std::string tauLabel(double tau) {
  const double l = std::log2(tau);
  if (tau > 0 && std::abs(l - std::round(l)) < 1e-9) return "2^" + std::to_string(int(std::lround(l)));
  return fmt(tau, 0);
}

scenes::Scene makeScene(const std::string& name, std::size_t tris) {
  return name == "indoor" ? scenes::makeIndoorScene(tris) : scenes::makeOutdoorScene(tris);
}
scenes::CameraPath pathFor(const std::string& name) {
  return name == "indoor" ? scenes::defaultIndoorPath() : scenes::defaultOutdoorPath();
}

void say(bool on, const char* fmtStr, const std::string& a) {
  if (on) {
    std::fprintf(stderr, fmtStr, a.c_str());
    std::fflush(stderr);
  }
}

}  // namespace

Result<json> runBenchSuite(const BenchOptions& opt) {
  for (const std::string& p : opt.parts)
    if (p != "complexity" && p != "trace" && p != "spacing" && p != "skips" && p != "scenes" &&
        p != "disocclusion" && p != "floor")
      return makeError("bench: unknown part '" + p +
                       "': expected complexity, trace, spacing, skips, scenes, disocclusion or "
                       "floor");
  auto want = [&](const char* part) {
    return opt.parts.empty() || std::find(opt.parts.begin(), opt.parts.end(), part) != opt.parts.end();
  };
  HW_TRY(ensureWritableDir(opt.outDir));
  Stopwatch all;
  const json machine = machineInfo(opt.glRenderer, opt.glVersion);

  json complexity = json::array();
  std::string csvA = "scene,triangles,tau,geometry_median_ms,geometry_p95_ms,in_between_median_ms,"
                     "in_between_p95_ms,reference_median_ms,psnr_median,quads_per_keyframe\n";
  if (want("complexity")) {
    // (a) Complexity.
    for (const std::string name : {"indoor", "outdoor"}) {
      for (std::size_t target : opt.sizes) {
        say(opt.progress, "bench: complexity %s\n", name + " " + sizeLabel(target));
        const scenes::Scene scene = makeScene(name, target);
        const scenes::CameraPath path = pathFor(name);
        std::vector<double> ms;
        {
          auto r = keyframe::GeometryRenderer::create(scene);
          if (!r) return r.error();
          Image<Rgba8> img;
          for (int k = 0; k < opt.renderFrames; ++k) {
            keyframe::RenderStats st;
            const int f = k * (path.frames - 1) / std::max(1, opt.renderFrames - 1);
            HW_TRY((*r)->renderColour(path.cameraAt(f), img, &st));
            if (k > 0) ms.push_back(st.drawMs + st.readbackMs);
          }
        }
        for (double tau : opt.taus) {
          WalkOptions w;
          w.lod.tau = tau;
          w.maxFrames = opt.walkFrames;
          w.progress = false;
          w.strips = 0;
          w.glRenderer = opt.glRenderer;
          w.glVersion = opt.glVersion;
          auto res = runWalk(scene, name, path, w);
          if (!res) return res.error();
          const json& s = res->report["summary"];
          json row = {{"scene", name},
                      {"target_triangles", target},
                      {"triangles", scene.triangleCount()},
                      {"tau", tau},
                      {"geometry_ms", {{"median", median(ms)}, {"p95", percentile(ms, 95)}}},
                      {"in_between_ms", s["in_between_ms"]},
                      {"reference_ms", s["reference_ms"]},
                      {"psnr", s["psnr"]},
                      {"quads_per_keyframe", s["quads_per_keyframe"]},
                      {"speedup", s["speedup_reference_over_in_between"]},
                      // What the table shows: its geometry column over its in-between column.
                      {"speedup_geometry_over_in_between",
                       finiteOrNull(median(ms) / numberOrNan(s["in_between_ms"]["median"]))}};
          complexity.push_back(row);
          csvA += name + "," + std::to_string(scene.triangleCount()) + "," + fmt(tau, 0) + "," +
                  fmt(median(ms)) + "," + fmt(percentile(ms, 95)) + "," +
                  fmt(numberOrNan(s["in_between_ms"]["median"])) + "," +
                  fmt(numberOrNan(s["in_between_ms"]["p95"])) + "," +
                  fmt(numberOrNan(s["reference_ms"]["median"])) + "," +
                  fmt(numberOrNan(s["psnr"]["median"])) + "," +
                  fmt(numberOrNan(s["quads_per_keyframe"]["median"]), 0) + "\n";
        }
      }
    }
    {
      std::vector<Series> series;
      for (const std::string name : {"indoor", "outdoor"}) {
        Series g;
        g.label = "geometry, " + name;
        for (const json& r : complexity)
          if (r["scene"] == name && r["tau"].get<double>() == opt.taus.front()) {
            g.x.push_back(numberOrNan(r["triangles"]));
            g.y.push_back(numberOrNan(r["geometry_ms"]["median"]));
          }
        series.push_back(g);
        for (double tau : opt.taus) {
          Series h;
          h.label = "in-between, " + name + ", tau " + tauLabel(tau);
          for (const json& r : complexity)
            if (r["scene"] == name && r["tau"].get<double>() == tau) {
              h.x.push_back(numberOrNan(r["triangles"]));
              h.y.push_back(numberOrNan(r["in_between_ms"]["median"]));
            }
          series.push_back(h);
        }
      }
      PlotOptions po;
      po.title = "Frame time vs scene complexity (512x512, median)";
      po.xLabel = "triangles";
      po.yLabel = "ms per frame";
      po.logX = po.logY = true;
      po.width = 900;
      po.height = 560;
      HW_TRY(writePlot(opt.outDir + "/complexity.png", series, po));
    }

}

  json trace;
  std::string csvB = "frame,is_keyframe,total_ms,reference_ms,warp_a_ms,warp_b_ms,compose_ms,psnr\n";
  json spacing = json::array();
  std::string csvC = "keyframe_every,keyframes,psnr_median,psnr_p5,ssim_median,holes_before_median,"
                     "in_between_ms_median\n";
  if (want("trace") || want("spacing")) {
    // (b) Walkthrough trace and (c) keyframe spacing, on the trace scene at 1M.
    const std::size_t traceTris = opt.traceTriangles;
    say(opt.progress, "bench: walkthrough trace %s\n", opt.traceScene + " " + sizeLabel(traceTris));
    const scenes::Scene traceScene = makeScene(opt.traceScene, traceTris);
    const scenes::CameraPath tracePath = pathFor(opt.traceScene);
    {
      WalkOptions w;
      w.progress = opt.progress;
      w.strips = 0;
      w.glRenderer = opt.glRenderer;
      w.glVersion = opt.glVersion;
      auto res = runWalk(traceScene, opt.traceScene, tracePath, w);
      if (!res) return res.error();
      Series total, keyframes, reference, warpA, warpB, comp;
      total.label = "in-between total";
      keyframes.label = "keyframe frames (render + LOD + upload)";
      keyframes.lines = false;
      reference.label = "geometry reference";
      warpA.label = "warp A (draw + readback)";
      warpB.label = "warp B";
      comp.label = "compose";
      for (const json& f : res->report["frames"]) {
        const double i = numberOrNan(f["index"]);
        const bool isKey = f["is_keyframe"].get<bool>();
        (isKey ? keyframes : total).x.push_back(i);
        (isKey ? keyframes : total).y.push_back(numberOrNan(f["ms"]["total"]));
        reference.x.push_back(i);
        reference.y.push_back(numberOrNan(f["reference_ms"]));
        if (!isKey) {
          warpA.x.push_back(i);
          warpA.y.push_back(numberOrNan(f["ms"]["warp_a"]));
          warpB.x.push_back(i);
          warpB.y.push_back(numberOrNan(f["ms"]["warp_b"]));
          comp.x.push_back(i);
          comp.y.push_back(numberOrNan(f["ms"]["compose"]));
        }
        csvB += std::to_string(int(i)) + "," + (isKey ? "1" : "0") + "," +
                fmt(numberOrNan(f["ms"]["total"]), 3) + "," +
                fmt(numberOrNan(f["reference_ms"]), 3) + "," +
                (isKey ? "" : fmt(numberOrNan(f["ms"]["warp_a"]), 3)) + "," +
                (isKey ? "" : fmt(numberOrNan(f["ms"]["warp_b"]), 3)) + "," +
                (isKey ? "" : fmt(numberOrNan(f["ms"]["compose"]), 3)) + "," +
                fmt(numberOrNan(f["psnr"])) + "\n";
      }
      PlotOptions po;
      po.title = "Walkthrough trace: " + opt.traceScene + " " + sizeLabel(traceTris) + ", tau 2^11";
      po.xLabel = "frame";
      po.yLabel = "ms";
      po.logY = true;
      po.width = 1000;
      po.height = 520;
      HW_TRY(writePlot(opt.outDir + "/trace.png", {reference, keyframes, total, warpA, warpB, comp}, po));
      trace = res->report["summary"];
    }

    say(opt.progress, "bench: keyframe spacing %s\n", opt.traceScene);
    Series psnrMed, psnrP5;
    psnrMed.label = "PSNR median";
    psnrP5.label = "PSNR 5th percentile";
    for (int every : opt.keyframeSpacings) {
      scenes::CameraPath p = tracePath;
      p.keyframeEvery = every;
      WalkOptions w;
      w.progress = false;
      w.strips = 0;
      w.glRenderer = opt.glRenderer;
      w.glVersion = opt.glVersion;
      auto res = runWalk(traceScene, opt.traceScene, p, w);
      if (!res) return res.error();
      const json& s = res->report["summary"];
      spacing.push_back({{"keyframe_every", every}, {"keyframes", s["keyframes"]}, {"psnr", s["psnr"]},
                         {"ssim", s["ssim"]}, {"holes_before_fallback", s["holes_before_fallback"]},
                         {"in_between_ms", s["in_between_ms"]}});
      psnrMed.x.push_back(every);
      psnrMed.y.push_back(numberOrNan(s["psnr"]["median"]));
      psnrP5.x.push_back(every);
      psnrP5.y.push_back(numberOrNan(s["psnr"]["p5"]));
      csvC += std::to_string(every) + "," + std::to_string(s["keyframes"].get<int>()) + "," +
              fmt(numberOrNan(s["psnr"]["median"])) + "," + fmt(numberOrNan(s["psnr"]["p5"])) +
              "," + fmt(numberOrNan(s["ssim"]["median"]), 4) + "," +
              fmt(numberOrNan(s["holes_before_fallback"]["median"]), 5) + "," +
              fmt(numberOrNan(s["in_between_ms"]["median"])) + "\n";
    }
    {
      PlotOptions po;
      po.title = "Quality vs keyframe spacing: " + opt.traceScene + " " + sizeLabel(traceTris) + ", tau 2^11";
      po.xLabel = "keyframe_every (frames)";
      po.yLabel = "in-between PSNR (dB)";
      HW_TRY(writePlot(opt.outDir + "/spacing.png", {psnrMed, psnrP5}, po));
    }

}

  // (d) Skips: each on and off.
  json skips;
  if (want("skips")) {
    SkipStudyOptions so = opt.skips;
    so.progress = opt.progress;
    so.glRenderer = opt.glRenderer;
    so.glVersion = opt.glVersion;
    auto st = runSkipStudy(so);
    if (!st) return st.error();
    skips = std::move(*st);
  }

  // (e) Scenes: the defaults against the paper's settings, scene by scene.
  json scenesTable;
  if (want("scenes")) {
    SceneTableOptions so = opt.sceneTable;
    so.outDir = opt.outDir;
    so.progress = opt.progress;
    so.glRenderer = opt.glRenderer;
    so.glVersion = opt.glVersion;
    auto st = runSceneTable(so);
    if (!st) return st.error();
    scenesTable = std::move(*st);
  }

  // (f) Disocclusion: a third keyframe, depth peeling's bound, the hole rectangles.
  json disocclusion;
  if (want("disocclusion")) {
    DisocclusionOptions d = opt.disocclusion;
    d.progress = opt.progress;
    auto st = runDisocclusionStudy(d);
    if (!st) return st.error();
    disocclusion = std::move(*st);
  }

  // (g) The fill floor: one full-screen textured quad as one layer and as two,
  // at three resolutions (session/frame_engine.h measureFloor).
  json floor = json::array();
  if (want("floor")) {
    const scenes::Scene scene = makeScene("indoor", 20000);
    auto engine = session::FrameEngine::create(scene, session::WalkOptions{}, false);
    if (!engine) return engine.error();
    for (int res : {256, 512, 1024}) {
      scenes::CameraPath path = pathFor("indoor");
      path.width = path.height = res;
      session::FloorTimes ft;
      HW_TRY((*engine)->measureFloor(path.cameraAt(0), 40, &ft));
      floor.push_back({{"resolution", res},
                       {"one_layer_ms", ft.oneLayerMs},
                       {"two_layers_ms", ft.twoLayersMs},
                       {"draws", ft.reps}});
      std::printf("floor %4d x %-4d  one layer %6.2f ms   two layers %6.2f ms   (median of %d)\n",
                  res, res, ft.oneLayerMs, ft.twoLayersMs, ft.reps);
    }
  }

  json doc = {{"resolution", {512, 512}},
              {"complexity", complexity},
              {"trace", trace},
              {"spacing", spacing},
              {"skips", skips},
              {"scenes", scenesTable},
              {"disocclusion", disocclusion},
              {"floor", floor},
              {"parts", opt.parts},
              {"machine", machine},
              {"elapsed_s", all.ms() / 1000.0},
              {"note", "wall-clock ms on a shared 2-vCPU VM with llvmpipe; figures move by tens of "
                       "percent between runs (NOTES-GL.md); ratios within one run are steadier"}};
  HW_TRY(writeFileAtomic(opt.outDir + "/bench.json", doc.dump(1)));
  if (want("complexity")) HW_TRY(writeFileAtomic(opt.outDir + "/complexity.csv", csvA));
  if (want("trace") || want("spacing")) {
    HW_TRY(writeFileAtomic(opt.outDir + "/trace.csv", csvB));
    HW_TRY(writeFileAtomic(opt.outDir + "/spacing.csv", csvC));
  }
  if (want("skips")) HW_TRY(writeFileAtomic(opt.outDir + "/skips.csv", skipStudyCsv(skips)));
  if (want("disocclusion"))
    HW_TRY(writeFileAtomic(opt.outDir + "/disocclusion.csv", disocclusionCsv(disocclusion)));

  HtmlReport page("hybridwalk frame-timing benchmark");
  page.paragraph("Machine: " + machine["cpu"].get<std::string>() + ", " +
                 std::to_string(machine["cores"].get<unsigned>()) + " cores, " + opt.glRenderer +
                 " (" + opt.glVersion + "), LP_NUM_THREADS=" + machine["lp_num_threads"].get<std::string>() +
                 ", build " + machine["build_type"].get<std::string>() + ", commit " +
                 machine["git_commit"].get<std::string>() + ". 512x512. " + doc["note"].get<std::string>() + ".");
  if (want("complexity")) {
  page.heading("(a) Scene complexity");
  page.paragraph("Geometry renderer (VBOs, frustum culling, material-sorted) against the in-between "
                 "frame (two warped layers + composition), medians over the built-in paths; the "
                 "speedup is the geometry column over the in-between column.");
  page.images({"complexity.png"});
  std::vector<std::vector<std::string>> rowsA;
  for (const json& r : complexity)
    rowsA.push_back(
        {r["scene"].get<std::string>(), std::to_string(r["triangles"].get<std::size_t>()),
         tauLabel(numberOrNan(r["tau"])), fmt(numberOrNan(r["geometry_ms"]["median"])),
         fmt(numberOrNan(r["in_between_ms"]["median"])),
         fmt(numberOrNan(r["in_between_ms"]["p95"])),
         fmt(numberOrNan(r["speedup_geometry_over_in_between"]), 1),
         fmt(numberOrNan(r["psnr"]["median"])),
         fmt(numberOrNan(r["quads_per_keyframe"]["median"]), 0)});
  page.table({"scene", "triangles", "tau", "geometry ms", "in-between ms", "in-between p95",
              "speedup = geometry ms / in-between ms", "PSNR dB", "quads/keyframe"},
             rowsA);
  }
  if (want("trace") || want("spacing")) {
  page.heading("(b) Walkthrough trace");
  page.images({"trace.png"});
  page.paragraph("In-between ms median " + fmt(numberOrNan(trace["in_between_ms"]["median"])) +
                 ", p95 " + fmt(numberOrNan(trace["in_between_ms"]["p95"])) + "; geometry median " +
                 fmt(numberOrNan(trace["reference_ms"]["median"])) + ", p95 " +
                 fmt(numberOrNan(trace["reference_ms"]["p95"])) + "; keyframe build median " +
                 fmt(numberOrNan(trace["keyframe_build_ms"]["median"])) + " ms.");
  page.heading("(c) Keyframe spacing");
  page.images({"spacing.png"});
  std::vector<std::vector<std::string>> rowsC;
  for (const json& r : spacing)
    rowsC.push_back({std::to_string(r["keyframe_every"].get<int>()),
                     std::to_string(r["keyframes"].get<int>()),
                     fmt(numberOrNan(r["psnr"]["median"])), fmt(numberOrNan(r["psnr"]["p5"])),
                     fmt(numberOrNan(r["ssim"]["median"]), 4),
                     fmt(100 * numberOrNan(r["holes_before_fallback"]["median"]), 3),
                     fmt(numberOrNan(r["in_between_ms"]["median"]))});
  page.table({"keyframe_every", "keyframes", "PSNR median", "PSNR p5", "SSIM", "holes %", "in-between ms"},
             rowsC);
  }
  if (want("skips")) {
    page.heading("(d) Skips: each stage only when the frame needs it");
    page.paragraph("The same walk (tau 2^11, region-local planarity, strip merging, " +
                   std::to_string(opt.skips.frames) + " frames) with each skip on and off; " +
                   "'fired' = in-between frames where the skip applied. In-between ms and PSNR "
                   "medians (PSNR 5th percentile in brackets); large-quad PSNR = over the pixels "
                   "drawn from leaves larger than one subdivision cell. Subdivision rows: on = "
                   "that mode, off = none. 'off − on' is what the skip saves; 'noise' is the "
                   "spread (max − min) of the in-between ms median over " +
                   std::to_string(std::max(2, opt.skips.repeats)) +
                   " runs of the same default walk, and a saving no larger than it is marked "
                   "'within noise', not a gain. Frames, hence PSNR, do not vary between runs.");
    std::vector<std::vector<std::string>> rowsD;
    for (const json& r : skips["rows"])
      rowsD.push_back({r["scene"].get<std::string>(), r["skip"].get<std::string>(),
                       r["default"].get<std::string>(),
                       r.contains("fired_frames")
                           ? std::to_string(r["fired_frames"].get<int>()) + "/" +
                                 std::to_string(r["in_between_frames"].get<int>())
                           : "",
                       fmt(numberOrNan(r["on"]["in_between_ms_median"])),
                       fmt(numberOrNan(r["off"]["in_between_ms_median"])),
                       fmt(numberOrNan(r.value("ms_difference", json(nullptr)))) +
                           (r.value("within_noise", json(nullptr)) == json(true)
                                ? " (within noise)"
                                : ""),
                       fmt(numberOrNan(r.value("ms_noise", json(nullptr)))),
                       fmt(numberOrNan(r["on"]["psnr_median"])) + " (" +
                           fmt(numberOrNan(r["on"]["psnr_p5"])) + ")",
                       fmt(numberOrNan(r["off"]["psnr_median"])) + " (" +
                           fmt(numberOrNan(r["off"]["psnr_p5"])) + ")",
                       fmt(numberOrNan(r["on"]["psnr_large_quads_median"])) + " (" +
                           fmt(numberOrNan(r["on"]["psnr_large_quads_p5"])) + ")",
                       fmt(numberOrNan(r["off"]["psnr_large_quads_median"])) + " (" +
                           fmt(numberOrNan(r["off"]["psnr_large_quads_p5"])) + ")"});
    page.table({"scene", "skip", "default", "fired", "ms on", "ms off", "off − on ms", "noise ms",
                "PSNR on", "PSNR off",
                "large-quad PSNR on", "large-quad PSNR off"},
               rowsD);
    for (const json& u : skips["unavailable"])
      page.paragraph("Not measured: " + u["scene"].get<std::string>() + " (" +
                     u["reason"].get<std::string>() + ")");
  }
  if (want("scenes")) {
    page.heading("(e) Scenes: the defaults against the paper's settings");
    page.paragraph("Each scene walked with the defaults and with --preset paper in this run. "
                   "frame/geometry: frame_ms over the geometry frame's ms at the same camera; "
                   "PSNR over warped frames only (dB). scenes.csv has every figure.");
    std::vector<std::vector<std::string>> rowsE;
    for (const json& r : scenesTable["rows"]) {
      if (r.contains("error")) {
        rowsE.push_back({r["scene"].get<std::string>(), "", "not run: " + r["error"].get<std::string>(),
                         "", "", "", "", ""});
        continue;
      }
      for (const char* preset : {"default", "paper"}) {
        const json& p = r[preset];
        rowsE.push_back({r["scene"].get<std::string>(), std::to_string(r["triangles"].get<std::size_t>()),
                         preset,
                         fmt(100 * numberOrNan(p["geometry_share"]), 0) + " / " +
                             fmt(100 * numberOrNan(p["warp_share"]), 0) + " / " +
                             fmt(100 * numberOrNan(p["keyframe_share"]), 0),
                         fmt(numberOrNan(p["frame_over_reference_median"])),
                         fmt(numberOrNan(p["frame_over_reference_p95"])),
                         fmt(numberOrNan(p["psnr_median"])), fmt(numberOrNan(p["psnr_p5"]))});
      }
    }
    page.table({"scene", "triangles", "preset", "% frames geometry / warp / keyframe",
                "frame/geometry median", "frame/geometry p95", "PSNR median", "PSNR p5"},
               rowsE);
  }
  if (want("disocclusion")) {
    page.heading("(f) Disocclusion: what a third keyframe or depth peeling could add");
    page.paragraph("In-between frames drawn as the default preset draws them in hybrid mode, holes "
                   "copied from the previous frame; then each frame's holes filled from the "
                   "keyframe before the pair, from the one after it, by the geometry renderer's "
                   "hole rectangles, exact where a keyframe of the pair has the surface in view "
                   "(depth peeling's bound), and exact everywhere. PSNR median (p5) in dB; "
                   "filled: share of hole pixels; holes: share outside both keyframes' views / "
                   "inside one / sky. disocclusion.csv has every frame.");
    std::vector<std::vector<std::string>> rowsF;
    auto cell = [](const json& v) {
      return fmt(numberOrNan(v["psnr"]["median"])) + " (" + fmt(numberOrNan(v["psnr"]["p5"])) +
             ")" + (v["filled_share"].is_number() ? ", " + fmt(100 * v["filled_share"].get<double>(), 0) + " %" : "") +
             (v["ms_median"].is_number() ? ", " + fmt(v["ms_median"].get<double>()) + " ms" : "");
    };
    for (const json& p : disocclusion["paths"]) {
      const json& s = p["summary"];
      rowsF.push_back({p["scene"].get<std::string>() + " " + p["path"].get<std::string>(),
                       fmt(100 * numberOrNan(s["holes_outside_share"]), 0) + " / " +
                           fmt(100 * numberOrNan(s["holes_occluded_share"]), 0) + " / " +
                           fmt(100 * numberOrNan(s["holes_sky_share"]), 0),
                       cell(s["copy"]), cell(s["third_prev"]), cell(s["third_next"]),
                       cell(s["hole_rects"]), cell(s["peel_bound"]), cell(s["exact_holes"])});
    }
    page.table({"path", "holes % outside / occluded / sky", "copy", "keyframe before", "keyframe after",
                "hole rectangles", "peeling bound", "exact holes"},
               rowsF);
    for (const json& u : disocclusion["unavailable"])
      page.paragraph("Not measured: " + u["scene"].get<std::string>() + " (" +
                     u["reason"].get<std::string>() + ")");
  }
  if (want("floor")) {
    page.heading("(g) The fill floor");
    page.paragraph("One full-screen textured quad warped as one layer, and as both layers of an "
                   "in-between frame (readback included): the least an in-between frame can "
                   "cost at that resolution. Median of 40 draws after an untimed one.");
    std::vector<std::vector<std::string>> rowsG;
    for (const json& f : floor)
      rowsG.push_back({std::to_string(f["resolution"].get<int>()) + "²",
                       fmt(f["one_layer_ms"].get<double>()), fmt(f["two_layers_ms"].get<double>())});
    page.table({"resolution", "one layer ms", "two layers ms"}, rowsG);
  }
  HW_TRY(page.write(opt.outDir + "/index.html"));
  return doc;
}

}  // namespace hw::bench
