#include "report/walk_page.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "core/file_io.h"
#include "core/json_util.h"
#include "report/html_report.h"
#include "report/plot.h"

namespace hw::report {

using nlohmann::json;

namespace {

const json& member(const json& j, const char* key) {
  static const json kNull;
  return j.is_object() && j.contains(key) ? j[key] : kNull;
}
double stat(const json& s, const char* key, const char* which) {
  return numberOrNan(member(member(s, key), which));
}
int count(const json& j, const char* key) {
  const json& v = member(j, key);
  return v.is_number() ? v.get<int>() : -1;
}
std::string text(const json& j, const char* key, const char* otherwise = "") {
  const json& v = member(j, key);
  return v.is_string() ? v.get<std::string>() : otherwise;
}
std::string printf1(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}
// A number as printed in the summary: "-" where it is not a number.
std::string num(double v, int decimals) { return fmt(v, decimals); }
std::string ms(double v) { return num(v, v >= 100 ? 0 : 1) + " ms"; }
std::string tauText(const json& s) {
  const double px = numberOrNan(member(s, "tau_parallax_px"));
  if (px > 0) return "tau-px " + printf1("%g", px);
  const double tau = numberOrNan(member(s, "tau"));
  if (!std::isfinite(tau)) return "tau -";
  const double l = std::log2(tau);
  if (tau > 0 && std::abs(l - std::round(l)) < 1e-9) return "tau 2^" + printf1("%.0f", l);
  return "tau " + printf1("%g", tau);
}
bool referenceOn(const json& s) {
  // Without reference renders no frame has a geometry time (reference_ms).
  return std::isfinite(stat(s, "reference_ms", "median"));
}

}  // namespace

std::string whyNothingWarped(const json& s) {
  const json& byMode = member(s, "frames_by_mode");
  if (count(byMode, "warp") > 0) return "";
  const std::string mode = text(s, "mode");
  if (mode == "geometry") return "--mode geometry draws every frame";
  const int frames = count(s, "frames"), keyframeFrames = count(byMode, "keyframe");
  if (mode == "hybrid" || mode.empty()) {
    if (keyframeFrames >= 0 && keyframeFrames == frames)
      return "every frame is a keyframe frame (a keyframe every " +
             std::to_string(count(s, "keyframe_every")) + " frames)";
    return "no frame lies between two keyframes";
  }
  // auto: what the choice compared.
  const json& c = member(s, "mode_costs");
  double geometry = numberOrNan(member(c, "geometry_ms"));
  if (!std::isfinite(geometry)) geometry = stat(s, "reference_ms", "median");
  double warp = numberOrNan(member(c, "in_between_ms"));
  if (!std::isfinite(warp)) warp = numberOrNan(member(c, "warp_calibration_ms"));
  if (!std::isfinite(warp)) warp = numberOrNan(member(c, "warp_floor_ms"));
  const std::string hint = "; `--mode hybrid` warps every frame";
  if (std::isfinite(geometry) && std::isfinite(warp) && warp >= geometry)
    return "auto: drawing was cheaper here, " + ms(geometry) + " against a warp of " + ms(warp) +
           hint;
  const double enter = numberOrNan(member(c, "enter_below"));
  if (std::isfinite(geometry) && std::isfinite(warp) && std::isfinite(enter) &&
      warp >= enter * geometry)
    return "auto: warping would save too little here, a warp of " + ms(warp) + " against " +
           ms(geometry) + " to draw (it warps below " + num(enter, 2) + "x the drawing time)" +
           hint;
  if (count(s, "warp_starts_deferred") > 0)
    return "auto: the keyframes of each segment that would have been warped were still being "
           "built when it began (" +
           std::to_string(count(s, "warp_starts_deferred")) + " segments drawn instead)" + hint;
  if (std::isfinite(geometry) && std::isfinite(warp))
    return "auto: drawing was predicted cheaper here (" + ms(geometry) + " against a warp of " +
           ms(warp) + ")" + hint;
  if (std::isfinite(geometry))
    return "auto: drawing was cheaper here (" + ms(geometry) + "; no warp was measured)" + hint;
  return "auto: drawing was predicted cheaper here" + hint;
}

// Where auto's choices came from (summary.auto_pin; "" when not auto).
static std::string autoPinText(const json& pin) {
  if (!pin.is_object()) return "";
  const std::string state = text(pin, "state"), file = text(pin, "file");
  std::string t;
  if (state == "replayed") {
    t = "; chosen as a measured run of this walk pinned them (" + file +
        "; --auto-pin measure chooses again)";
    if (const int dev = count(pin, "deviations"); dev > 0)
      t += ", " + std::to_string(dev) + " drawn as geometry while their keyframes were building";
  } else if (state == "off") {
    t = "; chosen from this run's costs";
  } else {
    t = "; chosen from this run's costs" +
        (state == "measured" && !file.empty() ? ", pinned to " + file : std::string());
  }
  if (const std::string note = text(pin, "note"); !note.empty()) t += " (" + note + ")";
  return t;
}

WalkSummaryText walkSummaryText(const json& s) {
  WalkSummaryText t;
  const json& byMode = member(s, "frames_by_mode");
  const int frames = count(s, "frames");
  const int warped = count(byMode, "warp"), drawn = count(byMode, "geometry"),
            keyframeFrames = count(byMode, "keyframe");
  const bool reference = referenceOn(s);
  const std::string scene = text(member(s, "scene"), "name", "walk");

  // The line to quote.
  std::string h = scene + ", " + std::to_string(frames) + " frames: ";
  if (warped > 0) {
    const double pct = frames > 0 ? 100.0 * warped / frames : 0;
    h += pct < 0.5 ? "<1 % warped" : printf1("%.0f", pct) + " % warped";
    const double p = stat(s, "psnr", "median"), p5 = stat(s, "psnr", "p5");
    if (!reference)
      h += ", PSNR not measured (--no-reference)";
    else if (std::isfinite(p))
      h += ", in-between " + num(p, 1) + " dB (p5 " + num(p5, 1) + ")";
    else
      h += ", in-between frames identical to the geometry frames";
  } else {
    h += "none warped (" + whyNothingWarped(s) + ")";
  }
  const json& ratio = member(s, "frame_over_reference");
  const double rMed = numberOrNan(member(ratio, "median")), rP95 = numberOrNan(member(ratio, "p95"));
  if (std::isfinite(rMed) && std::isfinite(rP95))
    h += ", frame " + num(rMed, 2) + "x the geometry frame (median), " + num(rP95, 2) + "x (p95)";
  else if (std::isfinite(stat(s, "frame_ms", "median")))
    h += ", frame " + ms(stat(s, "frame_ms", "median")) + " (median), " +
         ms(stat(s, "frame_ms", "p95")) + " (p95)";
  t.headline = h;

  // Details.
  const json& res = member(s, "resolution");
  const std::string size = res.is_array() && res.size() == 2 && res[0].is_number() && res[1].is_number()
                               ? std::to_string(res[0].get<int>()) + "x" + std::to_string(res[1].get<int>())
                               : "-";
  const json& tris = member(member(s, "scene"), "triangles");
  std::string planarity = text(s, "planarity", "-") + " planarity";
  if (member(s, "merge_strips") == true) planarity += ", merged strips";
  t.details.push_back("scene " + scene + " (" +
                      (tris.is_number() ? std::to_string(tris.get<long long>()) : "-") +
                      " triangles), " + size + ", depth " + text(s, "depth_mode", "-") +
                      "; mode " + text(s, "mode", "-") + ", " + tauText(s) + ", " +
                      text(s, "criterion", "-") + ", " + planarity + ", compose " +
                      text(s, "compose_mode", "-"));
  t.details.push_back("frames: " + std::to_string(frames) + " = " + std::to_string(warped) +
                      " warped + " + std::to_string(drawn) + " drawn as geometry + " +
                      std::to_string(keyframeFrames) +
                      (keyframeFrames == 1 ? " keyframe frame" : " keyframe frames") +
                      autoPinText(member(s, "auto_pin")));

  const json& schedule = member(s, "keyframe_frames");
  const int scheduled = schedule.is_array() ? static_cast<int>(schedule.size()) : -1;
  const int built = count(s, "keyframes");
  const std::string acq = text(s, "keyframe_acquisition");
  std::string k = "keyframes: " + std::to_string(scheduled) + " in the schedule (" +
                  (text(s, "keyframe_schedule") == "fixed"
                       ? "a keyframe every " + std::to_string(count(s, "keyframe_every")) + " frames"
                   : text(s, "keyframe_schedule") == "adaptive" ? std::string("adaptive schedule")
                   : acq == "source"                            ? std::string("the database's")
                                                                : std::string("given")) +
                  "), " + std::to_string(built) +
                  (acq == "source"  ? " read from the database"
                   : acq == "async" ? " built (ahead, on a worker thread)"
                                    : " built (when first needed)");
  if (text(s, "mode") == "auto" && built >= 0 && built < scheduled)
    k += "; segments drawn as geometry need none";
  // Keyframe stalls as report.json counts them (keyframe_stalls: frames'
  // keyframe gets that waited, the warm-up's excluded), then every wait
  // timed (keyframe_stall_ms: its count and total), which may include a
  // wait before frame 0.
  const int stalls = count(s, "keyframe_stalls");
  const int waits = count(member(s, "keyframe_stall_ms"), "count");
  if (stalls >= 0)
    k += "; " + std::to_string(stalls) + (stalls == 1 ? " keyframe stall" : " keyframe stalls") +
         " (a frame waited for a keyframe; warm-up excluded)";
  if (waits >= 0)
    k += "; " + std::to_string(waits) + (waits == 1 ? " wait" : " waits") + " for a keyframe, " +
         ms(numberOrNan(member(s, "keyframe_stall_ms_total"))) + " in all";
  t.details.push_back(k);

  if (warped > 0) {
    std::string q = "warped frames: ";
    if (reference)
      q += "PSNR median " + num(stat(s, "psnr", "median"), 2) + " dB (p5 " +
           num(stat(s, "psnr", "p5"), 2) + "), SSIM median " + num(stat(s, "ssim", "median"), 4) +
           "; ";
    else
      q += "PSNR not measured (--no-reference); ";
    q += "holes before fallback median " +
         num(100 * stat(s, "holes_before_fallback", "median"), 3) + " %, after " +
         num(100 * stat(s, "holes_after_fallback", "median"), 3) + " %; quads per keyframe median " +
         num(stat(s, "quads_per_keyframe", "median"), 0);
    t.details.push_back(q);
  }
  std::string tm = "time: ";
  if (warped > 0)
    tm += "warped frame " + ms(stat(s, "in_between_ms", "median")) + " median (p95 " +
          ms(stat(s, "in_between_ms", "p95")) + "); ";
  if (reference)
    tm += "geometry frame at the same camera " + ms(stat(s, "reference_ms", "median")) +
          " median (p95 " + ms(stat(s, "reference_ms", "p95")) + "); ";
  tm += "every frame " + ms(stat(s, "frame_ms", "median")) + " median (p95 " +
        ms(stat(s, "frame_ms", "p95")) + ")";
  t.details.push_back(tm);
  if (std::isfinite(rMed) && std::isfinite(rP95))
    t.details.push_back("frame time over geometry time: median " + num(rMed, 3) +
                        " (median frame over median geometry frame), p95 " + num(rP95, 3) +
                        " (p95 over p95: the slowest 5 % of each, not the same frames)");

  const std::string budgetMode = text(s, "frame_budget_mode", "off");
  if (budgetMode != "off") {
    char b[512];
    std::snprintf(
        b, sizeof b,
        "frame budget %s (%s): %d frames refreshed (%s px median, %s median), stale pixels median "
        "%s; presented interval %s median, p95/median %s; %d frames over budget",
        ms(numberOrNan(member(s, "frame_budget_ms"))).c_str(), budgetMode.c_str(),
        count(s, "frames_refreshed"), num(stat(s, "refreshed_pixels", "median"), 0).c_str(),
        ms(stat(s, "refresh_ms", "median")).c_str(), num(stat(s, "stale_pixels", "median"), 0).c_str(),
        ms(stat(s, "frame_interval_ms", "median")).c_str(),
        num(numberOrNan(member(s, "frame_interval_ms_p95_over_median")), 2).c_str(),
        count(s, "budget_overruns"));
    t.details.push_back(b);
  }
  return t;
}

Status writePsnrAlongPath(const std::string& pngPath, const json& report) {
  const json& frames = member(report, "frames");
  Series warped{"warped frame PSNR"}, keys{"keyframe frame (exact)"},
      drawn{"frame drawn as geometry (exact)"};
  warped.colour = {31, 119, 180, 255};
  keys.colour = {44, 160, 44, 255};
  drawn.colour = {140, 86, 75, 255};
  warped.markers = false;
  keys.lines = drawn.lines = false;
  keys.marker = Marker::kDiamond;
  drawn.marker = Marker::kSquare;
  double lo = INFINITY, hi = -INFINITY;
  std::vector<double> keyX, drawnX;
  if (frames.is_array())
    for (const json& f : frames) {
      const double x = numberOrNan(member(f, "index"));
      const bool isKey = member(f, "is_keyframe") == true;
      const json& pair = member(f, "keyframes");
      const bool isWarp = !isKey && pair.is_array() && pair.size() == 2;
      const double p = isWarp ? numberOrNan(member(f, "psnr")) : std::nan("");
      warped.x.push_back(x);
      warped.y.push_back(p);
      if (std::isfinite(p)) lo = std::min(lo, p), hi = std::max(hi, p);
      if (isKey) keyX.push_back(x);
      else if (!isWarp) drawnX.push_back(x);
    }
  if (!std::isfinite(lo)) lo = 20, hi = 40;
  const double span = std::max(hi - lo, 2.0);
  const double yMin = lo - 0.15 * span, yMax = hi + 0.05 * span;
  // Kinds of frame along the bottom of the plot.
  for (double x : keyX) keys.x.push_back(x), keys.y.push_back(yMin + 0.04 * span);
  for (double x : drawnX) drawn.x.push_back(x), drawn.y.push_back(yMin + 0.04 * span);
  PlotOptions po;
  po.title = "PSNR along the path: " + text(member(member(report, "summary"), "scene"), "name", "walk");
  po.xLabel = "frame";
  po.yLabel = "PSNR dB against the geometry frame";
  po.width = 1000;
  po.height = 420;
  po.yMin = yMin;
  po.yMax = yMax;
  std::vector<Series> series{warped};
  if (!keys.x.empty()) series.push_back(keys);
  if (!drawn.x.empty()) series.push_back(drawn);
  return writePlot(pngPath, series, po);
}

std::string walkPageHtml(const json& report, const std::vector<std::string>& files) {
  const json& s = member(report, "summary");
  const WalkSummaryText sum = walkSummaryText(s);
  auto has = [&](const std::string& f) {
    for (const auto& g : files)
      if (g == f) return true;
    return false;
  };
  HtmlReport page("hybridwalk walk: " + text(member(s, "scene"), "name", "walk"));
  page.paragraph(sum.headline);
  std::string details;
  for (const auto& d : sum.details) details += d + "\n";
  page.preformatted(details);

  page.heading("Summary");
  std::vector<std::vector<std::string>> rows;
  auto statRow = [&](const char* label, const char* key, double scale, int decimals) {
    const json& v = member(s, key);
    if (!v.is_object()) return;
    rows.push_back({label, num(scale * numberOrNan(member(v, "median")), decimals),
                    num(scale * numberOrNan(member(v, "p5")), decimals),
                    num(scale * numberOrNan(member(v, "p95")), decimals),
                    member(v, "count").is_number() ? std::to_string(member(v, "count").get<long long>())
                                                   : "-"});
  };
  statRow("PSNR of warped frames, dB", "psnr", 1, 2);
  statRow("SSIM of warped frames", "ssim", 1, 4);
  statRow("holes before fallback, %", "holes_before_fallback", 100, 3);
  statRow("holes after fallback, %", "holes_after_fallback", 100, 3);
  statRow("quads per keyframe", "quads_per_keyframe", 1, 0);
  statRow("warped frame, ms", "in_between_ms", 1, 2);
  statRow("geometry frame at the same camera, ms", "reference_ms", 1, 2);
  statRow("every frame, ms", "frame_ms", 1, 2);
  statRow("keyframe build, ms", "keyframe_build_ms", 1, 2);
  page.table({"", "median", "p5", "p95", "frames"}, rows);
  const json& byMode = member(s, "frames_by_mode");
  page.table({"frames", "warped", "drawn as geometry", "keyframe frames", "keyframes in the schedule",
              text(s, "keyframe_acquisition") == "source" ? "keyframes read" : "keyframes built"},
             {{std::to_string(count(s, "frames")), std::to_string(count(byMode, "warp")),
               std::to_string(count(byMode, "geometry")), std::to_string(count(byMode, "keyframe")),
               member(s, "keyframe_frames").is_array()
                   ? std::to_string(member(s, "keyframe_frames").size())
                   : "-",
               std::to_string(count(s, "keyframes"))}});

  if (has("frame_times.png")) {
    page.heading("Frame times");
    page.images({"frame_times.png"},
                {"each frame's work by frame index (log scale), the frames that built a keyframe "
                 "marked, and the geometry renderer's time at the same camera"});
  }
  if (has("psnr_along_path.png")) {
    page.heading("PSNR along the path");
    page.images({"psnr_along_path.png"},
                {"each warped frame's PSNR against the geometry frame at the same camera; "
                 "keyframe frames and frames drawn as geometry (exact) marked along the bottom"});
  }
  std::vector<std::string> strips, captions;
  const json& info = member(s, "strips");
  if (info.is_array())
    for (const json& st : info) {
      const int f = count(st, "frame");
      const std::string name = "strip_" + std::to_string(f) + ".png";
      if (!has(name)) continue;
      strips.push_back(name);
      captions.push_back("frame " + std::to_string(f) + ": reference | hybrid | difference x4 | "
                         "holes; " +
                         (member(st, "psnr").is_number() ? num(member(st, "psnr").get<double>(), 2) + " dB"
                                                         : std::string("identical")));
    }
  if (!strips.empty()) {
    page.heading("Strips");
    page.images(strips, captions);
  }
  for (const char* extra : {"schedule.png", "calibration.png", "verify.png"})
    if (has(extra)) {
      page.heading(std::string("Plan: ") + extra);
      page.images({extra});
    }

  // Settings: every plain value of the summary; statistics are above.
  page.heading("Settings that ran");
  std::vector<std::vector<std::string>> settings;
  if (s.is_object())
    for (const auto& [key, v] : s.items()) {
      if (key == "keyframe_frames" && v.is_array()) {
        std::string list;
        for (const json& x : v) list += (list.empty() ? "" : " ") + x.dump();
        settings.push_back({key, list});
      }
      if (v.is_object() || v.is_array()) continue;
      settings.push_back({key, v.is_string()         ? v.get<std::string>()
                               : v.is_number_float() ? printf1("%.4g", v.get<double>())
                                                     : v.dump()});
    }
  page.table({"setting", "value"}, settings);
  const json& m = member(s, "machine");
  if (m.is_object()) {
    page.heading("Machine and GL renderer");
    std::vector<std::vector<std::string>> mrows;
    for (const auto& [key, v] : m.items())
      mrows.push_back({key, v.is_string() ? v.get<std::string>() : v.dump()});
    page.table({"", ""}, mrows);
  }
  page.paragraph("Every field of report.json is described in docs/walk-report.md. Times are "
                 "wall-clock on the machine above; they move by tens of percent between runs.");
  return page.html();
}

Status writeWalkPage(const std::string& dir, json* summary) {
  const std::string path = dir + "/report.json";
  auto textR = readFile(path);
  if (!textR) return makeError(path + ": cannot read the walk's report (" + textR.error().message + ")");
  const json report = json::parse(*textR, nullptr, false);
  if (report.is_discarded())
    return makeError(path + ": not valid JSON; expected a walk report written by 'hybridwalk walk'");
  if (!member(report, "summary").is_object() || !member(report, "frames").is_array())
    return makeError(path + ": not a walk report; expected an object with \"summary\" and "
                     "\"frames\" (docs/walk-report.md)");
  if (summary) *summary = report["summary"];
  HW_TRY(writePsnrAlongPath(dir + "/psnr_along_path.png", report));
  std::vector<std::string> files;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec))
    if (e.is_regular_file(ec)) files.push_back(e.path().filename().string());
  return writeFileAtomic(dir + "/index.html", walkPageHtml(report, files));
}

}  // namespace hw::report
