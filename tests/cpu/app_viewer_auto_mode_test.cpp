// The viewer's --mode auto (app/viewer_auto_mode.h), fed made-up frame costs:
// a scene that draws far faster than a warp goes to geometry at a choice; a
// heavy one stays hybrid, measuring the geometry with probes at the first
// choices (and, with keyframes from the worker, every fourth choice after).
#include <gtest/gtest.h>

#include <vector>

#include "app/viewer_auto_mode.h"

namespace hw::app {
namespace {

using session::FrameKind;

struct Session {
  std::vector<long> probes;
  long switchedToGeometryAt = -1;
  ViewerAutoMode mode;
};

// `frames` frames starting hybrid: warped frames cost warpMs of work, probes
// and geometry frames geometryMs; no keyframe is rendered in the frame.
void play(Session& r, int frames, double warpMs, double geometryMs, bool probeRegularly) {
  bool hybrid = true;
  for (long f = 0; f < frames; ++f) {
    const ViewerAutoMode::Step s = r.mode.step(hybrid, 1000, f, probeRegularly);
    if (s.switched && !s.hybrid && r.switchedToGeometryAt < 0) r.switchedToGeometryAt = f;
    hybrid = s.hybrid;
    if (s.probe) r.probes.push_back(f);
    const bool geometry = !hybrid || s.probe;
    if (f > 0)  // the first frame is the load
      r.mode.record(geometry ? FrameKind::Geometry : FrameKind::Warp,
                    geometry ? geometryMs : warpMs, geometryMs, 1000, false, 0, 0);
  }
}

TEST(ViewerAutoMode, CheapGeometryIsChosenAtAChoice) {
  Session r;
  play(r, 60, 5.0, 0.5, false);
  // Geometry is unknown until the first probe (frame 9), so the earliest
  // switch is at a later frame; the first probes come at choices (every 10th frame).
  ASSERT_FALSE(r.probes.empty());
  EXPECT_EQ(r.probes.front(), 9);
  EXPECT_GT(r.switchedToGeometryAt, 9);
  EXPECT_LT(r.switchedToGeometryAt, 60);
  EXPECT_EQ(r.mode.firstGeometryChoice(), r.switchedToGeometryAt);
  EXPECT_GE(r.mode.switches(), 1);
}

TEST(ViewerAutoMode, HeavyGeometryStaysHybridWithProbes) {
  Session plain;
  play(plain, 120, 3.0, 100.0, false);
  EXPECT_EQ(plain.switchedToGeometryAt, -1);
  EXPECT_EQ(plain.mode.firstGeometryChoice(), -1);
  EXPECT_EQ(plain.mode.switches(), 0);
  // Three probes until three geometry renders are known, then none.
  EXPECT_EQ(plain.probes, (std::vector<long>{9, 19, 29}));
  EXPECT_NEAR(plain.mode.geometryMs(), 100.0, 1e-9);

  Session worker;  // keyframes from the worker: and every fourth choice after
  play(worker, 120, 3.0, 100.0, true);
  EXPECT_EQ(worker.switchedToGeometryAt, -1);
  EXPECT_EQ(worker.probes, (std::vector<long>{9, 19, 29, 69, 109}));
}

}  // namespace
}  // namespace hw::app
