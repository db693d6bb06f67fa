// The `lod` command.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "app/cli_common.h"
#include "app/commands.h"
#include "app/option_checks.h"
#include "app/viewer.h"
#include "core/file_io.h"
#include "core/gl/context.h"
#include "core/json_util.h"
#include "core/machine.h"
#include "core/memory.h"
#include "core/metrics.h"
#include "core/timer.h"
#include "keyframe/geometry_renderer.h"
#include "keyframe/keyframe_db.h"
#include "keyframe/lod_builder.h"
#include "keyframe/overlay.h"
#include "scenes/camera_path.h"
#include "scenes/fetch.h"
#include "scenes/loader.h"
#include "scenes/q3bsp.h"
#include "session/bake.h"
#include "session/export.h"
#include "session/keyframe_planner.h"
#include "session/schedule_calibration.h"
#include "session/walk.h"

namespace hw::app {
namespace {

using nlohmann::json;

struct LodCli {
  CLI::App* lod = nullptr;
  Common lodC;
  std::string lodOut = "overlay.png";
  std::string lodTau = "2^11";
  std::string lodCriterion = "five-point";
  int lodFrame = 0;
  std::string lodPlanarity = "stencil";
  bool lodMerge = false;
  std::string lodTauGradS = "0";
};

int run(LodCli& o, [[maybe_unused]] int argc, [[maybe_unused]] char** argv) {
    keyframe::LodOptions lo;
    if (!parseTau(o.lodTau, &lo.tau))
      return fail("--tau: expected a non-negative number like 2048 or 2^11, got '" + o.lodTau + "'");
    keyframe::parseDeltaCriterion(o.lodCriterion.c_str(), &lo.criterion);
    keyframe::parsePlanarity(o.lodPlanarity.c_str(), &lo.planarity);
    lo.mergeStrips = o.lodMerge;
    if (std::string err; !parseTauGradient(o.lodTauGradS, &lo.tauGradient, &err)) return fail(err);
    auto in = loadInputs(o.lodC);
    if (!in) return fail(in.error().message);
    if (o.lodFrame >= in->path.frames)
      return fail("--frame: expected 0.." + std::to_string(in->path.frames - 1) + ", got " +
                  std::to_string(o.lodFrame));
    keyframe::RenderOptions ropt;
    ropt.depthMode = depthModeOf(o.lodC.depth);
    auto r = keyframe::GeometryRenderer::create(in->scene, ropt);
    if (!r) return fail(r.error().message);
    keyframe::Keyframe kf;
    if (auto s = (*r)->renderKeyframe(in->path.cameraAt(o.lodFrame), kf); !s) return fail(s.error().message);
    keyframe::QuadMesh mesh;
    keyframe::LodBuilder builder;
    if (auto s = builder.build(kf, lo, &mesh); !s) return fail(s.error().message);
    const auto parent = std::filesystem::path(o.lodOut).parent_path();
    if (!parent.empty())
      if (auto s = ensureWritableDir(parent.string()); !s) return fail(s.error().message);
    if (auto s = writePng(o.lodOut, keyframe::drawQuadOverlay(kf.colour, mesh)); !s) return fail(s.error().message);
    const auto& st = mesh.stats;
    json j = {{"scene", {{"name", in->scene.name}, {"triangles", in->scene.triangleCount()}}},
              {"frame", o.lodFrame},
              {"resolution", {kf.colour.width(), kf.colour.height()}},
              {"tau", lo.tau},
              {"criterion", o.lodCriterion},
              {"planarity", o.lodPlanarity},
              {"merge_strips", o.lodMerge},
              {"tau_gradient", lo.tauGradient},
              {"depth_mode", o.lodC.depth},
              {"quads", st.quads},
              {"one_pixel_leaves", st.onePixelLeaves},
              {"empty_pixels", st.emptyPixels},
              {"clamped_corners", st.clampedCorners},
              {"ms", {{"delta", st.deltaMs}, {"subdivide", st.subdivideMs}, {"corners", st.cornersMs},
                      {"total", st.deltaMs + st.subdivideMs + st.cornersMs}}}};
    const std::string jsonPath = std::filesystem::path(o.lodOut).replace_extension(".json").string();
    if (auto s = writeFileAtomic(jsonPath, j.dump(1)); !s) return fail(s.error().message);
    std::printf("%d quads (%d one-pixel leaves) at tau %g in %.2f ms; overlay %s, stats %s\n",
                st.quads, st.onePixelLeaves, lo.tau, st.deltaMs + st.subdivideMs + st.cornersMs,
                o.lodOut.c_str(), jsonPath.c_str());
    return 0;
}

}  // namespace

void addLodCommand(CLI::App& app, Commands& commands) {
  auto state = std::make_shared<LodCli>();
  LodCli& o = *state;
  // lod
  auto* lod = o.lod = app.add_subcommand(
      "lod", "Build one keyframe's quad mesh and draw its leaves over it (paper Plate I-A); "
             "writes OUT (PNG) and OUT with .json (stats)");
  addCommon(lod, o.lodC);
  lod->add_option("--frame", o.lodFrame, "Frame index on the path to use as the keyframe")
      ->check(nonNegativeNumber())
      ->capture_default_str();
  addTauText(lod, o.lodTau);
  lod->add_option("--criterion", o.lodCriterion, "five-point or per-axis-max")
      ->check(CLI::IsMember({"five-point", "per-axis-max"}))
      ->capture_default_str();
  lod->add_option("--planarity", o.lodPlanarity, "stencil (paper) or region-local")
      ->check(CLI::IsMember({"stencil", "region-local"}))
      ->capture_default_str();
  lod->add_flag("--merge-strips", o.lodMerge, "Merge adjacent coplanar leaves");
  lod->add_option("--tau-gradient", o.lodTauGradS, tauGradientHelp())->capture_default_str();
  lod->add_option("--out", o.lodOut, "Overlay PNG path")->capture_default_str();

  commands.push_back({lod, [state](int argc, char** argv) { return run(*state, argc, argv); }});
}

}  // namespace hw::app
