// walk --render-holes: the holes both keyframes miss are drawn by the
// geometry renderer in tight rectangles, so the pixels there equal the
// reference's, the stale pixels drop and the PSNR rises.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "gl_fixture.h"
#include "session/walk.h"
#include "walk_fixture.h"

namespace hw {
namespace {

class WalkHolesTest : public test::GlTest {};

session::WalkOptions options(bool renderHoles) {
  session::WalkOptions wo;
  wo.mode = session::FrameMode::Hybrid;
  wo.saveFrames = false;
  wo.strips = 0;
  wo.progress = false;
  wo.renderHoles = renderHoles;
  return wo;
}

TEST_F(WalkHolesTest, RenderedHolesAreExactAndLiftThePsnr) {
  // Keyframes 10 frames apart at 128 px: the camera turns past them, so
  // frames have border and disocclusion holes.
  test::Indoor in = test::smallIndoor("indoor:20k", 128, 21, 10);
  auto plain = session::runWalk(in.scene, "indoor:20k", in.path, options(false));
  ASSERT_TRUE(plain.ok()) << plain.error().message;
  auto holes = session::runWalk(in.scene, "indoor:20k", in.path, options(true));
  ASSERT_TRUE(holes.ok()) << holes.error().message;
  const auto& pf = plain->report["frames"];
  const auto& hf = holes->report["frames"];
  ASSERT_EQ(pf.size(), hf.size());
  long long stalePlain = 0, staleHoles = 0, rendered = 0;
  int framesWithRects = 0;
  for (std::size_t i = 0; i < pf.size(); ++i) {
    if (pf[i]["mode"] != "warp") continue;
    stalePlain += pf[i]["stale_pixels"].get<long long>();
    staleHoles += hf[i]["stale_pixels"].get<long long>();
    const long long r = hf[i]["holes_rendered"].get<long long>();
    rendered += r;
    EXPECT_GE(hf[i]["hole_rect_pixels"].get<long long>(), r);
    // Hybrid: no budget, every rectangle found is drawn.
    EXPECT_EQ(hf[i]["hole_rects_over_budget"].get<int>(), 0);
    if (hf[i]["hole_rects"].get<int>() == 0) continue;
    ++framesWithRects;
    // Exact pixels replace warped and stale ones: never worse here.
    const double pp = pf[i]["psnr"].is_null() ? 99 : pf[i]["psnr"].get<double>();
    const double hp = hf[i]["psnr"].is_null() ? 99 : hf[i]["psnr"].get<double>();
    EXPECT_GE(hp, pp - 0.5) << "frame " << i;
  }
  EXPECT_GT(framesWithRects, 0);
  EXPECT_GT(rendered, 0);
  EXPECT_EQ(staleHoles, stalePlain - rendered);
  const auto& ps = plain->report["summary"];
  const auto& hs = holes->report["summary"];
  EXPECT_EQ(hs["render_holes"], true);
  EXPECT_EQ(ps["render_holes"], false);
  EXPECT_GT(hs["psnr"]["median"].get<double>(), ps["psnr"]["median"].get<double>() + 1.0);
  // The stale pixels carry a share of the plain walk's error that is gone.
  EXPECT_GT(ps["stale_error_share"]["median"].get<double>(), 0.05);
  EXPECT_LT(hs["stale_error_share"]["median"].get<double>(),
            ps["stale_error_share"]["median"].get<double>());
}

}  // namespace
}  // namespace hw
