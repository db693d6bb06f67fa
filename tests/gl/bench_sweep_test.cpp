// The sweep's numbers are the LOD builder's, its tile baselines match their
// τ within 25 %, and sweep.json holds every requested τ.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include "bench/sweep.h"
#include "core/file_io.h"
#include "core/timer.h"
#include "gl_fixture.h"
#include "keyframe/geometry_renderer.h"
#include "keyframe/keyframe_cache.h"
#include "keyframe/lod_builder.h"
#include "scenes/procedural.h"

namespace hw {
namespace {

class SweepTest : public test::GlTest {};

TEST_F(SweepTest, QuadCountsAreTheBuildersAndBaselinesMatch) {
  const scenes::Scene scene = scenes::makeIndoorScene(20000);
  scenes::CameraPath path = scenes::defaultIndoorPath();
  path.width = path.height = 192;
  path.frames = 21;  // keyframes 0, 10, 20
  const std::vector<double> taus = {2048.0, 8192.0, 32768.0};
  bench::SweepOptions o;
  o.taus = taus;
  o.bothCriteria = false;
  o.preset = session::Preset::Paper;  // the quad counts below are the paper's LOD builder
  o.variants = false;
  o.outDir = ::testing::TempDir() + "hw_sweep_test";
  o.progress = false;
  auto res = bench::runSweep(scene, "indoor", path, o);
  ASSERT_TRUE(res.ok()) << res.error().message;

  // sweep.json on disk parses and has every τ.
  auto text = readFile(o.outDir + "/sweep.json");
  ASSERT_TRUE(text.ok());
  const nlohmann::json doc = nlohmann::json::parse(*text);
  for (double tau : taus) {
    bool found = false;
    for (const auto& r : doc["rows"]) found |= r["tau"].is_number() && r["tau"].get<double>() == tau;
    EXPECT_TRUE(found) << "tau " << tau << " missing from sweep.json";
  }

  // Quads per keyframe: the median over the path's keyframes, rebuilt here.
  auto renderer = keyframe::GeometryRenderer::create(scene);
  ASSERT_TRUE(renderer.ok());
  std::vector<keyframe::Keyframe> kfs(3);
  for (int k = 0; k < 3; ++k) ASSERT_TRUE((*renderer)->renderKeyframe(path.cameraAt(10 * k), kfs[k]).ok());
  std::map<double, double> lodQuads;
  for (const auto& r : doc["rows"]) {
    if (r["mesh"] != "lod") continue;
    const double tau = r["tau"].get<double>();
    keyframe::LodOptions lo;
    lo.tau = tau;
    std::vector<double> q;
    for (const auto& kf : kfs) {
      auto m = keyframe::buildQuadMesh(kf, lo);
      ASSERT_TRUE(m.ok());
      q.push_back(m->stats.quads);
    }
    EXPECT_EQ(r["quads_per_keyframe"]["median"].get<double>(), median(q)) << "tau " << tau;
    lodQuads[tau] = median(q);
  }
  ASSERT_EQ(lodQuads.size(), taus.size());
  int tileRows = 0;
  for (const auto& r : doc["rows"]) {
    if (r["mesh"] != "uniform-tiles") continue;
    ++tileRows;
    const double matched = lodQuads.at(r["matched_to_tau"].get<double>());
    const double q = r["quads_per_keyframe"]["median"].get<double>();
    EXPECT_LE(std::abs(q - matched), 0.25 * matched)
        << "tile " << r["tile_size"] << ": " << q << " quads vs " << matched << " for tau "
        << r["matched_to_tau"];
  }
  EXPECT_GE(tileRows, 1);
  for (const char* f : {"index.html", "pareto.png", "sweep.csv"})
    EXPECT_TRUE(std::filesystem::exists(o.outDir + "/" + f)) << f;
}

}  // namespace
}  // namespace hw
