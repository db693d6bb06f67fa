#include "bench/scene_table.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "core/file_io.h"
#include "core/json_util.h"
#include "scenes/camera_path.h"
#include "scenes/loader.h"
#include "session/presets.h"
#include "session/walk.h"

namespace hw::bench {

using nlohmann::json;

std::vector<SceneCase> defaultSceneCases() {
  return {{"indoor:100k", ""},
          {"indoor:1M", ""},
          {"outdoor:100k", ""},
          {"outdoor:1M", ""},
          {"q3:oa_dm5", "paths/oa_dm5.json"},
          {"q3:oa_dm1", "paths/oa_dm1.json"},
          {"q3:aggressor", "paths/aggressor.json"},
          {"q3:ps37ctf", "paths/ps37ctf.json"},
          {"q3:delta", "paths/delta.json"},
          {"torcs:forza", "paths/forza.json"},
          {"torcs:ruudskogen", "paths/ruudskogen.json"},
          {"torcs:e-track-2", "paths/e-track-2.json"},
          {"morse:land-1/trees", "paths/trees.json"}};
}

namespace {

double num(const json& j) { return j.is_number() ? j.get<double>() : std::nan(""); }

// One walk's row: what the table shows of its summary.
json rowOf(const json& s) {
  const json& m = s["frames_by_mode"];
  const double frames = s["frames"].get<double>();
  auto share = [&](const char* k) { return frames > 0 ? m[k].get<double>() / frames : 0.0; };
  return {{"frames", s["frames"]},
          {"geometry_share", share("geometry")},
          {"warp_share", share("warp")},
          {"keyframe_share", share("keyframe")},
          {"keyframes_built", s["keyframes"]},
          {"frame_ms_median", s["frame_ms"]["median"]},
          {"frame_ms_p95", s["frame_ms"]["p95"]},
          {"reference_ms_median", s["reference_ms"]["median"]},
          {"reference_ms_p95", s["reference_ms"]["p95"]},
          {"frame_over_reference_median", s["frame_over_reference"]["median"]},
          {"frame_over_reference_p95", s["frame_over_reference"]["p95"]},
          {"psnr_median", s["psnr"]["median"]},
          {"psnr_p5", s["psnr"]["p5"]},
          {"quads_per_keyframe_median", s["quads_per_keyframe"]["median"]}};
}

std::string fmt(const json& j, const char* f) {
  if (!j.is_number()) return "–";
  char b[32];
  std::snprintf(b, sizeof b, f, j.get<double>());
  return b;
}

// A share in [0, 1] as a whole percentage.
std::string percent(const json& j) {
  return j.is_number() ? fmt(json(100.0 * j.get<double>()), "%.0f%%") : "–";
}

std::string markdown(const json& rows, const std::string& machine) {
  std::ostringstream md;
  md << "Each scene walked with the defaults and with `--preset paper` in one run (" << machine
     << "). frame/geom: `frame_ms` over `reference_ms` (the geometry frame at the same "
        "camera); PSNR over warped frames only (dB).\n\n"
     << "| scene | triangles | preset | geometry / warp / keyframe frames | frame/geom median | "
        "frame/geom p95 | PSNR median | PSNR p5 | quads/keyframe |\n"
     << "|---|---|---|---|---|---|---|---|---|\n";
  for (const json& r : rows) {
    if (r.contains("error")) {
      md << "| " << r["scene"].get<std::string>() << " | – | – | not run: "
         << r["error"].get<std::string>() << " | | | | | |\n";
      continue;
    }
    for (const char* preset : {"default", "paper"}) {
      const json& p = r[preset];
      md << "| " << r["scene"].get<std::string>() << " | " << r["triangles"].get<std::size_t>()
         << " | " << preset << " | " << percent(p["geometry_share"]) << " / "
         << percent(p["warp_share"]) << " / " << percent(p["keyframe_share"])
         << " | " << fmt(p["frame_over_reference_median"], "%.2f") << " | "
         << fmt(p["frame_over_reference_p95"], "%.2f") << " | " << fmt(p["psnr_median"], "%.2f")
         << " | " << fmt(p["psnr_p5"], "%.2f") << " | "
         << fmt(p["quads_per_keyframe_median"], "%.0f") << " |\n";
    }
  }
  return md.str();
}

}  // namespace

Result<json> runSceneTable(const SceneTableOptions& opt) {
  HW_TRY(ensureWritableDir(opt.outDir));
  json rows = json::array();
  std::ostringstream csv;
  csv << "scene,path,triangles,preset,frames,geometry_share,warp_share,keyframe_share,"
         "keyframes_built,frame_ms_median,frame_ms_p95,reference_ms_median,reference_ms_p95,"
         "frame_over_reference_median,frame_over_reference_p95,psnr_median,psnr_p5,"
         "quads_per_keyframe_median\n";
  for (const SceneCase& c : opt.cases) {
    json row = {{"scene", c.spec}};
    auto scene = scenes::loadScene(c.spec);
    const bool havePath = !c.path.empty() && std::filesystem::is_regular_file(c.path);
    auto path = havePath ? scenes::loadCameraPath(c.path) : scenes::defaultPathFor(c.spec);
    if (!scene || !path) {
      row["error"] = !scene ? scene.error().message : path.error().message;
      if (opt.progress) std::fprintf(stderr, "bench scenes: %s: %s\n", c.spec.c_str(),
                                     row["error"].get<std::string>().c_str());
      rows.push_back(row);
      continue;
    }
    if (opt.width > 0) path->width = opt.width;
    if (opt.height > 0) path->height = opt.height;
    row["path"] = havePath ? c.path : "default";
    row["triangles"] = scene->triangleCount();
    for (session::Preset preset : {session::Preset::Default, session::Preset::Paper}) {
      session::WalkOptions w = session::presetOptions(preset);
      w.maxFrames = opt.frames;
      w.keepFrames = false;
      w.strips = 0;
      w.progress = false;
      w.glRenderer = opt.glRenderer;
      w.glVersion = opt.glVersion;
      if (opt.progress)
        std::fprintf(stderr, "bench scenes: %s, %s preset\n", c.spec.c_str(),
                     session::presetName(preset));
      auto res = session::runWalk(*scene, c.spec, *path, w);
      if (!res) return res.error();
      const json r = rowOf(res->report["summary"]);
      row[session::presetName(preset)] = r;
      csv << c.spec << ',' << row["path"].get<std::string>() << ',' << scene->triangleCount()
          << ',' << session::presetName(preset);
      for (const char* k : {"frames", "geometry_share", "warp_share", "keyframe_share",
                            "keyframes_built", "frame_ms_median", "frame_ms_p95",
                            "reference_ms_median", "reference_ms_p95",
                            "frame_over_reference_median", "frame_over_reference_p95",
                            "psnr_median", "psnr_p5", "quads_per_keyframe_median"}) {
        const double v = num(r[k]);
        csv << ',';
        if (std::isfinite(v)) csv << v;
      }
      csv << '\n';
    }
    rows.push_back(row);
  }
  const std::string machine = opt.glRenderer.empty() ? "this machine" : opt.glRenderer;
  json doc = {{"rows", rows}, {"gl_renderer", opt.glRenderer}, {"gl_version", opt.glVersion}};
  HW_TRY(writeFileAtomic(opt.outDir + "/scenes.json", doc.dump(1)));
  HW_TRY(writeFileAtomic(opt.outDir + "/scenes.csv", csv.str()));
  HW_TRY(writeFileAtomic(opt.outDir + "/scenes.md", markdown(rows, machine)));
  return doc;
}

}  // namespace hw::bench
