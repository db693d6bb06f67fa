// schedule-study's `auto` predictor on OSMesa: the probe predictors
// (session::kProbePredictors, which need KeyframeProbe::probeError) are
// candidates next to the feature ones; their correlations are in
// schedule.json and their regressor in frames.csv, and the planner gets the
// usable predictor whose fit ranks the fixed walks' frames best.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <set>
#include <string>

#include "bench/schedule_study.h"
#include "gl_fixture.h"
#include "session/keyframe_planner.h"
#include "scenes/procedural.h"

namespace hw {
namespace {

using nlohmann::json;

class ScheduleStudyTest : public test::GlTest {};

TEST_F(ScheduleStudyTest, AutoPredictorWeighsTheProbePredictorsToo) {
  const scenes::Scene scene = scenes::makeIndoorScene(20000);
  scenes::CameraPath path = scenes::defaultIndoorPath();
  path.width = path.height = 128;
  path.frames = 40;
  bench::ScheduleStudyOptions so;
  so.outDir = ::testing::TempDir() + "hw_schedule_study_test";
  so.fixedSpacings = {4, 8, 12};
  so.referenceSpacing = 8;
  so.targets = {20, 30};  // two adaptive walks; no bisection for a keyframe count
  so.autoPredictor = true;
  so.progress = false;
  auto doc = bench::runScheduleStudy(scene, "indoor:20k", path, so);
  ASSERT_TRUE(doc.ok()) << doc.error().message;

  // Every predictor has a row, the probe ones with as many samples as the
  // others (every in-between frame of the fixed walks: probeMse is finite).
  std::set<std::string> names;
  std::size_t samples = 0;
  for (const json& c : (*doc)["correlation"]) {
    names.insert(c["predictor"].get<std::string>());
    if (samples == 0) samples = c["samples"].get<std::size_t>();
    EXPECT_EQ(c["samples"].get<std::size_t>(), samples) << c.dump();
  }
  EXPECT_GT(samples, 0u);
  for (session::Predictor p : session::kAllPredictors)
    EXPECT_EQ(names.count(session::predictorName(p)), 1u) << session::predictorName(p);
  for (session::Predictor p : session::kProbePredictors)
    EXPECT_EQ(names.count(session::predictorName(p)), 1u) << session::predictorName(p);
  EXPECT_EQ(names.size(),
            std::size(session::kAllPredictors) + std::size(session::kProbePredictors));

  // The probe predictors' fits are usable here: PSNR falls as the probe
  // error grows, and their rank correlation is a number.
  for (const json& c : (*doc)["correlation"]) {
    session::Predictor p;
    ASSERT_TRUE(session::parsePredictor(c["predictor"].get<std::string>().c_str(), &p));
    if (!session::isProbePredictor(p)) continue;
    ASSERT_TRUE(c["spearman_pooled"].is_number()) << c.dump();
    ASSERT_TRUE(c["fit"]["slope"].is_number()) << c.dump();
    EXPECT_LT(c["fit"]["slope"].get<double>(), 0.0) << c.dump();
    EXPECT_GT(c["spearman_pooled"].get<double>(), 0.5) << c.dump();
  }

  // auto = the highest pooled Spearman among fits with no rising slope
  // (the first of equals), and its fit.
  const json* best = nullptr;
  for (const json& c : (*doc)["correlation"]) {
    const json& f = c["fit"];
    if (!c["spearman_pooled"].is_number() || !f["slope"].is_number() || !f["slope2"].is_number())
      continue;
    if (!(f["slope"].get<double>() < 0 && f["slope2"].get<double>() <= 0)) continue;
    if (!best || c["spearman_pooled"].get<double>() > (*best)["spearman_pooled"].get<double>())
      best = &c;
  }
  ASSERT_NE(best, nullptr);
  const json& planner = (*doc)["planner"];
  EXPECT_TRUE(planner["predictor_chosen_by_correlation"].get<bool>());
  EXPECT_EQ(planner["predictor"], (*best)["predictor"]);
  EXPECT_EQ(planner["fit"]["slope"].get<double>(), (*best)["fit"]["slope"].get<double>());
  // On this path the probes' own warp ranks the frames best (Spearman 0.97
  // for probe-psnr against 0.94 for holes; probe-psnr+distance's is as high,
  // but its fitted distance term rises, so it is not usable).
  session::Predictor chosen;
  ASSERT_TRUE(session::parsePredictor(planner["predictor"].get<std::string>().c_str(), &chosen));
  EXPECT_TRUE(session::isProbePredictor(chosen)) << planner.dump();

  // The chosen predictor predicts every run's frames (a probe predictor
  // without probeMse would predict NaN, written as null).
  for (const json& r : (*doc)["runs"])
    EXPECT_TRUE(r["predicted_psnr_median"].is_number()) << r.dump();

  std::ifstream frames(so.outDir + "/frames.csv");
  std::string header;
  ASSERT_TRUE(std::getline(frames, header));
  EXPECT_EQ(header.substr(header.rfind(',') + 1), "probe_mse");
}

}  // namespace
}  // namespace hw
