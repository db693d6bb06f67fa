// End-to-end hybrid frames on OSMesa: disocclusion behind a box, the built-in
// indoor scene's quality floor, and that the previous-frame fallback fills
// every pixel after the first frame.
#include <gtest/gtest.h>

#include <cmath>

#include "session/walk.h"
#include "core/file_io.h"
#include "core/metrics.h"
#include "gapfill/compose.h"
#include "gl_fixture.h"
#include "keyframe/geometry_renderer.h"
#include "keyframe/lod_builder.h"
#include "scenes/procedural.h"
#include "warp/warper.h"

namespace hw {
namespace {

// A wall at z = −10 and a box in front of it at z ≈ −5.
scenes::Scene boxScene() {
  scenes::Scene s;
  s.name = "box-and-wall";
  s.materials.push_back(scenes::Material{"wall", glm::vec4(0.9f, 0.85f, 0.7f, 1.0f)});
  s.materials.push_back(scenes::Material{"box", glm::vec4(0.2f, 0.4f, 0.9f, 1.0f)});
  scenes::Mesh wall, box;
  wall.material = 0;
  box.material = 1;
  scenes::appendBox(wall, {-40, -20, -10.5f}, {40, 20, -10});
  scenes::appendBox(box, {-0.5f, -0.5f, -5.5f}, {0.5f, 0.5f, -4.5f});
  s.meshes = {wall, box};
  s.computeBounds();
  return s;
}

class HybridTest : public test::GlTest {};

TEST_F(HybridTest, DisocclusionHolesLieBesideTheBoxAndTheOtherKeyframeFillsThem) {
  const scenes::Scene scene = boxScene();
  auto r = keyframe::GeometryRenderer::create(scene);
  ASSERT_TRUE(r.ok()) << r.error().message;
  auto cam = [](double x) {
    return Camera::lookAt({x, 0, 0}, {x, 0, -1}, {0, 1, 0}, glm::radians(60.0), 128, 128, 0.1, 100);
  };
  const Camera ca = cam(-0.6), cb = cam(0.6), cm = cam(-0.2);
  keyframe::Keyframe ka, kb;
  ASSERT_TRUE((*r)->renderKeyframe(ca, ka).ok());
  ASSERT_TRUE((*r)->renderKeyframe(cb, kb).ok());
  keyframe::LodOptions lo;
  auto ma = keyframe::buildQuadMesh(ka, lo), mb = keyframe::buildQuadMesh(kb, lo);
  ASSERT_TRUE(ma.ok() && mb.ok());
  auto w = warp::Warper::create();
  ASSERT_TRUE(w.ok());
  auto sa = (*w)->upload(ka, *ma), sb = (*w)->upload(kb, *mb);
  ASSERT_TRUE(sa.ok() && sb.ok());
  warp::Layer la, lb;
  ASSERT_TRUE((*w)->warp(**sa, cm, la).ok());
  ASSERT_TRUE((*w)->warp(**sb, cm, lb).ok());
  Image<Rgba8> ref;
  ASSERT_TRUE((*r)->renderColour(cm, ref).ok());

  // Box's image at the in-between camera: blue pixels of the reference.
  int bx0 = 128, bx1 = -1;
  for (int y = 0; y < 128; ++y)
    for (int x = 0; x < 128; ++x)
      if (ref(x, y).b > 2 * ref(x, y).r) bx0 = std::min(bx0, x), bx1 = std::max(bx1, x);
  ASSERT_LT(bx0, bx1);
  // Layer A (camera left of the in-between one) misses the wall just right
  // of the box, and the columns at the right image edge that A's field of
  // view did not reach — nothing else.
  int holesA = 0, holesAFar = 0;
  for (int y = 0; y < 128; ++y)
    for (int x = 0; x < 128 - 8; ++x)
      if (!la.coverage(x, y)) {
        ++holesA;
        if (x < bx1 - 1 || x > bx1 + 12) ++holesAFar;
      }
  if (holesAFar) {
    (void)writePng(::testing::TempDir() + "box_layerA.png", maskToImage(la.coverage, {255, 255, 255, 255}, {255, 0, 0, 255}));
    std::fprintf(stderr, "layer A coverage written to %sbox_layerA.png\n", ::testing::TempDir().c_str());
  }
  EXPECT_GT(holesA, 20) << "moving sideways must disocclude wall beside the box";
  EXPECT_EQ(holesAFar, 0) << "holes outside the strip right of the box (box x " << bx0 << ".." << bx1 << ")";

  gapfill::Frame frame;
  gapfill::compose(la, &lb, nullptr, {}, frame);
  EXPECT_LT(frame.holeFractionBefore, 0.002) << "the other keyframe should fill the strip";
  EXPECT_GT(frame.fromBackground, holesA / 2);
  const double p = psnr(frame.colour, ref);
  if (!(p > 30)) {
    (void)writePng(::testing::TempDir() + "box_actual.png", frame.colour);
    (void)writePng(::testing::TempDir() + "box_expected.png", ref);
  }
  EXPECT_GT(p, 30.0);
}

TEST_F(HybridTest, IndoorWalkQualityAndFallback) {
  const scenes::Scene scene = scenes::makeIndoorScene(100000);
  scenes::CameraPath path = scenes::defaultIndoorPath();
  session::WalkOptions o;
  o.lod.tau = 2048;
  o.maxFrames = 21;
  o.progress = false;
  auto res = session::runWalk(scene, "indoor", path, o);
  ASSERT_TRUE(res.ok()) << res.error().message;
  const auto& frames = res->report["frames"];
  ASSERT_EQ(frames.size(), 21u);
  double best = 0;
  int inBetween = 0;
  for (const auto& f : frames) {
    if (f["is_keyframe"].get<bool>()) continue;
    ++inBetween;
    ASSERT_TRUE(f["psnr"].is_number());
    best = std::max(best, f["psnr"].get<double>());
    // After the first frame, the previous frame fills every remaining hole.
    EXPECT_EQ(f["holes_after_fallback"].get<double>(), 0.0) << "frame " << f["index"];
    EXPECT_GT(f["quads"].get<int>(), 0);
  }
  EXPECT_EQ(inBetween, 18);
  EXPECT_GE(best, 30.0);
  const double med = res->report["summary"]["psnr"]["median"].get<double>();
  EXPECT_GE(med, 30.0) << "median in-between PSNR over the first two segments";
}

}  // namespace
}  // namespace hw
