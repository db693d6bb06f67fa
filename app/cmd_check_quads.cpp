// The `check-quads` command: renders every keyframe of a path, builds its
// quad mesh with a preset's LOD settings and validates each quad against
// the keyframe's own pixels at the frames it will be warped to
// (keyframe/quad_validation.h, docs/quad-validation.md).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "app/cli_common.h"
#include "app/commands.h"
#include "app/option_checks.h"
#include "core/file_io.h"
#include "keyframe/geometry_renderer.h"
#include "keyframe/keyframe_cache.h"
#include "keyframe/lod_builder.h"
#include "keyframe/overlay.h"
#include "keyframe/quad_validation.h"
#include "report/plot.h"
#include "session/presets.h"

namespace hw::app {
namespace {

using nlohmann::json;

struct CheckQuadsCli {
  CLI::App* cmd = nullptr;
  Common c;
  std::string out;
  std::string preset = session::presetName(session::Preset::Default);
  std::string splitMisfit = "preset";
  double misfitTolerance = 0.0;
  double tolerancePx = 1.0;
  int minBadPixels = 1;
  bool quiet = false;
};

// Flagged quads filled with a red tint and outlined in red (2 px) over the
// leaf overlay, with a caption band of two lines above.
Image<Rgba8> flaggedOverlay(const keyframe::Keyframe& kf, const keyframe::QuadMesh& mesh,
                            const keyframe::QuadValidation& v, const std::string& line1,
                            const std::string& line2) {
  const Image<Rgba8> leaves = keyframe::drawQuadOverlay(kf.colour, mesh);
  const int w = leaves.width(), h = leaves.height();
  const int band = 2 * (report::captionHeight() + 6);
  Image<Rgba8> out(w, h + band);
  out.fill(Rgba8{255, 255, 255, 255});
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) out(x, y + band) = leaves(x, y);
  const Rgba8 red{255, 0, 0, 255};
  for (const keyframe::QuadCheck& c : v.quads) {
    if (!c.flagged) continue;
    const PixelRect& r = mesh.quads[static_cast<std::size_t>(c.quad)].rect;
    for (int y = r.y0; y < r.y1; ++y)
      for (int x = r.x0; x < r.x1; ++x) {
        Rgba8& p = out(x, y + band);
        const bool edge = x - r.x0 < 2 || r.x1 - 1 - x < 2 || y - r.y0 < 2 || r.y1 - 1 - y < 2;
        if (edge) {
          p = red;
        } else {
          p.r = static_cast<std::uint8_t>((p.r + 255) / 2);
          p.g = static_cast<std::uint8_t>(p.g / 2);
          p.b = static_cast<std::uint8_t>(p.b / 2);
        }
      }
  }
  const Rgba8 ink{20, 20, 20, 255};
  report::drawCaption(out, line1, 4, 3, ink);
  report::drawCaption(out, line2, 4, band / 2 + 3, ink);
  return out;
}

int run(CheckQuadsCli& o) {
  session::Preset preset = session::Preset::Default;
  session::parsePreset(o.preset, &preset);  // checked by the option's validator
  keyframe::LodOptions lod = session::presetOptions(preset).lod;
  if (o.splitMisfit != "preset") lod.splitMisfit = o.splitMisfit == "on";
  lod.misfitToleranceZPrime = o.misfitTolerance;
  keyframe::QuadValidationOptions vo;
  vo.tolerancePx = o.tolerancePx;
  vo.minBadPixels = o.minBadPixels;

  if (o.c.frames == 1) return failUsage("--frames: need at least 2 frames (two keyframes), got 1");
  auto in = loadInputs(o.c);
  if (!in) return fail(in.error().message);
  const scenes::CameraPath& path = in->path;
  const int frames = o.c.frames > 0 ? std::min(o.c.frames, path.frames) : path.frames;
  if (frames < 2) return failUsage("--frames: need at least 2 frames (two keyframes), got " +
                                   std::to_string(frames));
  if (auto s = ensureWritableDir(o.out); !s) return fail(s.error().message);

  keyframe::RenderOptions ropt;
  ropt.depthMode = depthModeOf(o.c.depth);
  auto renderer = keyframe::GeometryRenderer::create(in->scene, ropt);
  if (!renderer) return fail(renderer.error().message);
  const std::vector<int> keys = keyframe::KeyframeSchedule{frames, path.keyframeEvery, {}}.keyframes();

  keyframe::LodBuilder builder;
  keyframe::Keyframe kf, worstKf;
  keyframe::QuadMesh mesh, worstMesh;
  keyframe::QuadValidation worstV;
  int worstFrame = -1;
  double worstError = -1;
  json rows = json::array();
  std::string csv =
      "frame,quads,flagged,bad_pixels,checked_pixels,max_error_px,max_parallax_px_per_unit,"
      "misfit_splits,targets\n";
  long long totalQuads = 0, totalFlagged = 0;
  for (std::size_t k = 0; k < keys.size(); ++k) {
    const int f = keys[k];
    if (auto s = (*renderer)->renderKeyframe(path.cameraAt(f), kf); !s) return fail(s.error().message);
    if (auto s = builder.build(kf, lod, &mesh); !s) return fail(s.error().message);
    // Targets: every frame this keyframe brackets, up to both neighbouring
    // keyframes (their views are the farthest it is warped to).
    const int lo = k > 0 ? keys[k - 1] : f, hi = k + 1 < keys.size() ? keys[k + 1] : f;
    std::vector<Camera> targets;
    std::vector<int> targetFrames;
    for (int t = lo; t <= hi; ++t)
      if (t != f) {
        targets.push_back(path.cameraAt(t));
        targetFrames.push_back(t);
      }
    const keyframe::QuadValidation v = keyframe::validateQuads(kf, mesh, targets, vo);
    totalQuads += static_cast<long long>(mesh.quads.size());
    totalFlagged += v.flagged;
    json row = {{"frame", f},
                {"quads", mesh.quads.size()},
                {"flagged", v.flagged},
                {"bad_pixels", v.badPixels},
                {"checked_pixels", v.checkedPixels},
                {"max_error_px", v.maxErrorPx},
                {"max_parallax_px_per_unit", v.maxParallaxPxPerUnit},
                {"misfit_splits", builder.misfitSplits()},
                {"target_frames", {lo, hi}}};
    json flagged = json::array();
    for (const keyframe::QuadCheck& c : v.quads) {
      if (!c.flagged) continue;
      const PixelRect& r = mesh.quads[static_cast<std::size_t>(c.quad)].rect;
      flagged.push_back({{"quad", c.quad},
                         {"rect", {r.x0, r.y0, r.x1, r.y1}},
                         {"max_error_px", c.maxErrorPx},
                         {"bad_pixels", c.badPixels},
                         {"worst_pixel", {c.worstX, c.worstY}},
                         {"worst_target_frame", targetFrames[static_cast<std::size_t>(c.worstTarget)]},
                         {"parallax_px_per_unit", c.parallaxPxPerUnit}});
    }
    row["flagged_quads"] = std::move(flagged);
    rows.push_back(std::move(row));
    char line[256];
    std::snprintf(line, sizeof line, "%d,%zu,%d,%lld,%lld,%.4f,%.5f,%d,%zu\n", f, mesh.quads.size(),
                  v.flagged, v.badPixels, v.checkedPixels, v.maxErrorPx, v.maxParallaxPxPerUnit,
                  builder.misfitSplits(), targets.size());
    csv += line;
    if (!o.quiet)
      std::fprintf(stderr, "keyframe %d: %zu quads, %d flagged, worst %.2f px\n", f,
                   mesh.quads.size(), v.flagged, v.maxErrorPx);
    // The worst keyframe: most flagged quads, then the largest error.
    const double score = v.flagged * 1e9 + std::min(v.maxErrorPx, 1e8);
    if (score > worstError) {
      worstError = score;
      worstFrame = f;
      std::swap(worstKf, kf);
      worstMesh = mesh;
      worstV = v;
    }
  }

  json summary = {{"keyframes", keys.size()},
                  {"quads", totalQuads},
                  {"flagged", totalFlagged},
                  {"max_error_px", 0.0},
                  {"worst_keyframe", worstFrame}};
  double maxErr = 0;
  for (const json& r : rows) maxErr = std::max(maxErr, r["max_error_px"].get<double>());
  summary["max_error_px"] = maxErr;
  json doc = {{"scene", {{"name", in->scene.name}, {"triangles", in->scene.triangleCount()}}},
              {"path", o.c.path.empty() ? json("default") : json(o.c.path)},
              {"frames", frames},
              {"resolution", {path.width, path.height}},
              {"depth_mode", o.c.depth},
              {"preset", o.preset},
              {"lod",
               {{"tau", lod.tau},
                {"tau_px", lod.tauParallaxPx},
                {"criterion", keyframe::deltaCriterionName(lod.criterion)},
                {"planarity", keyframe::planarityName(lod.planarity)},
                {"merge_strips", lod.mergeStrips},
                {"tau_gradient", lod.tauGradient},
                {"split_misfit", lod.splitMisfit},
                {"misfit_tolerance_zprime", builder.misfitToleranceZPrime()}}},
              {"tolerance_px", vo.tolerancePx},
              {"min_bad_pixels", vo.minBadPixels},
              {"summary", summary},
              {"keyframes", std::move(rows)}};
  const std::string dir = o.out.back() == '/' ? o.out : o.out + "/";
  if (auto s = writeFileAtomic(dir + "report.json", doc.dump(1) + "\n"); !s) return fail(s.error().message);
  if (auto s = writeFileAtomic(dir + "keyframes.csv", csv); !s) return fail(s.error().message);
  char l1[200], l2[200];
  std::snprintf(l1, sizeof l1, "keyframe %d: %d/%zu flagged, worst %.2f px", worstFrame,
                worstV.flagged, worstMesh.quads.size(), worstV.maxErrorPx);
  std::snprintf(l2, sizeof l2, "%s, %s, split %s, tol %g px", in->scene.name.c_str(),
                o.preset.c_str(), lod.splitMisfit ? "on" : "off", vo.tolerancePx);
  if (auto s = writePng(dir + "overlay.png", flaggedOverlay(worstKf, worstMesh, worstV, l1, l2)); !s)
    return fail(s.error().message);
  std::printf("%s: %zu keyframes, %lld quads, %lld flagged (tolerance %g px), worst %.2f px at "
              "keyframe %d; %sreport.json, keyframes.csv, overlay.png\n",
              in->scene.name.c_str(), keys.size(), totalQuads, totalFlagged, vo.tolerancePx, maxErr,
              worstFrame, dir.c_str());
  return 0;
}

}  // namespace

void addCheckQuadsCommand(CLI::App& app, Commands& commands) {
  auto state = std::make_shared<CheckQuadsCli>();
  CheckQuadsCli& o = *state;
  auto* cmd = o.cmd = app.add_subcommand(
      "check-quads",
      "Validate every keyframe's quad mesh on a path: each quad's pixels reprojected at their own "
      "depth and at the quad's into the frames it is warped to; quads off by more than "
      "--tolerance-px are flagged (docs/quad-validation.md). Writes OUT/report.json, "
      "OUT/keyframes.csv and OUT/overlay.png (the worst keyframe, flagged quads in red)");
  addCommon(cmd, o.c);
  cmd->add_option("--out", o.out, "Output directory (created)")->required();
  cmd->add_option("--preset", o.preset, "LOD settings of this walk preset: default or paper")
      ->check(CLI::IsMember({"default", "paper"}))
      ->capture_default_str();
  cmd->add_option("--split-misfit", o.splitMisfit,
                  "Split leaves whose plane does not fit their pixels: on, off, or the preset's")
      ->check(CLI::IsMember({"preset", "on", "off"}))
      ->capture_default_str();
  cmd->add_option("--misfit-tolerance", o.misfitTolerance,
                  "With the split: largest departure of a leaf's pixels from its plane, in z' "
                  "units (2^24 scale; 0 = automatic: " +
                      misfitToleranceText() + ")")
      ->check(numberRange(0.0, 1e9))
      ->capture_default_str();
  cmd->add_option("--tolerance-px", o.tolerancePx,
                  "Flag a quad when a pixel of it lands more than this many target pixels from "
                  "the keyframe pixel's own reprojection")
      ->check(numberRange(1e-6, 1e6))
      ->capture_default_str();
  cmd->add_option("--min-bad-pixels", o.minBadPixels,
                  "Flag a quad only when at least this many of its pixels are over the tolerance")
      ->check(CLI::Range(1, 1 << 30))
      ->capture_default_str();
  cmd->add_flag("--quiet", o.quiet, "No line per keyframe");
  setGroups(cmd, {{"Essentials", {"--help", "--scene", "--path", "--out", "--preset", "--frames",
                                  "--width", "--height", "--quiet"}},
                  {"Level of detail", {"--split-misfit", "--misfit-tolerance", "--depth"}},
                  {"Validation", {"--tolerance-px", "--min-bad-pixels"}}});
  addForceOption(cmd);
  commands.push_back({cmd, [state](int, char**) {
    return runInOutputDir(state->cmd, state->out, {"report.json"},
                          [&] { return run(*state); });
  }});
}

}  // namespace hw::app
