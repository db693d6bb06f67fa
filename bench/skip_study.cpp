#include "bench/skip_study.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>

#include "report/html_report.h"
#include "core/json_util.h"
#include "session/walk.h"
#include "core/timer.h"
#include "scenes/camera_path.h"
#include "scenes/loader.h"
#include "warp/warper.h"

namespace hw::bench {

using namespace report;  // plots, tables and HTML of the studies
using session::WalkOptions;
using session::runWalk;

namespace {

using nlohmann::json;

struct Skip {
  const char* name;
  const char* what;
  bool onByDefault;                          // the walk's default state
  std::function<void(WalkOptions&)> toggle;  // flips it away from the default
  const char* firedField;                    // summary count of frames it fired on, or ""
};

json measure(const json& s) {
  const double pixels = numberOrNan(s["resolution"][0]) * numberOrNan(s["resolution"][1]);
  return {{"in_between_ms_median", s["in_between_ms"]["median"]},
          {"in_between_ms_p95", s["in_between_ms"]["p95"]},
          {"psnr_median", s["psnr"]["median"]},
          {"psnr_p5", s["psnr"]["p5"]},
          {"holes_before_fallback_median", s["holes_before_fallback"]["median"]},
          {"psnr_large_quads_median", s["psnr_large_quads"]["median"]},
          {"psnr_large_quads_p5", s["psnr_large_quads"]["p5"]},
          {"large_quad_pixel_share_median",
           finiteOrNull(numberOrNan(s["large_quad_pixels"]["median"]) / pixels)},
          {"drawn_quads_per_keyframe_median", s["drawn_quads_per_keyframe"]["median"]},
          {"subdivided_quads_per_keyframe_median", s["subdivided_quads_per_keyframe"]["median"]}};
}

}  // namespace

Result<json> runSkipStudy(const SkipStudyOptions& opt) {
  const double nearD = opt.nearDistance;
  const std::vector<Skip> skips = {
      {"fused layers", "both layers in one target, background only where the foreground left holes",
       true, [](WalkOptions& w) { w.inBetween.fusedLayers = false; }, ""},
      {"background skip", "no background layer when the coverage test finds no empty pixel", true,
       [](WalkOptions& w) { w.inBetween.skipBackground = false; }, "background_layer_skipped_frames"},
      {"previous-frame skip", "no previous-frame pass when there are no holes", true,
       [](WalkOptions& w) { w.inBetween.skipPrevious = false; }, "previous_frame_pass_skipped_frames"},
      {"sky at infinity", "empty keyframe pixels drawn as rectangles at infinity, not left as holes",
       true, [](WalkOptions& w) { w.warp.skyBackdrop = false; }, ""},
      {"near objects direct", "meshes within the near distance of a keyframe eye drawn as geometry",
       false, [nearD](WalkOptions& w) { w.inBetween.nearDistance = nearD; }, ""},
  };
  json rows = json::array(), unavailable = json::array();
  for (const SkipScene& sc : opt.scenes) {
    auto scene = scenes::loadScene(sc.spec);
    Result<scenes::CameraPath> path = sc.pathFile.empty() ? scenes::defaultPathFor(sc.spec)
                                                          : scenes::loadCameraPath(sc.pathFile);
    if (!scene || !path) {
      const std::string why = !scene ? scene.error().message : path.error().message;
      std::fprintf(stderr, "hybridwalk: warning: skip table: %s left out: %s\n", sc.spec.c_str(),
                   why.c_str());
      unavailable.push_back({{"scene", sc.spec}, {"reason", why}});
      continue;
    }
    auto walk = [&](const std::function<void(WalkOptions&)>& change) -> Result<json> {
      WalkOptions w;
      w.lod.tau = 2048;
      w.lod.planarity = keyframe::Planarity::RegionLocal;
      w.lod.mergeStrips = true;
      w.maxFrames = opt.frames;
      w.progress = false;
      w.strips = 0;
      w.keepFrames = false;
      w.glRenderer = opt.glRenderer;
      w.glVersion = opt.glVersion;
      if (change) change(w);
      auto r = runWalk(*scene, sc.spec, *path, w);
      if (!r) return r.error();
      return r->report["summary"];
    };
    if (opt.progress) std::fprintf(stderr, "bench: skips on %s\n", sc.spec.c_str());
    auto base = walk(nullptr);
    if (!base) return base.error();
    // Run-to-run noise: the default walk again; frames are identical, times are not.
    double msLo = numberOrNan((*base)["in_between_ms"]["median"]), msHi = msLo;
    for (int k = 1; k < std::max(2, opt.repeats); ++k) {
      auto again = walk(nullptr);
      if (!again) return again.error();
      const double v = numberOrNan((*again)["in_between_ms"]["median"]);
      msLo = std::min(msLo, v), msHi = std::max(msHi, v);
    }
    const double noise = msHi - msLo;
    auto timing = [noise](json& row) {
      const double d = numberOrNan(row["off"]["in_between_ms_median"]) -
                       numberOrNan(row["on"]["in_between_ms_median"]);
      row["ms_difference"] = finiteOrNull(d);
      row["ms_noise"] = finiteOrNull(noise);
      row["within_noise"] = std::isfinite(d) && std::isfinite(noise) ? json(std::abs(d) <= noise)
                                                                     : json(nullptr);
    };
    for (const Skip& k : skips) {
      auto other = walk(k.toggle);
      if (!other) return other.error();
      const json& on = k.onByDefault ? *base : *other;
      const json& off = k.onByDefault ? *other : *base;
      json row = {{"scene", sc.spec},
                  {"triangles", (*base)["scene"]["triangles"]},
                  {"skip", k.name},
                  {"what", k.what},
                  {"default", k.onByDefault ? "on" : "off"},
                  {"on", measure(on)},
                  {"off", measure(off)},
                  {"in_between_frames", on["in_between_frames"]}};
      if (*k.firedField) row["fired_frames"] = on[k.firedField];
      if (std::string(k.name) == "near objects direct") {
        row["near_distance"] = nearD;
        row["near_geometry_ms_median"] = on["near_geometry_ms"]["median"];
      }
      timing(row);
      rows.push_back(row);
    }
    // Subdivision of large quads (paper §2.1): each mode ("on") against the
    // default, none ("off"); PSNR also over the pixels large leaves drew.
    for (warp::Subdivision m :
         {warp::Subdivision::None, warp::Subdivision::Uniform, warp::Subdivision::Adaptive}) {
      Result<json> with = *base;
      if (m != warp::Subdivision::None) with = walk([m](WalkOptions& w) { w.warp.subdivision = m; });
      if (!with) return with.error();
      json row = {{"scene", sc.spec},
                      {"triangles", (*base)["scene"]["triangles"]},
                      {"skip", std::string("subdivision ") + warp::subdivisionName(m)},
                      {"what", "large quads cut into cells at upload; on = this mode, off = none"},
                      {"default", m == warp::Subdivision::None ? "on" : "off"},
                      {"on", measure(*with)},
                      {"off", measure(*base)},
                      {"in_between_frames", (*with)["in_between_frames"]},
                      {"subdivide_cell_px", (*with)["subdivide_cell_px"]}};
      timing(row);
      rows.push_back(row);
    }
  }
  return json{{"rows", rows},
              {"unavailable", unavailable},
              {"settings",
               {{"frames", opt.frames},
                {"tau", 2048},
                {"planarity", "region-local"},
                {"merge_strips", true},
                {"near_distance", nearD},
                {"repeats", std::max(2, opt.repeats)}}}};
}

std::string skipStudyCsv(const json& study) {
  std::string csv =
      "scene,triangles,skip,default,fired_frames,in_between_frames,ms_on_median,ms_off_median,"
      "ms_on_p95,ms_off_p95,psnr_on_median,psnr_off_median,psnr_on_p5,psnr_off_p5,"
      "psnr_large_on_median,psnr_large_off_median,psnr_large_on_p5,psnr_large_off_p5,"
      "large_px_share_on,large_px_share_off,drawn_quads_on,drawn_quads_off,subdivided_quads_on,"
      "subdivided_quads_off,ms_difference,ms_noise,within_noise\n";
  for (const json& r : study["rows"]) {
    csv += r["scene"].get<std::string>() + "," + std::to_string(r["triangles"].get<std::size_t>()) +
           "," + r["skip"].get<std::string>() + "," + r["default"].get<std::string>() + "," +
           (r.contains("fired_frames") ? std::to_string(r["fired_frames"].get<int>()) : "") + "," +
           std::to_string(r["in_between_frames"].get<int>()) + "," +
           fmt(numberOrNan(r["on"]["in_between_ms_median"])) + "," +
           fmt(numberOrNan(r["off"]["in_between_ms_median"])) + "," +
           fmt(numberOrNan(r["on"]["in_between_ms_p95"])) + "," +
           fmt(numberOrNan(r["off"]["in_between_ms_p95"])) + "," +
           fmt(numberOrNan(r["on"]["psnr_median"])) + "," +
           fmt(numberOrNan(r["off"]["psnr_median"])) + "," + fmt(numberOrNan(r["on"]["psnr_p5"])) +
           "," + fmt(numberOrNan(r["off"]["psnr_p5"]));
    for (const char* k : {"psnr_large_quads_median", "psnr_large_quads_p5",
                          "large_quad_pixel_share_median", "drawn_quads_per_keyframe_median",
                          "subdivided_quads_per_keyframe_median"}) {
      const int decimals = std::string(k) == "large_quad_pixel_share_median" ? 4 : 2;
      csv += ',';
      csv += fmt(numberOrNan(r["on"][k]), decimals);
      csv += ',';
      csv += fmt(numberOrNan(r["off"][k]), decimals);
    }
    csv += ',';
    csv += fmt(numberOrNan(r.value("ms_difference", json(nullptr))));
    csv += ',';
    csv += fmt(numberOrNan(r.value("ms_noise", json(nullptr))));
    csv += ',';
    const json within = r.value("within_noise", json(nullptr));
    if (within.is_boolean()) csv += within.get<bool>() ? '1' : '0';
    csv += '\n';
  }
  return csv;
}

}  // namespace hw::bench
