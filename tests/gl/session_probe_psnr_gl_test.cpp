// The probe-psnr predictor on OSMesa probes of the built-in indoor scene: a
// frame at a keyframe's camera has no error (plain and supersampled probes,
// with and without the previous-frame fill), keyframes next to a frame are
// ranked above keyframes far from it, and the previous-frame fill renders
// nothing the constant hole charge does not.
#include <gtest/gtest.h>

#include "gl_fixture.h"
#include "keyframe/geometry_renderer.h"
#include "session/keyframe_planner.h"
#include "scenes/procedural.h"

namespace hw {
namespace {

class ProbePsnrGlTest : public test::GlTest {
 protected:
  static scenes::CameraPath shortPath() {
    scenes::CameraPath p = scenes::defaultIndoorPath();
    p.width = p.height = 128;
    p.frames = 40;
    return p;
  }
};

TEST_F(ProbePsnrGlTest, NoErrorAtAKeyframeAndNearKeyframesRankAboveFarOnes) {
  const scenes::Scene scene = scenes::makeIndoorScene(20000);
  const scenes::CameraPath path = shortPath();
  auto r = keyframe::GeometryRenderer::create(scene);
  ASSERT_TRUE(r.ok()) << r.error().message;
  for (int ss : {1, 2})
    for (bool fill : {false, true}) {
      session::ProbeErrorOptions eo;
      eo.supersample = ss;
      eo.previousFill = fill;
      session::KeyframeProbe probe(**r, [&](int i) { return path.cameraAt(i); }, 64, eo);
      // Frame 10 is keyframe 10's own camera.
      auto at = probe.probeError(10, 20, 10);
      ASSERT_TRUE(at.ok()) << at.error().message;
      EXPECT_EQ(*at, 0.0) << "supersample " << ss << ", fill " << fill;
      EXPECT_EQ(session::probePsnrDb(*at), session::kProbePsnrCap);
      // Frame 20 between its neighbours against keyframes 19 frames away.
      auto nearE = probe.probeError(19, 21, 20);
      auto farE = probe.probeError(1, 39, 20);
      ASSERT_TRUE(nearE.ok() && farE.ok());
      EXPECT_GT(*nearE, 0.0);
      EXPECT_LT(*nearE, *farE) << "supersample " << ss << ", fill " << fill;
      if (!fill) {
        EXPECT_EQ(probe.probesRendered(), 6);  // 10, 20, 19, 21, 1, 39
      } else {
        // The chain renders every frame of the segments it composes.
        // 10, 20, 19, 21, 1, 39 and 2..18 but for 10.
        EXPECT_EQ(probe.probesRendered(), 6 + 16);
      }
    }
}

}  // namespace
}  // namespace hw
