// The walk's PSNR on the pixels large leaves drew (psnr_large_quads,
// large_quad_pixels): the metric is core's masked PSNR of the displayed frame
// over a mask rebuilt here from the layers warped one at a time, whether the
// walk fuses the layers or not; null when no leaf is larger than a cell.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "session/walk.h"
#include "core/file_io.h"
#include "core/metrics.h"
#include "gapfill/compose.h"
#include "gl_fixture.h"
#include "keyframe/geometry_renderer.h"
#include "keyframe/lod_builder.h"
#include "walk_fixture.h"
#include "warp/warper.h"

namespace hw {
namespace {

class WalkLargeQuadsTest : public test::GlTest {};

constexpr int kSize = 128, kFrames = 9, kEvery = 4;

session::WalkOptions options(const std::string& out) {
  session::WalkOptions wo;
  wo.lod.tau = 2048;
  wo.lod.planarity = keyframe::Planarity::RegionLocal;
  wo.lod.mergeStrips = true;
  wo.progress = false;
  wo.strips = 0;
  wo.outDir = out;
  wo.saveFrames = true;
  return wo;
}

TEST_F(WalkLargeQuadsTest, MetricIsMaskedPsnrOverTheLargeLeafPixels) {
  test::Indoor in = test::smallIndoor("indoor:20k", kSize, kFrames, kEvery);
  const std::string dir = ::testing::TempDir() + "walk_large_quads";
  const session::WalkOptions wo = options(dir);
  auto fused = session::runWalk(in.scene, "indoor:20k", in.path, wo);
  ASSERT_TRUE(fused.ok()) << fused.error().message;
  session::WalkOptions so = options(dir + "_separate");
  so.inBetween.fusedLayers = false;
  auto separate = session::runWalk(in.scene, "indoor:20k", in.path, so);
  ASSERT_TRUE(separate.ok()) << separate.error().message;

  // The independent mask: each keyframe rendered and meshed as the walk does,
  // each layer warped alone, the overlay rule (foreground where it covers).
  auto r = keyframe::GeometryRenderer::create(in.scene);
  ASSERT_TRUE(r.ok()) << r.error().message;
  auto w = test::warperOfWalk(fused->report, wo.warp);
  ASSERT_TRUE(w.ok()) << w.error().message;
  const auto& frames = fused->report["frames"];
  const auto& framesSep = separate->report["frames"];
  ASSERT_EQ(frames.size(), static_cast<std::size_t>(kFrames));
  int checked = 0;
  for (int i = 0; i < kFrames; ++i) {
    const auto& f = frames[static_cast<std::size_t>(i)];
    if (f["is_keyframe"].get<bool>()) continue;
    const int k0 = f["keyframes"][0].get<int>(), k1 = f["keyframes"][1].get<int>();
    const int fgFrame = f["foreground"].get<int>();
    const int bgFrame = fgFrame == k0 ? k1 : k0;
    keyframe::Keyframe kf[2];
    std::unique_ptr<warp::WarpSource> src[2];
    for (int k = 0; k < 2; ++k) {
      ASSERT_TRUE((*r)->renderKeyframe(in.path.cameraAt(k == 0 ? fgFrame : bgFrame), kf[k]).ok());
      auto mesh = keyframe::buildQuadMesh(kf[k], wo.lod);
      ASSERT_TRUE(mesh.ok());
      auto s = (*w)->upload(kf[k], *mesh);
      ASSERT_TRUE(s.ok()) << s.error().message;
      src[k] = std::move(*s);
    }
    const Camera cam = in.path.cameraAt(i);
    warp::Layer fg, bg;
    ASSERT_TRUE((*w)->warp(*src[0], cam, fg).ok());
    ASSERT_TRUE((*w)->warp(*src[1], cam, bg).ok());
    Image<std::uint8_t> mask(cam.width, cam.height);
    int count = 0;
    for (std::size_t p = 0; p < mask.size(); ++p) {
      mask.data()[p] = fg.coverage.data()[p] ? fg.largeQuad.data()[p]
                                             : bg.coverage.data()[p] ? bg.largeQuad.data()[p] : 0;
      count += mask.data()[p];
    }
    char name[32];
    std::snprintf(name, sizeof name, "/frames/%04d.png", i);
    auto shown = readPng(dir + name);
    ASSERT_TRUE(shown.ok()) << shown.error().message;
    Image<Rgba8> reference;
    ASSERT_TRUE((*r)->renderColour(cam, reference).ok());
    EXPECT_GT(count, 0) << "frame " << i;
    EXPECT_EQ(f["large_quad_pixels"].get<long long>(), count) << "frame " << i;
    ASSERT_TRUE(f["psnr_large_quads"].is_number()) << "frame " << i;
    const double expected = psnrCapped(*shown, reference, mask);
    EXPECT_DOUBLE_EQ(f["psnr_large_quads"].get<double>(), expected) << "frame " << i;
    // Not the whole frame's PSNR (the mask is a part of the frame).
    EXPECT_LT(count, cam.width * cam.height) << "frame " << i;
    // The separate layers give the same frame, so the same pixels and value.
    const auto& g = framesSep[static_cast<std::size_t>(i)];
    EXPECT_EQ(g["large_quad_pixels"], f["large_quad_pixels"]) << "frame " << i;
    EXPECT_EQ(g["psnr_large_quads"], f["psnr_large_quads"]) << "frame " << i;
    ++checked;
  }
  EXPECT_EQ(checked, kFrames - 3);
  const auto& s = fused->report["summary"];
  EXPECT_EQ(s["psnr_large_quads"]["count"].get<int>(), checked);
  EXPECT_EQ(s["large_quad_pixels"]["count"].get<int>(), checked);
}

TEST_F(WalkLargeQuadsTest, NullWithoutLargeLeavesOrWithTheDepthMerge) {
  test::Indoor in = test::smallIndoor("indoor:20k", kSize, 5, kEvery);
  session::WalkOptions wo = options("");
  wo.saveFrames = false;
  wo.warp.subdivideCellPx = 256;  // every leaf fits in one cell
  auto none = session::runWalk(in.scene, "indoor:20k", in.path, wo);
  ASSERT_TRUE(none.ok()) << none.error().message;
  wo.warp.subdivideCellPx = 16;
  wo.inBetween.compose.mode = gapfill::ComposeMode::DepthMerge;
  auto merged = session::runWalk(in.scene, "indoor:20k", in.path, wo);
  ASSERT_TRUE(merged.ok()) << merged.error().message;
  int inBetween = 0;
  for (std::size_t i = 0; i < 5; ++i) {
    const auto& f = none->report["frames"][i];
    const auto& g = merged->report["frames"][i];
    if (f["is_keyframe"].get<bool>()) continue;
    ++inBetween;
    EXPECT_EQ(f["large_quad_pixels"].get<long long>(), 0) << i;
    EXPECT_TRUE(f["psnr_large_quads"].is_null()) << i;
    EXPECT_TRUE(f["psnr"].is_number()) << i;
    EXPECT_TRUE(g["large_quad_pixels"].is_null()) << i;
    EXPECT_TRUE(g["psnr_large_quads"].is_null()) << i;
  }
  EXPECT_EQ(inBetween, 3);
  EXPECT_EQ(none->report["summary"]["psnr_large_quads"]["count"].get<int>(), 0);
  EXPECT_TRUE(none->report["summary"]["psnr_large_quads"]["median"].is_null());
  EXPECT_EQ(none->report["summary"]["large_quad_pixels"]["count"].get<int>(), 3);
  EXPECT_EQ(merged->report["summary"]["large_quad_pixels"]["count"].get<int>(), 0);
}

}  // namespace
}  // namespace hw
