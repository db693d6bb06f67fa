// The probe-psnr predictor without GL: a ray-cast stand-in for
// the geometry renderer draws a textured back wall behind a pillar, and the
// planner warps its low-resolution probes. A frame at a keyframe's camera has
// no error (low-res PSNR at the cap), keyframes next to a frame are ranked
// above keyframes far from it (the far ones disocclude the wall behind the
// pillar), the fit round-trips, the name parses, and a stricter target never
// plans fewer keyframes.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "keyframe/geometry_renderer.h"
#include "session/keyframe_planner.h"

namespace hw::session {
namespace {

using namespace hw::keyframe;  // the renderer interface the probe draws with

// Wall at eye depth 20 (world z = −20) behind two wide pillars at depth 6
// with a gap |x| < 0.5 between them; the cameras look down −z from z = 0, so
// eye depth is −z of the hit. From x = 0 the wall is seen through the gap;
// from |x| >= 2.5 that part of the wall is hidden.
class RayCastRenderer : public GeometryRenderer {
 public:
  Status renderKeyframe(const Camera& camera, Keyframe& out, RenderStats* = nullptr) override {
    ++renders;
    lastWidth = camera.width;
    const int w = camera.width, h = camera.height;
    out.camera = camera;
    out.colour = Image<Rgba8>(w, h);
    out.eyeZ = Image<float>(w, h);
    out.zPrime = Image<double>(w, h);
    out.covered = Image<std::uint8_t>(w, h, 1);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const glm::dvec3 pillar = camera.unproject(x + 0.5, y + 0.5, 6.0);
        const bool onPillar = std::abs(pillar.x) >= 0.5 && std::abs(pillar.x) <= 6.0;
        const double z = onPillar ? 6.0 : 20.0;
        const glm::dvec3 p = onPillar ? pillar : camera.unproject(x + 0.5, y + 0.5, 20.0);
        // Smooth textures (a few probe pixels a period): resampling is not
        // where the error comes from.
        Rgba8 c;
        if (onPillar) {
          c = {200, static_cast<std::uint8_t>(60 + 40 * std::sin(p.y * 1.3)), 40, 255};
        } else {
          const double t = std::sin(p.x * 0.6) * std::cos(p.y * 0.5);
          c = {static_cast<std::uint8_t>(40 + 30 * t), static_cast<std::uint8_t>(120 + 90 * t),
               static_cast<std::uint8_t>(190 - 60 * t), 255};
        }
        out.colour(x, y) = c;
        out.eyeZ(x, y) = static_cast<float>(z);
        out.zPrime(x, y) = zPrimeFromEyeZ(z, camera.nearPlane, camera.farPlane);
      }
    return {};
  }
  Status renderColour(const Camera& camera, Image<Rgba8>& out, RenderStats* s = nullptr) override {
    Keyframe k;
    HW_TRY(renderKeyframe(camera, k, s));
    out = std::move(k.colour);
    return {};
  }
  Status renderColourRect(const Camera&, const PixelRect&, Image<Rgba8>&, RenderStats*) override {
    return makeError("not drawn by the ray-cast test renderer");
  }
  Status renderNear(const Camera&, const glm::dvec3*, int, double, Image<Rgba8>&, Image<float>&,
                    Image<std::uint8_t>&, RenderStats*) override {
    return makeError("not drawn by the ray-cast test renderer");
  }
  std::size_t visibleTriangles(const Camera&) const override { return 0; }
  std::size_t sceneTriangles() const override { return 0; }
  std::size_t sceneClusters() const override { return 0; }
  const RenderOptions& options() const override { return options_; }

  int renders = 0;
  int lastWidth = 0;

 private:
  RenderOptions options_;
};

// 41 frames sliding sideways from x = −5 to 5, looking at the wall.
Camera cameraOf(int i) {
  const glm::dvec3 eye(-5.0 + 0.25 * i, 0.0, 0.0);
  return Camera::lookAt(eye, eye + glm::dvec3(0, 0, -1), {0, 1, 0}, 1.0471975511965976, 64, 64,
                        0.1, 100.0);
}

TEST(KeyframeProbePsnr, AFrameAtAKeyframesCameraHasNoError) {
  RayCastRenderer r;
  ProbeErrorOptions plain;
  plain.supersample = 1;
  KeyframeProbe probe(r, cameraOf, 64, plain);
  auto e = probe.probeError(5, 12, 5);
  ASSERT_TRUE(e.ok()) << e.error().message;
  EXPECT_EQ(*e, 0.0);
  EXPECT_EQ(probePsnrDb(*e), kProbePsnrCap);
  EXPECT_EQ(probe.probesRendered(), 2);  // the frame's probe is keyframe 5's
  // The same with anti-aliased probes (rendered at 2x, box-filtered down).
  RayCastRenderer r2;
  ProbeErrorOptions ss;
  ss.supersample = 2;
  KeyframeProbe probe2(r2, cameraOf, 64, ss);
  auto e2 = probe2.probeError(20, 30, 30);
  ASSERT_TRUE(e2.ok()) << e2.error().message;
  EXPECT_EQ(*e2, 0.0);
  EXPECT_EQ(r2.lastWidth, 128);
}

TEST(KeyframeProbePsnr, RanksNearKeyframesAboveFarOnes) {
  RayCastRenderer r;
  for (int blur : {0, 1}) {
    ProbeErrorOptions eo;
    eo.blurRadius = blur;
    eo.shiftTolerance = 1 - blur;
    eo.supersample = 1;
    eo.previousFill = false;  // holes charged holeMse
    KeyframeProbe probe(r, cameraOf, 64, eo);
    auto nearE = probe.probeError(19, 21, 20);
    auto midE = probe.probeError(12, 28, 20);
    auto farE = probe.probeError(0, 40, 20);
    ASSERT_TRUE(nearE.ok() && midE.ok() && farE.ok());
    EXPECT_GT(*nearE, 0.0) << "blur " << blur;
    // (Not mid < far: from x = ±2 the keyframes see the wall through the gap
    // where, from x = 0, a pillar stands that they do not see — the warp's
    // foreground paints that wall over it, and so does the probe's.)
    EXPECT_LT(*nearE, *midE) << "blur " << blur;
    EXPECT_LT(*nearE, *farE) << "blur " << blur;
    // Through the default fit: the nearer pair is predicted better.
    FrameFeatures fn, ff;
    fn.probeMse = *nearE;
    ff.probeMse = *farE;
    const PsnrFit fit = defaultFit(Predictor::ProbePsnr);
    EXPECT_GT(predictPsnr(fit, fn, Predictor::ProbePsnr), predictPsnr(fit, ff, Predictor::ProbePsnr));
    // Holes charged: a dearer hole raises the far pair's error, whose wall
    // behind the pillar neither keyframe sees.
    ProbeErrorOptions dear = eo;
    dear.holeMse = 4 * eo.holeMse;
    KeyframeProbe probeDear(r, cameraOf, 64, dear);
    auto farDear = probeDear.probeError(0, 40, 20);
    ASSERT_TRUE(farDear.ok());
    EXPECT_GT(*farDear, *farE) << "blur " << blur;
  }
}

TEST(KeyframeProbePsnr, FitRoundTripsAndNameParses) {
  std::vector<FrameFeatures> f;
  std::vector<double> y;
  for (double mse : {0.5, 3.0, 20.0, 150.0, 900.0}) {
    FrameFeatures x;
    x.probeMse = mse;
    f.push_back(x);
    y.push_back(31.0 - 7.5 * std::log10(mse + 1e-2));
  }
  const PsnrFit fit = fitPredictor(f, y, Predictor::ProbePsnr);
  EXPECT_NEAR(fit.intercept, 31.0, 1e-9);
  EXPECT_NEAR(fit.slope, -7.5, 1e-9);
  EXPECT_EQ(fit.slope2, 0.0);
  FrameFeatures unset;  // probeMse NaN: not computed, no prediction
  EXPECT_TRUE(std::isnan(predictPsnr(fit, unset, Predictor::ProbePsnr)));
  Predictor p = Predictor::Holes;
  ASSERT_TRUE(parsePredictor("probe-psnr", &p));
  EXPECT_EQ(p, Predictor::ProbePsnr);
  EXPECT_STREQ(predictorName(p), "probe-psnr");
  EXPECT_FALSE(parsePredictor("probe_psnr", &p));
  EXPECT_NEAR(probePsnrDb(255.0 * 255.0), 0.0, 1e-12);
  EXPECT_NEAR(probePsnrDb(65.025), 30.0, 1e-9);
}

TEST(KeyframeProbePsnr, PlansAndAStricterTargetNeverUsesFewerKeyframes) {
  RayCastRenderer r;
  PlannerOptions opt;
  opt.predictor = Predictor::ProbePsnr;
  opt.criterion = PlanCriterion::WalkMedian;
  opt.minGap = 1;
  opt.maxGap = 10;
  KeyframeProbe probe(r, cameraOf, opt.probeSize, opt.probeError);
  std::size_t last = 0;
  for (double t : {15.0, 25.0, 35.0, 45.0}) {
    opt.targetPsnrDb = t;
    auto plan = planAdaptiveSchedule(probe, 41, opt);
    ASSERT_TRUE(plan.ok()) << plan.error().message;
    ASSERT_GE(plan->keyframes.size(), 2u);
    EXPECT_EQ(plan->keyframes.front(), 0);
    EXPECT_EQ(plan->keyframes.back(), 40);
    EXPECT_GE(plan->keyframes.size(), last) << "target " << t;
    last = plan->keyframes.size();
  }
  EXPECT_EQ(probe.probesRendered(), 41);  // every frame's own probe, once
  EXPECT_GT(last, 5u);                    // the strictest target needs more than the fewest
  opt.probeError.supersample = 0;
  auto bad = planAdaptiveSchedule(r, cameraOf, 41, opt);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("supersample"), std::string::npos);
}

// Refitting the predictor to measured frames (the walk's --calibrate-spacing):
// "measured" PSNRs made from the probe's own regressor with a known line and
// ±0.5 dB of alternating noise give back that line, a 0.5 dB spread and a
// rank correlation near 1; too few frames or a frame outside its keyframes
// are errors that say so.
TEST(KeyframeProbePsnr, CalibrationRecoversTheLineAndItsSpread) {
  RayCastRenderer r;
  KeyframeProbe probe(r, cameraOf, 64);
  std::vector<CalibrationSample> samples;
  for (int g : {4, 8})
    for (int k0 = 0; k0 + g <= 40; k0 += g)
      for (int f = k0 + 1; f < k0 + g; ++f) {
        auto e = probe.probeError(k0, k0 + g, f);
        ASSERT_TRUE(e.ok()) << e.error().message;
        const double noise = (samples.size() % 2 == 0) ? 0.5 : -0.5;
        samples.push_back({k0, k0 + g, f, 30.0 - 6.0 * std::log10(*e + 1e-2) + noise});
      }
  auto c = calibratePredictor(probe, Predictor::ProbePsnr, samples);
  ASSERT_TRUE(c.ok()) << c.error().message;
  EXPECT_EQ(c->samples, static_cast<int>(samples.size()));
  EXPECT_NEAR(c->fit.slope, -6.0, 0.3);
  EXPECT_NEAR(c->fit.intercept, 30.0, 0.6);
  EXPECT_NEAR(c->residualStdDb, 0.5, 0.05);
  EXPECT_GT(c->spearman, 0.9);
  ASSERT_EQ(c->predictedDb.size(), samples.size());
  EXPECT_NEAR(c->predictedDb[0], samples[0].psnrDb, 1.5);
  // Two regressors: distance is a second, independent term here.
  auto c2 = calibratePredictor(probe, Predictor::ProbePsnrDistance, samples);
  ASSERT_TRUE(c2.ok()) << c2.error().message;
  EXPECT_LE(c2->residualStdDb, c->residualStdDb + 0.02);
  // Six regressors (probe error, distance, holes, stretch, disagreement, angle).
  auto c6 = calibratePredictor(probe, Predictor::ProbePsnrFeatures, samples);
  ASSERT_TRUE(c6.ok()) << c6.error().message;
  EXPECT_EQ(c6->fit.more.size(), 4u);
  EXPECT_LE(c6->residualStdDb, c->residualStdDb + 0.05);
  // Too few frames to fit.
  auto few = calibratePredictor(probe, Predictor::ProbePsnr, {samples[0], samples[1]});
  ASSERT_FALSE(few.ok());
  EXPECT_NE(few.error().message.find("expected more than 2"), std::string::npos) << few.error().message;
  auto outside = calibratePredictor(probe, Predictor::ProbePsnr, {{5, 10, 12, 30.0}});
  ASSERT_FALSE(outside.ok());
  EXPECT_NE(outside.error().message.find("k0 < frame < k1"), std::string::npos);
}

}  // namespace
}  // namespace hw::session
