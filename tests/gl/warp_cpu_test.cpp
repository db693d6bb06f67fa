// The CPU warper against the GL warper on rendered keyframes of the indoor
// scene: the same pixels covered (to a few edge pixels), the same colours to
// within rounding, the same large-leaf marks and eye z, for single layers
// and fused pairs, and the keyframe itself back at its own camera.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "core/file_io.h"
#include "core/metrics.h"
#include "gl_fixture.h"
#include "keyframe/geometry_renderer.h"
#include "keyframe/lod_builder.h"
#include "scenes/procedural.h"
#include "warp/cpu_warper.h"
#include "warp/warper.h"

namespace hw {
namespace {

class CpuWarpTest : public test::GlTest {};

struct Rendered {
  keyframe::Keyframe kf;
  keyframe::QuadMesh mesh;
};

Rendered render(keyframe::GeometryRenderer& r, const Camera& cam) {
  Rendered out;
  EXPECT_TRUE(r.renderKeyframe(cam, out.kf).ok());
  keyframe::LodOptions o;
  o.tau = 2048;
  o.planarity = keyframe::Planarity::RegionLocal;
  o.mergeStrips = true;
  keyframe::LodBuilder builder;
  EXPECT_TRUE(builder.build(out.kf, o, &out.mesh).ok());
  return out;
}

// Pixels both layers cover the same way, as a share of all pixels; colour
// PSNR over pixels both cover (1 = covered in any layer).
struct Agreement {
  double coverage = 0, large = 0, colourDb = 0, eyeZ = 0;
};

Agreement compare(const warp::Layer& gl, const warp::Layer& cpu, bool eyeZ) {
  Agreement a;
  const std::size_t n = gl.colour.size();
  EXPECT_EQ(cpu.colour.size(), n);
  Image<std::uint8_t> both(gl.colour.width(), gl.colour.height(), 0);
  std::size_t same = 0, sameLarge = 0, zClose = 0, covered = 0;
  for (std::size_t i = 0; i < n; ++i) {
    same += gl.coverage.data()[i] == cpu.coverage.data()[i];
    sameLarge += gl.largeQuad.data()[i] == cpu.largeQuad.data()[i];
    const bool b = gl.coverage.data()[i] != 0 && cpu.coverage.data()[i] != 0;
    both.data()[i] = b;
    if (b && eyeZ) {
      ++covered;
      const float zg = gl.eyeZ.data()[i], zc = cpu.eyeZ.data()[i];
      zClose += std::fabs(zg - zc) <= 1e-3f * std::fabs(zg);
    }
  }
  a.coverage = double(same) / double(n);
  a.large = double(sameLarge) / double(n);
  a.colourDb = psnr(gl.colour, cpu.colour, both);
  a.eyeZ = covered ? double(zClose) / double(covered) : 1.0;
  return a;
}

void dumpIfLow(double db, const warp::Layer& gl, const warp::Layer& cpu, const std::string& what) {
  if (db >= 40.0) return;
  const std::string base = ::testing::TempDir() + "warp_cpu_" + what;
  (void)writePng(base + "_gl.png", gl.colour);
  (void)writePng(base + "_cpu.png", cpu.colour);
  (void)writePng(base + "_diff.png", diffImage(gl.colour, cpu.colour, 4));
}

TEST_F(CpuWarpTest, LayersMatchTheGlWarper) {
  const scenes::Scene scene = scenes::makeIndoorScene(20000);
  const scenes::CameraPath path = scenes::defaultIndoorPath();
  auto r = keyframe::GeometryRenderer::create(scene);
  ASSERT_TRUE(r.ok()) << r.error().message;
  warp::WarpOptions wo;
  wo.writeEyeZ = true;
  auto glw = warp::Warper::create(wo);
  ASSERT_TRUE(glw.ok()) << glw.error().message;
  for (int threads : {1, 3}) {
    auto cpuw = warp::createCpuWarper(wo, threads);
    ASSERT_TRUE(cpuw.ok()) << cpuw.error().message;
    for (int k0 : {0, 50}) {
      Camera c0 = path.cameraAt(k0), c1 = path.cameraAt(k0 + 10);
      c0.width = c1.width = 320;
      c0.height = c1.height = 240;
      const Rendered a = render(**r, c0), b = render(**r, c1);
      auto ga = (*glw)->upload(a.kf, a.mesh), gb = (*glw)->upload(b.kf, b.mesh);
      auto ca = (*cpuw)->upload(a.kf, a.mesh), cb = (*cpuw)->upload(b.kf, b.mesh);
      ASSERT_TRUE(ga.ok() && gb.ok() && ca.ok() && cb.ok());
      EXPECT_EQ((*ca)->quadCount(), (*ga)->quadCount());
      for (int f : {k0, k0 + 3, k0 + 7}) {
        Camera cam = path.cameraAt(f);
        cam.width = 320;
        cam.height = 240;
        char name[64];
        std::snprintf(name, sizeof name, "t%d_f%d", threads, f);
        const std::string what = name;
        SCOPED_TRACE(what);
        warp::Layer gl1, cpu1;
        warp::WarpStats gs, cs;
        ASSERT_TRUE((*glw)->warp(**ga, cam, gl1, &gs).ok());
        ASSERT_TRUE((*cpuw)->warp(**ca, cam, cpu1, &cs).ok());
        const Agreement one = compare(gl1, cpu1, true);
        EXPECT_GE(one.coverage, 0.995);
        EXPECT_GE(one.large, 0.995);
        EXPECT_GE(one.colourDb, 40.0);
        EXPECT_GE(one.eyeZ, 0.995);
        EXPECT_NEAR(cs.uncovered, gs.uncovered, 0.005 * 320 * 240);
        dumpIfLow(one.colourDb, gl1, cpu1, what + "_one");

        warp::Layer gl2, cpu2;
        warp::PairStats gp, cp;
        ASSERT_TRUE((*glw)->warpPair(**ga, gb->get(), cam, gl2, true, &gp).ok());
        ASSERT_TRUE((*cpuw)->warpPair(**ca, cb->get(), cam, cpu2, true, &cp).ok());
        const Agreement two = compare(gl2, cpu2, true);
        EXPECT_GE(two.coverage, 0.995);
        EXPECT_GE(two.colourDb, 40.0);
        EXPECT_EQ(cp.backgroundDrawn, gp.backgroundDrawn);
        EXPECT_NEAR(cp.uncovered, gp.uncovered, 0.005 * 320 * 240);
        EXPECT_NEAR(cp.fromBackground, gp.fromBackground, 0.005 * 320 * 240);
        EXPECT_NEAR(cp.uncoveredByForeground, gp.uncoveredByForeground, 0.005 * 320 * 240);
        dumpIfLow(two.colourDb, gl2, cpu2, what + "_pair");
        std::printf("%s: coverage %.5f, large %.5f, colour %.1f dB, eye z %.5f; pair %.5f, %.1f dB\n",
                    what.c_str(), one.coverage, one.large, one.colourDb, one.eyeZ, two.coverage,
                    two.colourDb);
      }
    }
  }
}

TEST_F(CpuWarpTest, KeyframeComesBackAtItsOwnCamera) {
  const scenes::Scene scene = scenes::makeIndoorScene(20000);
  auto r = keyframe::GeometryRenderer::create(scene);
  ASSERT_TRUE(r.ok()) << r.error().message;
  Camera cam = scenes::defaultIndoorPath().cameraAt(30);
  cam.width = 256;
  cam.height = 192;
  const Rendered a = render(**r, cam);
  auto w = warp::createCpuWarper({}, 2);
  ASSERT_TRUE(w.ok());
  auto src = (*w)->upload(a.kf, a.mesh);
  ASSERT_TRUE(src.ok());
  warp::Layer layer;
  ASSERT_TRUE((*w)->warp(**src, cam, layer).ok());
  long long missed = 0;
  for (std::size_t i = 0; i < a.kf.covered.size(); ++i)
    missed += layer.coverage.data()[i] == 0;  // the sky backdrop covers the empty pixels
  EXPECT_EQ(missed, 0);
  EXPECT_GE(psnr(layer.colour, a.kf.colour), 50.0);
}

// Threads split the set-up and the rows (cut where the work is): the pixels
// and the counts must not depend on how many there are, and the counts must
// be those of the layer written. A camera turned away from the keyframes'
// (quads off screen, some behind the eye) takes the paths that skip or clip
// quads.
TEST_F(CpuWarpTest, PixelsDoNotDependOnThreads) {
  const scenes::Scene scene = scenes::makeIndoorScene(20000);
  const scenes::CameraPath path = scenes::defaultIndoorPath();
  auto r = keyframe::GeometryRenderer::create(scene);
  ASSERT_TRUE(r.ok()) << r.error().message;
  Camera c0 = path.cameraAt(20), c1 = path.cameraAt(30);
  c0.width = c1.width = 256;
  c0.height = c1.height = 192;
  const Rendered a = render(**r, c0), b = render(**r, c1);
  Camera near = path.cameraAt(24);
  near.width = 256;
  near.height = 192;
  // Turned 60 degrees: the keyframes' quads partly off screen, partly behind.
  const Camera away = Camera::lookAt(c0.eye, c0.eye + 0.5 * c0.forward + 0.866 * c0.right, c0.up,
                                     c0.fovYRadians, 256, 192, c0.nearPlane, c0.farPlane);
  warp::WarpOptions wo;
  wo.writeEyeZ = true;
  for (const Camera& cam : {near, away}) {
    warp::Layer first;
    warp::PairStats firstStats;
    for (int threads : {1, 2, 3, 7}) {
      SCOPED_TRACE(std::to_string(threads) + " threads");
      auto w = warp::createCpuWarper(wo, threads);
      ASSERT_TRUE(w.ok());
      auto sa = (*w)->upload(a.kf, a.mesh), sb = (*w)->upload(b.kf, b.mesh);
      ASSERT_TRUE(sa.ok() && sb.ok());
      warp::Layer layer;
      warp::PairStats st;
      ASSERT_TRUE((*w)->warpPair(**sa, sb->get(), cam, layer, false, &st).ok());
      long long fromBg = 0, empty = 0, fromFg = 0;
      for (std::size_t i = 0; i < layer.coverage.size(); ++i) {
        fromFg += layer.coverage.data()[i] == 1;
        fromBg += layer.coverage.data()[i] == 2;
        empty += layer.coverage.data()[i] == 0;
      }
      EXPECT_GT(fromFg, 0);
      EXPECT_EQ(st.fromBackground, fromBg);
      EXPECT_EQ(st.uncovered, empty);
      EXPECT_EQ(st.uncoveredByForeground, fromBg + empty);
      if (threads == 1) {
        first = layer;
        firstStats = st;
        continue;
      }
      EXPECT_EQ(layer.colour.pixels(), first.colour.pixels());
      EXPECT_EQ(layer.coverage.pixels(), first.coverage.pixels());
      EXPECT_EQ(layer.largeQuad.pixels(), first.largeQuad.pixels());
      EXPECT_EQ(layer.eyeZ.pixels(), first.eyeZ.pixels());
      EXPECT_EQ(st.uncoveredByForeground, firstStats.uncoveredByForeground);
    }
  }
}

TEST(CpuWarper, RefusesWhatItCannotDraw) {
  warp::WarpOptions o;
  o.subdivision = warp::Subdivision::Uniform;
  EXPECT_FALSE(warp::createCpuWarper(o).ok());
  o = {};
  o.primitives = warp::Primitives::Points;
  EXPECT_FALSE(warp::createCpuWarper(o).ok());
  o = {};
  o.texcoords = warp::TexcoordMode::Affine;
  EXPECT_FALSE(warp::createCpuWarper(o).ok());
  EXPECT_FALSE(warp::createCpuWarper({}, 0).ok());
  EXPECT_TRUE(warp::createCpuWarper({}, 2).ok());
}

}  // namespace
}  // namespace hw
