#include "bench/stress.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <optional>
#include <sstream>

#include "report/html_report.h"
#include "core/json_util.h"
#include "report/plot.h"
#include "core/file_io.h"
#include "core/machine.h"
#include "core/metrics.h"
#include "core/timer.h"
#include "gapfill/compose.h"
#include "keyframe/geometry_renderer.h"
#include "keyframe/lod_builder.h"
#include "scenes/procedural.h"
#include "warp/warper.h"

namespace hw::bench {

using namespace report;  // plots, tables and HTML of the studies

namespace {

using nlohmann::json;

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kPi = 3.14159265358979323846;
constexpr DepthMode kModes[3] = {DepthMode::Fixed24, DepthMode::Float32, DepthMode::Float32Reversed};
constexpr double kRatios[4] = {10.0, 1e3, 1e5, 1e6};
constexpr double kAngles[5] = {0.0, 30.0, 60.0, 75.0, 85.0};
constexpr double kPlaneNear = 0.1;

std::string ratioLabel(double r) {
  const double l = std::log10(r);
  if (std::abs(l - std::round(l)) < 1e-9) return "1e" + std::to_string(int(std::lround(l)));
  return fmt(r, 0);
}

// ---- scenes -----------------------------------------------------------------

// 64×64 texels, 8×8 cells of distinct pseudo-random colours (fixed hash), so
// that a misregistered warp shows up in PSNR.
scenes::Texture cellTexture() {
  scenes::Texture t;
  t.name = "cells";
  t.image.resize(64, 64);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      std::uint32_t h = static_cast<std::uint32_t>((x / 8) * 73856093u ^ (y / 8) * 19349663u);
      h ^= h >> 13;
      h *= 0x5bd1e995u;
      h ^= h >> 15;
      const auto c = [&](int s) { return static_cast<std::uint8_t>(40 + ((h >> s) & 0xFF) * 180 / 255); };
      t.image(x, y) = Rgba8{c(0), c(8), c(16), 255};
    }
  return t;
}

// A square in the plane y = 0, centred at the origin, cells×cells quads
// (triangle edges cross the image, as in real scenes), two-sided, with
// uv = world / texWorld.
void addGroundGrid(scenes::Mesh& m, double halfSize, int cells, double texWorld) {
  const auto base = static_cast<std::uint32_t>(m.vertices.size());
  for (int j = 0; j <= cells; ++j)
    for (int i = 0; i <= cells; ++i) {
      const double x = -halfSize + 2.0 * halfSize * i / cells;
      const double z = -halfSize + 2.0 * halfSize * j / cells;
      m.vertices.push_back(scenes::Vertex{glm::vec3(float(x), 0.0f, float(z)), glm::vec3(0, 1, 0),
                                          glm::vec2(float(x / texWorld), float(z / texWorld))});
    }
  const auto at = [&](int i, int j) { return base + static_cast<std::uint32_t>(j * (cells + 1) + i); };
  for (int j = 0; j < cells; ++j)
    for (int i = 0; i < cells; ++i)
      m.indices.insert(m.indices.end(), {at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i, j),
                                         at(i + 1, j + 1), at(i + 1, j)});
}

scenes::Scene planeScene(double farPlane, double texWorld) {
  scenes::Scene s;
  s.name = "stress-plane";
  s.textures.push_back(cellTexture());
  scenes::Material mat;
  mat.name = "cells";
  mat.texture = 0;
  mat.twoSided = true;
  s.materials.push_back(mat);
  scenes::Mesh m;
  m.name = "plane";
  addGroundGrid(m, 2.0 * farPlane, 64, texWorld);
  s.meshes.push_back(std::move(m));
  s.computeBounds();
  return s;
}

// Small scenes of their own for the cases that need controlled geometry.
// Materials: 0 textured ground, 1 red (behind-eye marker), 2 blue box
// (one-sided), 3 green box (two-sided).
scenes::Scene caseScene(bool ground, bool redWall, bool blueBox, bool greenBoxTwoSided) {
  scenes::Scene s;
  s.name = "stress-case";
  s.textures.push_back(cellTexture());
  scenes::Material g;
  g.name = "ground";
  g.texture = 0;
  g.twoSided = true;
  scenes::Material red{"red", glm::vec4(1.0f, 0.0f, 0.0f, 1.0f)};
  red.unlit = true;
  red.twoSided = true;
  scenes::Material blue{"blue", glm::vec4(0.2f, 0.4f, 0.9f, 1.0f)};
  blue.texture = 0;
  scenes::Material green{"green", glm::vec4(0.3f, 0.9f, 0.4f, 1.0f)};
  green.texture = 0;
  green.twoSided = true;
  s.materials = {g, red, blue, green};
  if (ground) {
    scenes::Mesh m;
    m.name = "ground";
    m.material = 0;
    addGroundGrid(m, 60.0, 16, 2.0);
    s.meshes.push_back(std::move(m));
  }
  if (redWall) {
    // A wall in z = −10 facing +z, 100 × 100, as a 4×4 grid.
    scenes::Mesh m;
    m.name = "red-wall";
    m.material = 1;
    for (int j = 0; j <= 4; ++j)
      for (int i = 0; i <= 4; ++i)
        m.vertices.push_back(scenes::Vertex{glm::vec3(-50.0f + 25.0f * i, -50.0f + 25.0f * j, -10.0f),
                                            glm::vec3(0, 0, 1), glm::vec2(0)});
    for (std::uint32_t j = 0; j < 4; ++j)
      for (std::uint32_t i = 0; i < 4; ++i) {
        const std::uint32_t a = j * 5 + i;
        m.indices.insert(m.indices.end(), {a, a + 1, a + 6, a, a + 6, a + 5});
      }
    s.meshes.push_back(std::move(m));
  }
  if (blueBox) {
    scenes::Mesh m;
    m.name = "blue-box";
    m.material = 2;
    scenes::appendBox(m, {-1, 0, -6}, {1, 2, -4});
    s.meshes.push_back(std::move(m));
  }
  if (greenBoxTwoSided) {
    scenes::Mesh m;
    m.name = "green-box";
    m.material = 3;
    scenes::appendBox(m, {2, 0, -7}, {5, 3, -4});
    s.meshes.push_back(std::move(m));
  }
  s.computeBounds();
  return s;
}

// ---- small helpers -----------------------------------------------------------

template <class T>
long long countNonFinite(const Image<T>& img) {
  long long n = 0;
  for (const T& v : img.pixels())
    if (!std::isfinite(static_cast<double>(v))) ++n;
  return n;
}

// Non-finite values in a quad mesh, and corners with eyeZ <= 0 (both bugs).
long long countBadCorners(const keyframe::QuadMesh& mesh) {
  long long n = 0;
  for (const keyframe::Quad& q : mesh.quads)
    for (int i = 0; i < 4; ++i) {
      const bool finite = std::isfinite(q.world[i].x) && std::isfinite(q.world[i].y) &&
                          std::isfinite(q.world[i].z) && std::isfinite(q.eyeZ[i]) &&
                          std::isfinite(q.pixel[i].x) && std::isfinite(q.pixel[i].y);
      if (!finite || !(q.eyeZ[i] > 0)) ++n;
    }
  return n;
}

// Camera turned about the world up axis by `yawDeg` (positive: to the left).
Camera yawed(const Camera& c, double yawDeg) {
  const double a = yawDeg * kPi / 180.0, ca = std::cos(a), sa = std::sin(a);
  const glm::dvec3 f = c.forward;
  const glm::dvec3 g(ca * f.x + sa * f.z, f.y, -sa * f.x + ca * f.z);
  return Camera::lookAt(c.eye, c.eye + g, {0, 1, 0}, c.fovYRadians, c.width, c.height,
                        c.nearPlane, c.farPlane);
}

Camera moved(const Camera& c, const glm::dvec3& d) {
  Camera o = c;
  o.eye += d;
  return o;
}

Camera sized(Camera c, int w, int h) {
  c.width = w;
  c.height = h;
  return c;
}

// The indoor scene and walk: content with textures, edges and depth range.
const scenes::Scene& indoorScene() {
  static const scenes::Scene s = scenes::makeIndoorScene(5000);
  return s;
}
Camera indoorCamera(int frame, int size) {
  static const scenes::CameraPath path = scenes::defaultIndoorPath();
  return sized(path.cameraAt(frame), size, size);
}

// ---- the hybrid pipeline on three cameras -------------------------------------

// What one in-between frame went through: keyframes A and B, their meshes,
// the two warped layers (foreground first), the composed frame (previous
// frame = keyframe A's image, as for the first in-between frame of a walk)
// and the geometry reference.
struct Hybrid {
  keyframe::Keyframe ka, kb;
  keyframe::QuadMesh ma, mb;
  warp::Layer fg, bg;
  int fgPick = 0;
  gapfill::Frame frame;
  keyframe::Keyframe truth;  // geometry render at the in-between camera
  const Image<Rgba8>& reference() const { return truth.colour; }
  long long nonFinite = 0;
  long long badCorners = 0;
  long long behindEye = 0;  // layer pixels covered by a quad with eye z < n/2
  std::string failedStage;
};

Status runHybrid(const scenes::Scene& scene, const Camera& a, const Camera& b, const Camera& m,
                 DepthMode mode, Hybrid& h) {
  keyframe::RenderOptions ro;
  ro.depthMode = mode;
  h.failedStage = "renderer";
  auto renderer = keyframe::GeometryRenderer::create(scene, ro);
  if (!renderer) return renderer.error();
  h.failedStage = "keyframe A";
  HW_TRY((*renderer)->renderKeyframe(a, h.ka));
  h.failedStage = "keyframe B";
  HW_TRY((*renderer)->renderKeyframe(b, h.kb));
  for (const keyframe::Keyframe* k : {&h.ka, &h.kb})
    h.nonFinite += countNonFinite(k->zPrime) + countNonFinite(k->eyeZ);
  keyframe::LodBuilder builder;
  h.failedStage = "LOD A";
  HW_TRY(builder.build(h.ka, keyframe::LodOptions{}, &h.ma));
  h.failedStage = "LOD B";
  HW_TRY(builder.build(h.kb, keyframe::LodOptions{}, &h.mb));
  h.badCorners = countBadCorners(h.ma) + countBadCorners(h.mb);
  h.failedStage = "warper";
  auto warper = warp::Warper::create();
  if (!warper) return warper.error();
  auto sa = (*warper)->upload(h.ka, h.ma);
  if (!sa) return sa.error();
  auto sb = (*warper)->upload(h.kb, h.mb);
  if (!sb) return sb.error();
  h.fgPick = gapfill::chooseForeground(m.eye, a.eye, b.eye);
  h.failedStage = "warp";
  HW_TRY((*warper)->warp(h.fgPick == 0 ? **sa : **sb, m, h.fg));
  HW_TRY((*warper)->warp(h.fgPick == 0 ? **sb : **sa, m, h.bg));
  for (const warp::Layer* l : {&h.fg, &h.bg}) {
    h.nonFinite += countNonFinite(l->eyeZ);
    for (std::size_t i = 0; i < l->coverage.size(); ++i) {
      const float z = l->eyeZ.pixels()[i];
      if (l->coverage.pixels()[i] && z != warp::kSkyEyeZ && !(z >= 0.5 * m.nearPlane)) ++h.behindEye;
    }
  }
  h.failedStage = "compose";
  gapfill::Frame previous;
  if (h.ka.colour.width() == m.width && h.ka.colour.height() == m.height) {
    previous.colour = h.ka.colour;
    previous.valid.resize(m.width, m.height, 1);
    previous.holesBefore.resize(m.width, m.height, 0);
  }
  gapfill::compose(h.fg, &h.bg, previous.colour.empty() ? nullptr : &previous,
                   gapfill::ComposeOptions{}, h.frame);
  h.failedStage = "reference";
  HW_TRY((*renderer)->renderKeyframe(m, h.truth));
  h.failedStage.clear();
  return {};
}

// The common verdict: valid frame (no NaN/Inf, no corner behind its eye, no
// fragment from behind the eye, every hole filled) or a clear error.
struct CaseSpec {
  std::string name;
  const scenes::Scene* scene = nullptr;
  Camera a, b, m;
  double minPsnr = -1.0;     // dB; < 0: not checked
  bool expectError = false;  // passes only with a clear error
};

StressCaseRow runCase(const CaseSpec& spec, const StressCaseOptions& opt,
                      const std::function<std::string(const Hybrid&)>& extraCheck = {}) {
  StressCaseRow row;
  row.name = spec.name;
  row.expectError = spec.expectError;
  row.psnr = kNan;
  Stopwatch sw;
  Hybrid h;
  const Status st = runHybrid(*spec.scene, spec.a, spec.b, spec.m, opt.depthMode, h);
  row.nanCount = h.nonFinite + h.badCorners;
  if (!st.ok()) {
    row.ms = sw.ms();
    row.message = "error at " + h.failedStage + ": " + st.error().message;
    // A clear error: a non-empty message, and nothing non-finite produced.
    row.ok = spec.expectError && !st.error().message.empty() && row.nanCount == 0;
    if (!spec.expectError) row.message = "unexpected " + row.message;
    return row;
  }
  row.ms = sw.ms();
  if (!opt.imageDir.empty() && std::size_t(spec.m.width) * spec.m.height <= 1024u * 1024u) {
    const std::string base = opt.imageDir + "/" + stressCaseSlug(spec.name);
    // Images are a by-product: a write error is reported but does not fail the case.
    for (const auto& [suffix, img] : {std::pair<const char*, const Image<Rgba8>*>{"_frame", &h.frame.colour},
                                      {"_reference", &h.reference()}, {"_layer", &h.fg.colour}}) {
      const Status ws = writePng(base + suffix + ".png", *img);
      if (!ws.ok()) row.message += "(image not written: " + ws.error().message + ") ";
    }
  }
  row.holes = h.frame.holeFractionBefore;
  row.psnr = psnrCapped(h.frame.colour, h.reference());
  std::vector<std::string> problems;
  if (spec.expectError) problems.push_back("expected an error, got a frame");
  if (h.nonFinite) problems.push_back(std::to_string(h.nonFinite) + " non-finite depth values");
  if (h.badCorners) problems.push_back(std::to_string(h.badCorners) + " non-finite or behind-eye corners");
  if (h.behindEye) problems.push_back(std::to_string(h.behindEye) + " layer pixels from behind the eye");
  if (h.frame.unfilled) problems.push_back(std::to_string(h.frame.unfilled) + " pixels unfilled after fallback");
  if (spec.minPsnr >= 0 && !(row.psnr >= spec.minPsnr))
    problems.push_back("PSNR " + fmt(row.psnr) + " dB < " + fmt(spec.minPsnr) + " dB");
  if (extraCheck) {
    const std::string e = extraCheck(h);
    if (!e.empty()) problems.push_back(e);
  }
  std::ostringstream msg;
  msg << row.message << spec.a.width << "x" << spec.a.height << ", quads " << h.ma.stats.quads << "+"
      << h.mb.stats.quads << ", clamped corners " << h.ma.stats.clampedCorners + h.mb.stats.clampedCorners
      << ", foreground " << (h.fgPick == 0 ? "A" : "B");
  if (spec.minPsnr >= 0) msg << ", PSNR floor " << fmt(spec.minPsnr, 0) << " dB";
  for (const std::string& p : problems) msg << "; FAIL: " << p;
  row.message = msg.str();
  row.ok = problems.empty();
  return row;
}

int caseSize(const StressCaseOptions& o) { return o.quick ? 128 : 512; }

// Pixels of `img` that are strongly red (the behind-eye marker material).
long long redPixels(const Image<Rgba8>& img) {
  long long n = 0;
  for (const Rgba8& c : img.pixels())
    if (c.r > 200 && c.g < 60 && c.b < 60) ++n;
  return n;
}

std::vector<StressCase> makeCases() {
  std::vector<StressCase> cs;
  auto add = [&](std::string name, bool slow, std::function<StressCaseRow(const StressCaseOptions&)> f) {
    cs.push_back(StressCase{std::move(name), slow, std::move(f)});
  };

  add("in-between eye = keyframe A eye", false, [](const StressCaseOptions& o) {
    const int s = caseSize(o);
    CaseSpec c{"in-between eye = keyframe A eye", &indoorScene(), indoorCamera(0, s),
               indoorCamera(10, s), indoorCamera(0, s), 30.0};
    return runCase(c, o);
  });
  add("both keyframes at one eye (same view)", false, [](const StressCaseOptions& o) {
    const int s = caseSize(o);
    const Camera a = indoorCamera(0, s);
    CaseSpec c{"both keyframes at one eye (same view)", &indoorScene(), a, a,
               moved(a, 0.05 * a.right), 20.0};
    return runCase(c, o);
  });
  add("both keyframes at one eye (turned 20 deg)", false, [](const StressCaseOptions& o) {
    const int s = caseSize(o);
    const Camera a = indoorCamera(0, s);
    CaseSpec c{"both keyframes at one eye (turned 20 deg)", &indoorScene(), a, yawed(a, 20.0),
               yawed(a, 10.0), 25.0};
    return runCase(c, o);
  });
  add("180 deg turn between keyframes", false, [](const StressCaseOptions& o) {
    const int s = caseSize(o);
    const Camera a = indoorCamera(30, s);
    Camera b = a;  // exactly opposite, same eye
    b.forward = -a.forward;
    b.right = -a.right;
    CaseSpec c{"180 deg turn between keyframes", &indoorScene(), a, b, yawed(a, 90.0)};
    return runCase(c, o);
  });
  add("eye inside a box (one-sided, culled)", false, [](const StressCaseOptions& o) {
    static const scenes::Scene sc = caseScene(true, false, true, false);
    const int s = caseSize(o);
    const Camera a = Camera::lookAt({-0.2, 1.0, -5}, {0, 1, -20}, {0, 1, 0}, kPi / 3, s, s, 0.05, 200);
    CaseSpec c{"eye inside a box (one-sided, culled)", &sc, a, moved(a, {0.4, 0, 0}),
               moved(a, {0.2, 0, 0}), 20.0};
    return runCase(c, o);
  });
  add("eye inside a box (two-sided walls)", false, [](const StressCaseOptions& o) {
    static const scenes::Scene sc = caseScene(true, false, false, true);
    const int s = caseSize(o);
    const Camera a = Camera::lookAt({3.2, 1.5, -5.5}, {3.5, 1.2, -20}, {0, 1, 0}, kPi / 3, s, s, 0.05, 200);
    CaseSpec c{"eye inside a box (two-sided walls)", &sc, a, moved(a, {0.4, 0, 0}),
               moved(a, {0.2, 0, 0}), 20.0};
    return runCase(c, o);
  });
  add("geometry crossing the near plane", false, [](const StressCaseOptions& o) {
    static const scenes::Scene sc = caseScene(true, false, true, true);
    const int s = caseSize(o);
    // Eye 0.3 above the ground with n = 1: the ground and the box's near
    // corner cross the near plane.
    const Camera a = Camera::lookAt({0.0, 0.3, -2.5}, {0.5, 0.0, -8}, {0, 1, 0}, kPi / 3, s, s, 1.0, 200);
    CaseSpec c{"geometry crossing the near plane", &sc, a, moved(a, {0.1, 0, 0}),
               moved(a, {0.05, 0, 0}), 20.0};
    return runCase(c, o);
  });
  for (const double fovDeg : {1.0, 170.0}) {
    const std::string name = "fov " + fmt(fovDeg, 0) + " deg";
    add(name, false, [name, fovDeg](const StressCaseOptions& o) {
      const int s = caseSize(o);
      Camera a = indoorCamera(20, s);
      a.fovYRadians = fovDeg * kPi / 180.0;
      // Baseline in pixels about the same: 2 px of parallax at 10 m.
      const double base = 2.0 * 10.0 / a.fx();
      CaseSpec c{name, &indoorScene(), a, moved(a, base * a.right), moved(a, 0.5 * base * a.right),
                 fovDeg < 10 ? 20.0 : 15.0};
      return runCase(c, o);
    });
  }
  struct SizeCase {
    int w, h;
    bool slow;
  };
  for (const SizeCase sz : {SizeCase{1, 1, false}, SizeCase{1, 4096, false}, SizeCase{4096, 1, false},
                            SizeCase{4096, 4096, true}}) {
    const std::string name = "image " + std::to_string(sz.w) + "x" + std::to_string(sz.h);
    add(name, sz.slow, [name, sz](const StressCaseOptions& o) {
      CaseSpec c{name, &indoorScene(), sized(indoorCamera(0, 1), sz.w, sz.h),
                 sized(indoorCamera(10, 1), sz.w, sz.h), sized(indoorCamera(5, 1), sz.w, sz.h)};
      if (sz.w > 64 && sz.h > 64) c.minPsnr = 20.0;
      return runCase(c, o);
    });
  }
  add("keyframes whose views do not overlap", false, [](const StressCaseOptions& o) {
    const int s = caseSize(o);
    // B stands 1 m behind A looking exactly the other way: A's frustum lies in
    // front of A's eye, B's behind B's, so they share no point. The in-between
    // camera, midway, looks 45 deg off A's direction.
    const Camera a = indoorCamera(40, s);
    Camera b = a;
    b.forward = -a.forward;
    b.right = -a.right;
    b.eye = a.eye - 1.0 * a.forward;
    const Camera m = moved(yawed(a, 45.0), -0.5 * a.forward);
    CaseSpec c{"keyframes whose views do not overlap", &indoorScene(), a, b, m};
    return runCase(c, o);
  });
  add("quads entirely behind the eye", false, [](const StressCaseOptions& o) {
    static const scenes::Scene sc = caseScene(false, true, false, false);
    const int s = caseSize(o);
    // Keyframes see the red wall at z = −10; the in-between camera stands 2 m
    // past it, looking on: every quad is behind it, and divided by a
    // negative w would land, inverted, inside the image.
    const Camera a = Camera::lookAt({0, 0, 0}, {0, 0, -1}, {0, 1, 0}, kPi / 3, s, s, 0.1, 100);
    const Camera m = moved(a, {0, 0, -12});
    CaseSpec c{"quads entirely behind the eye", &sc, a, moved(a, {0.5, 0, 0}), m};
    return runCase(c, o, [](const Hybrid& h) -> std::string {
      long long quadPixels = 0;
      for (const warp::Layer* l : {&h.fg, &h.bg})
        for (std::size_t i = 0; i < l->coverage.size(); ++i)
          if (l->coverage.pixels()[i] && l->eyeZ.pixels()[i] != warp::kSkyEyeZ) ++quadPixels;
      const long long red = redPixels(h.fg.colour) + redPixels(h.bg.colour);
      if (h.ma.stats.quads == 0) return "keyframe A has no quads (case not exercised)";
      if (quadPixels || red)
        return std::to_string(quadPixels) + " layer pixels from quads, " + std::to_string(red) +
               " red pixels (inverted sheets)";
      return {};
    });
  });
  add("quads straddling the eye plane", false, [](const StressCaseOptions& o) {
    static const scenes::Scene sc = caseScene(true, false, false, false);
    const int s = caseSize(o);
    // A looks down the ground from z = 2; the in-between camera stands 5 m
    // ahead: the ground's large quads have corners behind and in front of it.
    const Camera a = Camera::lookAt({0, 1.7, 2}, {0, 0, -10}, {0, 1, 0}, kPi / 3, s, s, 0.1, 200);
    const Camera m = Camera::lookAt({0.3, 1.7, -3}, {0.3, 1.2, -20}, {0, 1, 0}, kPi / 3, s, s, 0.1, 200);
    CaseSpec c{"quads straddling the eye plane", &sc, a, moved(a, {0.5, 0, 0}), m};
    return runCase(c, o, [m](const Hybrid& h) -> std::string {
      // The case is exercised: some foreground quads have corners on both
      // sides of the in-between eye plane.
      const keyframe::QuadMesh& fgMesh = h.fgPick == 0 ? h.ma : h.mb;
      int straddling = 0;
      for (const keyframe::Quad& q : fgMesh.quads) {
        int behind = 0;
        for (int i = 0; i < 4; ++i) behind += glm::dot(q.world[i] - m.eye, m.forward) <= 0 ? 1 : 0;
        straddling += (behind > 0 && behind < 4) ? 1 : 0;
      }
      if (straddling == 0) return "no foreground quad straddles the eye plane (case not exercised)";
      // Where the foreground layer and the reference both see the ground,
      // their depths agree to 2 % plus the reference's own depth step to a
      // neighbour (near the horizon a pixel spans a long stretch of ground):
      // a sheet drawn through the eye (w < 0 corners projected without
      // clipping) would be far off.
      const Image<float>& tz = h.truth.eyeZ;
      const Image<std::uint8_t>& tc = h.truth.covered;
      long long both = 0, off = 0;
      for (int y = 0; y < tz.height(); ++y)
        for (int x = 0; x < tz.width(); ++x) {
          const float z = h.fg.eyeZ(x, y), t = tz(x, y);
          if (!h.fg.coverage(x, y) || z == warp::kSkyEyeZ || !tc(x, y)) continue;
          float step = 0;
          const int nx[4] = {x - 1, x + 1, x, x}, ny[4] = {y, y, y - 1, y + 1};
          for (int k = 0; k < 4; ++k)
            if (nx[k] >= 0 && ny[k] >= 0 && nx[k] < tz.width() && ny[k] < tz.height() && tc(nx[k], ny[k]))
              step = std::max(step, std::abs(tz(nx[k], ny[k]) - t));
          ++both;
          off += std::abs(z - t) > 0.02f * t + step ? 1 : 0;
        }
      if (both == 0) return "foreground layer and reference share no ground pixel";
      if (off > 0)
        return std::to_string(off) + " of " + std::to_string(both) +
               " ground pixels off in depth by more than 2 % + the local depth step";
      return {};
    });
  });
  add("fov 180 deg (invalid: clear error)", false, [](const StressCaseOptions& o) {
    const int s = caseSize(o);
    Camera a = indoorCamera(0, s);
    a.fovYRadians = kPi;
    CaseSpec c{"fov 180 deg (invalid: clear error)", &indoorScene(), a, a, a};
    c.expectError = true;
    return runCase(c, o);
  });
  return cs;
}

// ---- depth precision ------------------------------------------------------------

struct PlaneSetup {
  Camera centre;      // in-between camera
  Camera a, b;        // keyframes
  double distance;    // centre ray to the plane
  double texWorld;
};

PlaneSetup planeSetup(const DepthPrecisionSpec& spec) {
  PlaneSetup p;
  const double f = kPlaneNear * spec.farNearRatio;
  p.distance = 0.25 * f;
  const double th = spec.angleDeg * kPi / 180.0;
  Camera c;
  c.forward = glm::dvec3(0, -std::cos(th), -std::sin(th));
  c.right = glm::dvec3(1, 0, 0);
  c.up = glm::dvec3(0, std::sin(th), -std::cos(th));
  c.eye = -p.distance * c.forward;
  c.fovYRadians = kPi / 3;
  c.width = c.height = spec.size;
  c.nearPlane = kPlaneNear;
  c.farPlane = f;
  p.centre = c;
  const double s = 0.025 * p.distance;
  p.a = moved(c, -s * c.right);
  p.b = moved(c, s * c.right);
  // A texture cell spans about 12 px at the centre of a face-on 512² view.
  const double cellWorld = 12.0 * p.distance * 2.0 * std::tan(c.fovYRadians / 2) / 512.0;
  p.texWorld = 8.0 * cellWorld;
  return p;
}

// Depth along W of the plane y = 0 on the ray through (u, v); +inf if the ray
// misses it (at or past the horizon).
double planeDepthAt(const Camera& c, double u, double v) {
  const glm::dvec3 d = c.unproject(u, v, 1.0) - c.eye;
  if (!(d.y < 0)) return std::numeric_limits<double>::infinity();
  return -c.eye.y / d.y;
}

}  // namespace

Result<DepthPrecisionRow> measureDepthPrecision(const DepthPrecisionSpec& spec) {
  if (!(spec.farNearRatio > 1) || !(spec.angleDeg >= 0 && spec.angleDeg <= 89) || spec.size < 16)
    return makeError("depth precision: need ratio > 1, angle in [0, 89] deg and size >= 16; got ratio " +
                     fmt(spec.farNearRatio) + ", angle " + fmt(spec.angleDeg) + ", size " +
                     std::to_string(spec.size));
  Stopwatch sw;
  DepthPrecisionRow row;
  row.spec = spec;
  const PlaneSetup ps = planeSetup(spec);
  const scenes::Scene scene = planeScene(ps.centre.farPlane, ps.texWorld);
  keyframe::RenderOptions ro;
  ro.depthMode = spec.mode;
  auto renderer = keyframe::GeometryRenderer::create(scene, ro);
  if (!renderer) return renderer.error();
  keyframe::Keyframe kf[2];
  keyframe::QuadMesh mesh[2];
  keyframe::LodBuilder builder;
  keyframe::LodOptions lo;
  lo.tau = spec.tau;
  std::vector<double> noise, worldErr, fittedErr;
  const Camera* cams[2] = {&ps.a, &ps.b};
  for (int k = 0; k < 2; ++k) {
    const Camera& cam = *cams[k];
    HW_TRY((*renderer)->renderKeyframe(cam, kf[k]));
    const Image<double>& z = kf[k].zPrime;
    const Image<std::uint8_t>& cv = kf[k].covered;
    const int w = z.width(), h = z.height();
    for (int y = 1; y + 1 < h; ++y)
      for (int x = 1; x + 1 < w; ++x) {
        if (!(cv(x, y) && cv(x - 1, y) && cv(x + 1, y) && cv(x, y - 1) && cv(x, y + 1))) continue;
        noise.push_back(std::fabs(4.0 * z(x, y) - z(x - 1, y) - z(x + 1, y) - z(x, y - 1) - z(x, y + 1)));
      }
    if (k == 0) {
      long long covered = 0, expected = 0;
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          covered += cv(x, y) ? 1 : 0;
          const double d = planeDepthAt(cam, x + 0.5, y + 0.5);
          expected += (d > cam.nearPlane && d < cam.farPlane) ? 1 : 0;
        }
      row.coveredFraction = double(covered) / (double(w) * h);
      row.expectedCoveredFraction = double(expected) / (double(w) * h);
    }
    HW_TRY(builder.build(kf[k], lo, &mesh[k]));
    row.quads += 0.5 * mesh[k].stats.quads;
    row.clampedCorners += mesh[k].stats.clampedCorners;
    for (const keyframe::Quad& q : mesh[k].quads)
      for (int i = 0; i < 4; ++i) {
        const glm::dvec3 wf(glm::vec3(q.world[i]));  // as shipped to the GPU
        const ProjectedPoint pf = cam.project(wf), pd = cam.project(q.world[i]);
        row.cornerReprojMaxPx =
            std::max(row.cornerReprojMaxPx, std::hypot(pf.u - q.pixel[i].x, pf.v - q.pixel[i].y));
        row.cornerReprojMaxPxDouble =
            std::max(row.cornerReprojMaxPxDouble, std::hypot(pd.u - q.pixel[i].x, pd.v - q.pixel[i].y));
        const double d = planeDepthAt(cam, q.pixel[i].x, q.pixel[i].y);
        if (!std::isfinite(d)) {
          ++row.cornersPastHorizon;
          continue;
        }
        const glm::dvec3 truth = cam.unproject(q.pixel[i].x, q.pixel[i].y, d);
        const double e = glm::length(q.world[i] - truth) / glm::length(truth - cam.eye);
        worldErr.push_back(e);
        if (q.rect.width() >= 2 && q.rect.height() >= 2) fittedErr.push_back(e);
      }
  }
  row.noisePixels = static_cast<long long>(noise.size());
  row.noiseP99 = percentile(noise, 99.0);
  row.noiseMax = noise.empty() ? kNan : *std::max_element(noise.begin(), noise.end());
  row.worldRelErrP50 = percentile(worldErr, 50.0);
  row.worldRelErrP99 = percentile(worldErr, 99.0);
  row.worldRelErrMax = worldErr.empty() ? kNan : *std::max_element(worldErr.begin(), worldErr.end());
  row.fittedRelErrP50 = percentile(fittedErr, 50.0);
  row.fittedRelErrP99 = percentile(fittedErr, 99.0);
  row.fittedRelErrMax = fittedErr.empty() ? kNan : *std::max_element(fittedErr.begin(), fittedErr.end());

  auto warper = warp::Warper::create();
  if (!warper) return warper.error();
  auto sa = (*warper)->upload(kf[0], mesh[0]);
  if (!sa) return sa.error();
  auto sb = (*warper)->upload(kf[1], mesh[1]);
  if (!sb) return sb.error();
  warp::Layer la, lb;
  const int fg = gapfill::chooseForeground(ps.centre.eye, ps.a.eye, ps.b.eye);
  HW_TRY((*warper)->warp(fg == 0 ? **sa : **sb, ps.centre, la));
  HW_TRY((*warper)->warp(fg == 0 ? **sb : **sa, ps.centre, lb));
  gapfill::Frame frame;
  gapfill::compose(la, &lb, nullptr, gapfill::ComposeOptions{}, frame);
  Image<Rgba8> ref;
  HW_TRY((*renderer)->renderColour(ps.centre, ref));
  row.psnr = psnrCapped(frame.colour, ref);
  row.holeFraction = frame.holeFractionBefore;
  row.ms = sw.ms();
  return row;
}

std::string stressCaseSlug(const std::string& name) {
  std::string s;
  for (char c : name) {
    if (std::isalnum(static_cast<unsigned char>(c))) s += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    else if (!s.empty() && s.back() != '_') s += '_';
  }
  while (!s.empty() && s.back() == '_') s.pop_back();
  return s;
}

const std::vector<StressCase>& stressCases() {
  static const std::vector<StressCase> cs = makeCases();
  return cs;
}

std::vector<StressCaseRow> runStressCases(const StressCaseOptions& options, bool includeSlow) {
  std::vector<StressCaseRow> rows;
  for (const StressCase& c : stressCases()) {
    if (c.slow && !includeSlow) continue;
    rows.push_back(c.run(options));
  }
  return rows;
}

// ---- the report -------------------------------------------------------------------

namespace {

json rowJson(const DepthPrecisionRow& r) {
  return {{"mode", depthModeName(r.spec.mode)},
          {"far_near_ratio", r.spec.farNearRatio},
          {"angle_deg", r.spec.angleDeg},
          {"size", r.spec.size},
          {"tau", r.spec.tau},
          {"noise_p99", finiteOrNull(r.noiseP99)},
          {"noise_max", finiteOrNull(r.noiseMax)},
          {"noise_pixels", r.noisePixels},
          {"quads", r.quads},
          {"clamped_corners", r.clampedCorners},
          {"corner_reproj_max_px", finiteOrNull(r.cornerReprojMaxPx)},
          {"corner_reproj_max_px_double", finiteOrNull(r.cornerReprojMaxPxDouble)},
          {"world_rel_err_p50", finiteOrNull(r.worldRelErrP50)},
          {"world_rel_err_p99", finiteOrNull(r.worldRelErrP99)},
          {"world_rel_err_max", finiteOrNull(r.worldRelErrMax)},
          {"fitted_rel_err_p50", finiteOrNull(r.fittedRelErrP50)},
          {"fitted_rel_err_p99", finiteOrNull(r.fittedRelErrP99)},
          {"fitted_rel_err_max", finiteOrNull(r.fittedRelErrMax)},
          {"corners_past_horizon", r.cornersPastHorizon},
          {"covered_fraction", r.coveredFraction},
          {"expected_covered_fraction", r.expectedCoveredFraction},
          {"psnr", finiteOrNull(r.psnr)},
          {"hole_fraction", r.holeFraction},
          {"ms", r.ms}};
}

json caseJson(const StressCaseRow& r) {
  return {{"name", r.name},         {"ok", r.ok},       {"message", r.message},
          {"holes", r.holes},       {"psnr", finiteOrNull(r.psnr)},
          {"nan_count", r.nanCount}, {"ms", r.ms},      {"expect_error", r.expectError}};
}

std::string csvField(const std::string& s) {
  std::string o = "\"";
  for (char c : s) o += c == '"' ? std::string("\"\"") : std::string(1, c);
  return o + "\"";
}

std::string num(double v, int digits = 6) {
  if (!std::isfinite(v)) return "";
  char b[64];
  std::snprintf(b, sizeof b, "%.*g", digits, v);
  return b;
}

std::string sci(double v) {
  if (!std::isfinite(v)) return "-";
  char b[64];
  std::snprintf(b, sizeof b, "%.2g", v);
  return b;
}

// The written conclusion: the numbers it rests on are taken from `rows`.
std::string conclusionText(const std::vector<DepthPrecisionRow>& rows, const std::string& recommended) {
  auto get = [&](DepthMode m, double ratio, double angle) -> const DepthPrecisionRow* {
    for (const auto& r : rows)
      if (r.spec.mode == m && r.spec.farNearRatio == ratio && r.spec.angleDeg == angle) return &r;
    return nullptr;
  };
  // Worst over angles of a field, per mode and ratio.
  auto worst = [&](DepthMode m, double ratio, double (*f)(const DepthPrecisionRow&)) {
    double w = 0;
    for (double a : kAngles)
      if (const auto* r = get(m, ratio, a); r && std::isfinite(f(*r))) w = std::max(w, f(*r));
    return w;
  };
  auto fitted = [](const DepthPrecisionRow& r) { return r.fittedRelErrP99; };
  auto lost = [](const DepthPrecisionRow& r) { return r.expectedCoveredFraction - r.coveredFraction; };
  auto quads = [](const DepthPrecisionRow& r) { return r.quads; };
  std::ostringstream o;
  o << "Findings. Noise |D2 z'| p99/max (z' units) at f/n 1e3 and 1e5, 0 and 85 deg: ";
  for (DepthMode m : kModes) {
    o << depthModeName(m) << " ";
    for (double ratio : {1e3, 1e5})
      for (double a : {0.0, 85.0})
        if (const auto* r = get(m, ratio, a))
          o << "[" << ratioLabel(ratio) << ", " << fmt(a, 0) << "deg: " << sci(r->noiseP99) << "/"
            << sci(r->noiseMax) << "] ";
    o << "; ";
  }
  o << "Every mode stays orders of magnitude below tau = 2^11, so the quad count is the same in "
       "all three (worst over angles at f/n 1e6: ";
  for (DepthMode m : kModes) o << depthModeName(m) << " " << fmt(worst(m, 1e6, quads), 0) << " ";
  o << "quads; the quads beyond one per plane are the one-pixel strips along the far-clip edge): "
       "no mode breaks by exploding quads. What differs is where the recovered corners are. The "
       "p99 world error of fitted corners, relative to distance, worst over angles, at f/n 10 / "
       "1e3 / 1e5 / 1e6: ";
  for (DepthMode m : kModes) {
    o << depthModeName(m);
    for (double ratio : kRatios) o << " " << sci(worst(m, ratio, fitted));
    o << "; ";
  }
  o << "a 24-bit z' step is z/(2^24 n) of the distance z, so with the plane at f/4 it grows "
       "linearly with f/n (1.5 % at 1e6), while reversed float keeps its relative precision at "
       "every distance. Pixels of the plane read back as empty (z' rounded to 2^24 - 1 near f), "
       "worst over angles, at 1e5 / 1e6: ";
  for (DepthMode m : kModes)
    o << depthModeName(m) << " " << fmt(100.0 * worst(m, 1e5, lost), 2) << " % / "
      << fmt(100.0 * worst(m, 1e6, lost), 2) << " %; ";
  o << "In-between PSNR reacts late: a corner depth error e moves a warped point by about e "
       "times its parallax, a fraction of a pixel for this short move. Largest deficit against "
       "the best mode: ";
  for (DepthMode m : kModes) {
    double d = 0, atRatio = 0, atAngle = 0;
    for (const auto& r : rows) {
      if (r.spec.mode != m) continue;
      double best = r.psnr;
      for (DepthMode k : kModes)
        if (const auto* q = get(k, r.spec.farNearRatio, r.spec.angleDeg)) best = std::max(best, q->psnr);
      if (best - r.psnr > d) {
        d = best - r.psnr;
        atRatio = r.spec.farNearRatio;
        atAngle = r.spec.angleDeg;
      }
    }
    o << depthModeName(m) << " " << fmt(d, 2) << " dB";
    if (d > 0.05) o << " (f/n " << ratioLabel(atRatio) << ", " << fmt(atAngle, 0) << " deg)";
    o << "; ";
  }
  o << "Over all corners (including the 1-pixel strips along the far-clip edge, which carry no "
       "slope) the p99 error is of the same order in every mode, worst over the grid: ";
  for (DepthMode m : kModes) {
    double w = 0;
    for (double ratio : kRatios)
      w = std::max(w, worst(m, ratio, [](const DepthPrecisionRow& r) { return r.worldRelErrP99; }));
    o << depthModeName(m) << " " << sci(w) << " ";
  }
  o << "- a property of the LOD builder, not of the depth buffer. ";
  double lost6 = 0;
  for (DepthMode m : kModes) lost6 = std::max(lost6, worst(m, 1e6, lost));
  o << "Fixed24 and Float32 (standard) give the same z' wherever window depth is in [0.5, 1), "
       "which covers all of this plane, so they break together, by corner accuracy first: at f/n "
       "1e5 the fitted corners are off by up to "
    << sci(worst(DepthMode::Fixed24, 1e5, fitted)) << " of the distance, at 1e6 by up to "
    << sci(worst(DepthMode::Fixed24, 1e6, fitted)) << " (up to " << fmt(100.0 * lost6, 2)
    << " % of the image lost next to f). Default: "
    << recommended
    << ". It never breaks in this grid, costs the same 32 bits per pixel as 24-bit depth + "
       "stencil, maps onto the same z' scale (one tau means the same thing), gives the same "
       "quads, lowers the noise floor so that small tau measure geometry, not the rasteriser "
       "(except on steep surfaces right at the near plane, where the rasteriser's own "
       "interpolation dominates in every mode), and needs only glClipControl (GL 4.5). The "
       "paper's 24-bit buffer stays available for its sweeps.";
  return o.str();
}

}  // namespace

Result<json> runStress(const StressOptions& opt) {
  if (opt.outDir.empty()) return makeError("stress: an output directory is required (--out DIR)");
  HW_TRY(ensureWritableDir(opt.outDir));
  Stopwatch total;
  const int size = opt.quick ? 256 : 512;

  // Part 1.
  std::vector<DepthPrecisionRow> rows;
  const std::size_t nConfigs = 3 * 4 * 5;
  Stopwatch p1;
  for (DepthMode mode : kModes)
    for (double ratio : kRatios)
      for (double angle : kAngles) {
        if (opt.progress) {
          std::fprintf(stderr, "\rstress: depth precision %zu/%zu (%s, f/n %s, %g deg)        ",
                       rows.size() + 1, nConfigs, depthModeName(mode), ratioLabel(ratio).c_str(), angle);
          std::fflush(stderr);
        }
        auto r = measureDepthPrecision(DepthPrecisionSpec{mode, ratio, angle, size, 2048.0});
        if (!r) return makeError("stress: depth precision (" + std::string(depthModeName(mode)) + ", f/n " +
                                 ratioLabel(ratio) + ", " + fmt(angle, 0) + " deg): " + r.error().message);
        rows.push_back(*r);
      }
  const double part1Ms = p1.ms();

  // Part 2.
  Stopwatch p2;
  std::map<std::string, std::vector<StressCaseRow>> caseRows;
  const std::vector<DepthMode> caseModes = {kModes[0], kModes[1], kModes[2]};
  for (DepthMode mode : caseModes) {
    StressCaseOptions co;
    co.depthMode = mode;
    co.quick = opt.quick;
    auto& out = caseRows[depthModeName(mode)];
    for (const StressCase& c : stressCases()) {
      if (c.slow && (opt.quick || mode != DepthMode::Fixed24)) continue;
      if (opt.progress) {
        std::fprintf(stderr, "\rstress: case %s (%s)                              ", c.name.c_str(),
                     depthModeName(mode));
        std::fflush(stderr);
      }
      out.push_back(c.run(co));
    }
  }
  const double part2Ms = p2.ms();
  if (opt.progress) std::fprintf(stderr, "\n");

  auto find = [&](DepthMode m, double ratio, double angle) -> const DepthPrecisionRow& {
    for (const auto& r : rows)
      if (r.spec.mode == m && r.spec.farNearRatio == ratio && r.spec.angleDeg == angle) return r;
    HW_CHECK(false);
    return rows.front();
  };

  // Break criteria, per configuration. Against the best mode at the same
  // ratio and angle: PSNR more than 3 dB below it; quads more than twice its
  // count (and > 8 more). Absolute: p99 world error of fitted corners above
  // 1e-3 of the distance; more than 0.1 % of the image, where the plane lies
  // inside the far plane, read back as empty.
  std::map<std::string, std::vector<std::string>> breaks;  // mode → descriptions
  std::map<std::string, double> firstBreakRatio;
  json verdicts = json::array();
  for (double ratio : kRatios)
    for (double angle : kAngles) {
      double bestPsnr = -1e300, bestQuads = 1e300, bestErr = 1e300;
      for (DepthMode m : kModes) {
        const auto& r = find(m, ratio, angle);
        bestPsnr = std::max(bestPsnr, r.psnr);
        bestQuads = std::min(bestQuads, r.quads);
        if (std::isfinite(r.fittedRelErrP99)) bestErr = std::min(bestErr, r.fittedRelErrP99);
      }
      for (DepthMode m : kModes) {
        const auto& r = find(m, ratio, angle);
        std::vector<std::string> why;
        if (r.psnr < bestPsnr - 3.0) why.push_back("PSNR " + fmt(r.psnr, 1) + " dB vs best " + fmt(bestPsnr, 1));
        if (r.quads > 2.0 * bestQuads && r.quads > bestQuads + 8)
          why.push_back("quads " + fmt(r.quads, 0) + " vs best " + fmt(bestQuads, 0));
        if (r.fittedRelErrP99 > 1e-3)
          why.push_back("fitted-corner world error p99 " + sci(r.fittedRelErrP99) + " of the distance (best " +
                        sci(bestErr) + ")");
        if (r.expectedCoveredFraction - r.coveredFraction > 0.001)
          why.push_back(fmt(100.0 * (r.expectedCoveredFraction - r.coveredFraction), 1) +
                        " % of the image lost as empty");
        if (why.empty()) continue;
        std::string d = "f/n " + ratioLabel(ratio) + ", " + fmt(angle, 0) + " deg: ";
        for (std::size_t i = 0; i < why.size(); ++i) d += (i ? "; " : "") + why[i];
        breaks[depthModeName(m)].push_back(d);
        auto it = firstBreakRatio.find(depthModeName(m));
        if (it == firstBreakRatio.end() || ratio < it->second) firstBreakRatio[depthModeName(m)] = ratio;
        verdicts.push_back({{"mode", depthModeName(m)}, {"far_near_ratio", ratio}, {"angle_deg", angle},
                            {"why", why}});
      }
    }
  // Recommended default: the mode that breaks at the highest ratio (never is
  // best); ties go to the lower worst-case p99 world error.
  std::string recommended;
  double recBreak = -1, recErr = 1e300;
  for (DepthMode m : kModes) {
    const std::string name = depthModeName(m);
    const double br = firstBreakRatio.count(name) ? firstBreakRatio[name] : 1e300;
    double worst = 0;
    for (const auto& r : rows)
      if (r.spec.mode == m && std::isfinite(r.fittedRelErrP99)) worst = std::max(worst, r.fittedRelErrP99);
    if (br > recBreak || (br == recBreak && worst < recErr)) {
      recommended = name;
      recBreak = br;
      recErr = worst;
    }
  }

  // Outputs: JSON, CSVs.
  json doc;
  doc["machine"] = machineInfo(opt.glRenderer, opt.glVersion);
  doc["options"] = {{"quick", opt.quick}, {"size", size}, {"tau", 2048.0}, {"near", kPlaneNear},
                    {"plane", "y = 0, 64x64 cells, half-size 2f, centre ray at distance f/4, "
                              "keyframes at +-2.5% of it sideways, in-between at the midpoint"}};
  json dp = json::array();
  for (const auto& r : rows) dp.push_back(rowJson(r));
  doc["depth_precision"] = dp;
  doc["breaks"] = verdicts;
  doc["recommended_default"] = recommended;
  json cj = json::object();
  int casesFailed = 0, casesTotal = 0;
  for (const auto& [mode, list] : caseRows) {
    json a = json::array();
    for (const auto& r : list) {
      a.push_back(caseJson(r));
      ++casesTotal;
      casesFailed += r.ok ? 0 : 1;
    }
    cj[mode] = a;
  }
  doc["cases"] = cj;
  doc["cases_failed"] = casesFailed;
  doc["timing_s"] = {{"depth_precision", part1Ms / 1000.0}, {"cases", part2Ms / 1000.0}};

  {
    std::string csv =
        "mode,far_near_ratio,angle_deg,size,noise_p99,noise_max,noise_pixels,quads,clamped_corners,"
        "corner_reproj_max_px,corner_reproj_max_px_double,world_rel_err_p50,world_rel_err_p99,"
        "world_rel_err_max,fitted_rel_err_p50,fitted_rel_err_p99,fitted_rel_err_max,corners_past_horizon,covered_fraction,expected_covered_fraction,psnr,"
        "hole_fraction,ms\n";
    for (const auto& r : rows)
      csv += std::string(depthModeName(r.spec.mode)) + "," + num(r.spec.farNearRatio) + "," +
             num(r.spec.angleDeg) + "," + std::to_string(r.spec.size) + "," + num(r.noiseP99) + "," +
             num(r.noiseMax) + "," + std::to_string(r.noisePixels) + "," + num(r.quads) + "," +
             std::to_string(r.clampedCorners) + "," + num(r.cornerReprojMaxPx) + "," +
             num(r.cornerReprojMaxPxDouble) + "," + num(r.worldRelErrP50) + "," +
             num(r.worldRelErrP99) + "," + num(r.worldRelErrMax) + "," + num(r.fittedRelErrP50) + "," +
             num(r.fittedRelErrP99) + "," + num(r.fittedRelErrMax) + "," +
             std::to_string(r.cornersPastHorizon) + "," + num(r.coveredFraction) + "," +
             num(r.expectedCoveredFraction) + "," + num(r.psnr) + "," + num(r.holeFraction) + "," +
             num(r.ms) + "\n";
    HW_TRY(writeFileAtomic(opt.outDir + "/depth_precision.csv", csv));
    std::string c2 = "mode,name,ok,holes,psnr,nan_count,ms,message\n";
    for (const auto& [mode, list] : caseRows)
      for (const auto& r : list)
        c2 += mode + "," + csvField(r.name) + "," + (r.ok ? "1" : "0") + "," + num(r.holes) + "," +
              num(r.psnr) + "," + std::to_string(r.nanCount) + "," + num(r.ms) + "," +
              csvField(r.message) + "\n";
    HW_TRY(writeFileAtomic(opt.outDir + "/cases.csv", c2));
  }

  // Plots: per mode, one series per ratio (against angle) or per angle
  // (against ratio).
  std::vector<std::string> noisePngs, quadPngs, reprojPngs, worldPngs, psnrPngs;
  for (DepthMode m : kModes) {
    const std::string mn = depthModeName(m);
    std::vector<Series> noiseS;
    for (double ratio : kRatios) {
      Series s;
      s.label = "f/n " + ratioLabel(ratio);
      for (double angle : kAngles) {
        s.x.push_back(angle);
        // Log axis: an exact 0 (constant z' face-on) is drawn at 1e-9.
        s.y.push_back(std::max(find(m, ratio, angle).noiseP99, 1e-9));
      }
      noiseS.push_back(s);
    }
    PlotOptions po;
    po.width = 560;
    po.height = 360;
    po.logY = true;
    po.yMin = 1e-9;
    po.yMax = 1e3;
    po.title = mn + ": |D2 z'| p99 on the plane";
    po.xLabel = "angle between view and plane normal (deg)";
    po.yLabel = "p99 |D2 z'| (z' units)";
    HW_TRY(writePlot(opt.outDir + "/noise_" + mn + ".png", noiseS, po));
    noisePngs.push_back("noise_" + mn + ".png");

    auto perAngle = [&](const std::string& file, const std::string& title, const std::string& yLabel,
                        bool logY, std::optional<double> yMin, std::optional<double> yMax,
                        double (*get)(const DepthPrecisionRow&)) -> Status {
      std::vector<Series> ss;
      for (double angle : kAngles) {
        Series s;
        s.label = fmt(angle, 0) + " deg";
        for (double ratio : kRatios) {
          s.x.push_back(ratio);
          s.y.push_back(get(find(m, ratio, angle)));
        }
        ss.push_back(s);
      }
      PlotOptions o;
      o.width = 560;
      o.height = 360;
      o.logX = true;
      o.logY = logY;
      o.yMin = yMin;
      o.yMax = yMax;
      o.title = mn + ": " + title;
      o.xLabel = "far/near ratio";
      o.yLabel = yLabel;
      return writePlot(opt.outDir + "/" + file, ss, o);
    };
    HW_TRY(perAngle("quads_" + mn + ".png", "quads per keyframe, tau 2^11", "quads", true, 1.0, 1e5,
                    [](const DepthPrecisionRow& r) { return r.quads; }));
    quadPngs.push_back("quads_" + mn + ".png");
    HW_TRY(perAngle("reproj_" + mn + ".png", "reprojection, float corners", "max error (px)",
                    true, 1e-6, 1e2,
                    [](const DepthPrecisionRow& r) { return std::max(r.cornerReprojMaxPx, 1e-6); }));
    reprojPngs.push_back("reproj_" + mn + ".png");
    HW_TRY(perAngle("world_" + mn + ".png", "fitted corners, world err/dist p99",
                    "relative error", true, 1e-8, 10.0,
                    [](const DepthPrecisionRow& r) { return std::max(r.fittedRelErrP99, 1e-8); }));
    worldPngs.push_back("world_" + mn + ".png");
    HW_TRY(perAngle("psnr_" + mn + ".png", "in-between PSNR", "PSNR (dB)", false,
                    std::nullopt, std::nullopt, [](const DepthPrecisionRow& r) { return r.psnr; }));
    psnrPngs.push_back("psnr_" + mn + ".png");
  }

  // index.html
  HtmlReport page("hybridwalk stress: depth precision and degenerate cameras");
  page.heading("Summary", 2);
  {
    std::string s = "Recommended default depth mode: " + recommended + ". ";
    for (DepthMode m : kModes) {
      const std::string name = depthModeName(m);
      s += name + ": ";
      if (!firstBreakRatio.count(name)) s += "never breaks in this grid. ";
      else s += "first breaks at f/n " + ratioLabel(firstBreakRatio[name]) + " (" +
                std::to_string(breaks[name].size()) + " of 20 configurations). ";
    }
    s += "Degenerate cases: " + std::to_string(casesTotal - casesFailed) + " of " +
         std::to_string(casesTotal) + " pass.";
    page.paragraph(s);
  }
  page.heading("Depth precision", 2);
  page.paragraph(
      "Setup: near n = 0.1, far f = ratio * n; a textured plane (64x64 cells of two triangles, "
      "half-size 2f) seen with the given angle between the view direction and its normal, the "
      "centre ray meeting it at distance f/4 (the far part of the range). Keyframes A and B at "
      "+-2.5 % of that distance sideways, the in-between frame at their midpoint, " +
      std::to_string(size) + "x" + std::to_string(size) +
      " pixels, tau = 2^11 (five-point, paper's stencil rule). Noise: |D2 z'| (eq. 3, z' units) "
      "over pixels whose 5-point stencil is on the plane, A and B pooled; an exact 0 is drawn at "
      "1e-9. Reprojection: float world corners (what the GPU gets) projected with the keyframe "
      "camera vs their pixel corner. World error: |corner - analytic ray/plane point| / distance.");
  page.images(noisePngs, {}, 560);
  page.images(quadPngs, {}, 560);
  page.images(worldPngs, {}, 560);
  page.images(reprojPngs, {}, 560);
  page.images(psnrPngs, {}, 560);
  {
    std::vector<std::vector<std::string>> t;
    for (DepthMode m : kModes)
      for (double ratio : {1e3, 1e5})
        for (double angle : {0.0, 85.0}) {
          const auto& r = find(m, ratio, angle);
          t.push_back({depthModeName(m), ratioLabel(ratio), fmt(angle, 0), fmt(r.noiseP99, 2),
                       fmt(r.noiseMax, 2), fmt(r.quads, 1), sci(r.fittedRelErrP99), sci(r.fittedRelErrMax),
                       sci(r.worldRelErrP99), sci(r.cornerReprojMaxPx), fmt(r.psnr, 2),
                       fmt(100.0 * (r.expectedCoveredFraction - r.coveredFraction), 2)});
        }
    page.heading("Key numbers", 3);
    page.table({"mode", "f/n", "angle", "noise p99", "noise max", "quads", "fitted err p99",
                "fitted err max", "all-corner err p99", "reproj max px", "PSNR dB", "lost %"},
               t);
  }
  page.heading("Where each mode breaks", 3);
  page.paragraph(
      "Break criteria, per configuration, against the best of the three modes at the same ratio "
      "and angle: PSNR more than 3 dB below the best; more than twice the best quad count (and 8 "
      "more); or, absolutely: p99 world error of fitted corners above 1e-3 of the distance (1 m "
      "at 1 km); or more than 0.1 % of the image, where the plane lies within the far plane, read "
      "back as empty.");
  for (DepthMode m : kModes) {
    const std::string name = depthModeName(m);
    std::string txt = name + ": ";
    if (breaks[name].empty()) txt += "no configuration breaks.";
    else
      for (std::size_t i = 0; i < breaks[name].size(); ++i) txt += (i ? " | " : "") + breaks[name][i];
    page.paragraph(txt);
  }
  page.paragraph(conclusionText(rows, recommended));
  page.heading("All configurations", 3);
  {
    std::vector<std::vector<std::string>> t;
    for (const auto& r : rows)
      t.push_back({depthModeName(r.spec.mode), ratioLabel(r.spec.farNearRatio), fmt(r.spec.angleDeg, 0),
                   fmt(r.noiseP99, 2), fmt(r.noiseMax, 2), fmt(r.quads, 1), std::to_string(r.clampedCorners),
                   sci(r.fittedRelErrP50), sci(r.fittedRelErrP99), sci(r.fittedRelErrMax),
                   sci(r.worldRelErrP99), sci(r.worldRelErrMax),
                   sci(r.cornerReprojMaxPx), fmt(r.psnr, 2), fmt(100.0 * r.coveredFraction, 1),
                   fmt(100.0 * r.expectedCoveredFraction, 1)});
    page.table({"mode", "f/n", "angle", "noise p99", "noise max", "quads", "clamped", "fitted p50",
                "fitted p99", "fitted max", "all p99", "all max", "reproj px", "PSNR", "covered %", "expected %"},
               t);
  }
  page.heading("Degenerate and extreme cameras", 2);
  page.paragraph(
      "Each case runs the whole pipeline (keyframes A and B, LOD mesh at tau 2^11, warp of both to "
      "the in-between camera, composition with keyframe A's image as the previous frame) and "
      "passes with a valid frame - no NaN/Inf in z', eye z, quad corners or layer depth; no corner "
      "at or behind its eye; no layer pixel from a fragment behind the eye; no pixel unfilled "
      "after the fallback; the case's own checks - or, for invalid cameras, with a clear error. "
      "holes = fraction before the fallback.");
  for (const auto& [mode, list] : caseRows) {
    page.heading("Depth mode " + mode, 3);
    std::vector<std::vector<std::string>> t;
    for (const auto& r : list)
      t.push_back({r.name, r.ok ? "pass" : "FAIL", fmt(r.holes, 4), fmt(r.psnr, 2),
                   std::to_string(r.nanCount), fmt(r.ms, 0), r.message});
    page.table({"case", "result", "holes", "PSNR dB", "nan_count", "ms", "message"}, t);
  }
  page.heading("Run", 2);
  page.paragraph("Depth precision " + fmt(part1Ms / 1000.0, 1) + " s, cases " + fmt(part2Ms / 1000.0, 1) +
                 " s, total " + fmt(total.ms() / 1000.0, 1) + " s (" + (opt.quick ? "quick" : "full") +
                 " mode). Machine: " + doc["machine"].dump());
  doc["timing_s"]["total"] = total.ms() / 1000.0;
  doc["conclusion"] = conclusionText(rows, recommended);
  HW_TRY(page.write(opt.outDir + "/index.html"));
  HW_TRY(writeFileAtomic(opt.outDir + "/stress.json", doc.dump(2)));
  return doc;
}

}  // namespace hw::bench
