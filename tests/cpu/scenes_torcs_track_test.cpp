// TORCS track descriptions (scenes/torcs_track.h) on synthetic files: the
// centreline of a closed oval closes and has the oval's length, spiral arcs
// turn by their arc, bad descriptions are errors naming the file, line and
// segment, registration recovers a known shift, and the drive stays on the
// road at eye height.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>
#include <string>

#include "scenes/fetch.h"
#include "scenes/torcs_track.h"

namespace hw::scenes {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::string segmentXml(const std::string& name, const std::string& body) {
  return "      <section name=\"" + name + "\">\n" + body + "      </section>\n";
}
std::string straight(const std::string& name, double lg, const char* unit = "m") {
  return segmentXml(name,
                    "        <attstr name=\"type\" val=\"str\"/>\n"
                    "        <attnum name=\"lg\" unit=\"" +
                        std::string(unit) + "\" val=\"" + std::to_string(lg) + "\"/>\n");
}
std::string arc(const std::string& name, const char* type, double radius, double deg,
                double endRadius = 0) {
  std::string b = std::string("        <attstr name=\"type\" val=\"") + type + "\"/>\n" +
                  "        <attnum name=\"radius\" unit=\"m\" val=\"" + std::to_string(radius) +
                  "\"/>\n" + "        <attnum name=\"arc\" unit=\"deg\" val=\"" +
                  std::to_string(deg) + "\"/>\n";
  if (endRadius > 0)
    b += "        <attnum name=\"end radius\" unit=\"m\" val=\"" + std::to_string(endRadius) +
         "\"/>\n";
  return segmentXml(name, b);
}
std::string trackXml(const std::string& segments, double width = 12.0) {
  return "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
         "<!DOCTYPE params SYSTEM \"../../../src/libs/tgf/params.dtd\" [\n"
         "<!-- general definitions for tracks -->\n"
         "<!ENTITY default-surfaces SYSTEM \"../../../data/tracks/surfaces.xml\">\n"
         "]>\n"
         "<params name=\"Test\" type=\"trackdef\" mode=\"mw\">\n"
         "  <section name=\"Surfaces\">&default-surfaces;</section>\n"
         "  <section name=\"Header\">\n"
         "    <attstr name=\"name\" val=\"Test &amp; Oval\"/>\n"
         "    <attstr name=\"category\" val=\"oval\"/>\n"
         "  </section>\n"
         "  <section name=\"Main Track\">\n"
         "    <attnum name=\"width\" unit=\"m\" val=\"" +
         std::to_string(width) +
         "\"/>\n"
         "    <attnum name=\"profil steps length\" unit=\"m\" val=\"4.0\"/>\n"
         "    <!-- segments -->\n"
         "    <section name=\"Track Segments\">\n" +
         segments +
         "    </section>\n"
         "  </section>\n"
         "</params>\n";
}

// 200 m straights joined by two left half circles of radius 50 m.
std::string ovalXml() {
  return trackXml(straight("front", 200) + arc("turn 1", "lft", 50, 180) + straight("back", 200) +
                  arc("turn 2", "lft", 50, 180));
}

TEST(TorcsTrackXml, ParsesSegmentsUnitsAndHeader) {
  auto d = parseTorcsTrackXml(ovalXml(), "oval.xml");
  ASSERT_TRUE(d.ok()) << d.error().message;
  EXPECT_EQ(d->name, "Test & Oval");
  EXPECT_EQ(d->category, "oval");
  EXPECT_DOUBLE_EQ(d->widthMetres, 12.0);
  ASSERT_EQ(d->segments.size(), 4u);
  EXPECT_EQ(d->segments[1].name, "turn 1");
  EXPECT_EQ(d->segments[1].kind, TorcsSegment::Kind::Left);
  EXPECT_NEAR(d->segments[1].arcRadians, kPi, 1e-9);
  EXPECT_NEAR(d->lengthMetres(), 400.0 + 2 * kPi * 50.0, 1e-9);
  // Feet are converted.
  auto f = parseTorcsTrackXml(trackXml(straight("a", 1000, "ft")), "ft.xml");
  ASSERT_TRUE(f.ok()) << f.error().message;
  EXPECT_NEAR(f->segments[0].lengthMetres, 304.8, 1e-9);
}

TEST(TorcsTrackXml, OvalClosesWithItsLength) {
  auto d = parseTorcsTrackXml(ovalXml(), "oval.xml");
  ASSERT_TRUE(d.ok()) << d.error().message;
  TorcsCentrelineOptions o;
  o.sampleMetres = 1.0;
  auto c = integrateTorcsCentreline(*d, o);
  ASSERT_TRUE(c.ok()) << c.error().message;
  const double expected = 400.0 + 2 * kPi * 50.0;
  EXPECT_NEAR(c->lengthMetres, expected, 1e-6);
  EXPECT_LT(c->closureGapMetres, 1e-6);
  EXPECT_LT(c->closureDegrees, 1e-6);
  // Sampled at about 1 m, and the polyline's own length is the loop's (a
  // chord polygon, so just below it).
  double poly = 0;
  for (std::size_t k = 0; k < c->points.size(); ++k)
    poly += glm::length(c->points[(k + 1) % c->points.size()] - c->points[k]);
  EXPECT_NEAR(poly, expected, 0.01);
  EXPECT_NEAR(static_cast<double>(c->points.size()), expected, 1.0);
  // Starts at the middle of the start line, heading +x; the far straight is
  // 100 m (2 r) to the left.
  EXPECT_NEAR(c->points[0].x, 0.0, 1e-9);
  EXPECT_NEAR(c->points[0].y, 6.0, 1e-9);
  double maxY = -1e9;
  for (const auto& p : c->points) maxY = std::max(maxY, p.y);
  EXPECT_NEAR(maxY, 6.0 + 100.0, 1e-3);
  // Every point is on the oval: within 1e-6 of a straight or at 50 m from
  // a turn's centre.
  for (const auto& p : c->points) {
    double dist;
    if (p.x < 0)
      dist = std::abs(glm::length(p - glm::dvec2(0, 56)) - 50);
    else if (p.x > 200)
      dist = std::abs(glm::length(p - glm::dvec2(200, 56)) - 50);
    else
      dist = std::min(std::abs(p.y - 6), std::abs(p.y - 106));
    ASSERT_LT(dist, 1e-6) << p.x << "," << p.y;
  }
  // Two edge points per step, ±6 m from the centreline.
  ASSERT_GE(c->edgePoints.size(), 8u);
  EXPECT_NEAR(glm::length(c->edgePoints[0] - c->edgePoints[1]), 12.0, 1e-9);
}

TEST(TorcsTrackXml, RightHandedLoopAndSpiralsTurnByTheirArc) {
  // Four right spirals of 90° (radius 40 → 70): whatever the shape, the
  // heading must come back to the start's.
  std::string segs;
  for (int k = 0; k < 4; ++k) segs += arc("s" + std::to_string(k), "rgt", 40, 90, 70);
  auto d = parseTorcsTrackXml(trackXml(segs), "spiral.xml");
  ASSERT_TRUE(d.ok()) << d.error().message;
  TorcsCentrelineOptions o;
  o.closeMetres = 1e9;  // a spiral loop need not close in position
  auto c = integrateTorcsCentreline(*d, o);
  ASSERT_TRUE(c.ok()) << c.error().message;
  EXPECT_LT(c->closureDegrees, 1e-6);
  // A right-hand loop goes clockwise: the signed area is negative.
  double area = 0;
  for (std::size_t k = 0; k < c->points.size(); ++k) {
    const auto& a = c->points[k];
    const auto& b = c->points[(k + 1) % c->points.size()];
    area += a.x * b.y - b.x * a.y;
  }
  EXPECT_LT(area, 0.0);
  // Its length lies between the loops of the two radii.
  EXPECT_GT(c->lengthMetres, 2 * kPi * 40);
  EXPECT_LT(c->lengthMetres, 2 * kPi * 70);
}

TEST(TorcsTrackXml, TrackThatDoesNotCloseNamesFileAndLastSegment) {
  const std::string xml = trackXml(straight("front", 200) + arc("turn 1", "lft", 50, 180) +
                                   straight("back", 150) + arc("last turn", "lft", 50, 180));
  auto d = parseTorcsTrackXml(xml, "open.xml");
  ASSERT_TRUE(d.ok()) << d.error().message;
  auto c = integrateTorcsCentreline(*d);
  ASSERT_FALSE(c.ok());
  const std::string& m = c.error().message;
  EXPECT_NE(m.find("open.xml"), std::string::npos) << m;
  EXPECT_NE(m.find("does not close"), std::string::npos) << m;
  EXPECT_NE(m.find("'last turn'"), std::string::npos) << m;
  EXPECT_NE(m.find("50.0 m"), std::string::npos) << m;  // the 50 m missing from the back straight
}

TEST(TorcsTrackXml, BadDescriptionsNameFileLineAndSegment) {
  struct Case {
    std::string xml, expect;
  };
  const std::vector<Case> cases = {
      {"<params><section name=\"Header\"></section></params>", "no <section name=\"Main Track\">"},
      {trackXml(""), "Main Track has no segments"},
      {trackXml(segmentXml("zig", "<attstr name=\"type\" val=\"zig\"/>\n")),
       "segment 'zig': type expected 'str', 'lft' or 'rgt', got 'zig'"},
      {trackXml(segmentXml("nolen", "<attstr name=\"type\" val=\"str\"/>\n")),
       "segment 'nolen': a straight needs 'lg'"},
      {trackXml(segmentXml("neg",
                           "<attstr name=\"type\" val=\"lft\"/><attnum name=\"radius\" "
                           "val=\"-5\"/><attnum name=\"arc\" val=\"1\"/>\n")),
       "segment 'neg': an arc needs 'radius'"},
      {trackXml(segmentXml("noarc",
                           "<attstr name=\"type\" val=\"rgt\"/><attnum name=\"radius\" "
                           "val=\"50\"/>\n")),
       "segment 'noarc': an arc needs 'arc'"},
      {trackXml(segmentXml("unit",
                           "<attstr name=\"type\" val=\"str\"/><attnum name=\"lg\" "
                           "unit=\"furlong\" val=\"3\"/>\n")),
       "unknown unit 'furlong'"},
      {trackXml(segmentXml("nan",
                           "<attstr name=\"type\" val=\"str\"/><attnum name=\"lg\" "
                           "val=\"12x\"/>\n")),
       "'lg' expected a number, got '12x'"},
      {"<params><section name=\"Main Track\"></params>", "where '</section>' was expected"},
      {"<params><section name=\"Main Track\">", "still open"},
      {"<params><section name=Main></section></params>", "value without quotes"},
      {"<params><!-- never closed", "comment never closed"},
  };
  for (const Case& c : cases) {
    auto d = parseTorcsTrackXml(c.xml, "bad.xml");
    ASSERT_FALSE(d.ok()) << c.expect;
    EXPECT_NE(d.error().message.find("bad.xml"), std::string::npos) << d.error().message;
    EXPECT_NE(d.error().message.find(c.expect), std::string::npos)
        << "expected '" << c.expect << "' in: " << d.error().message;
  }
  // The line is that of the segment's section (line 17 of trackXml's text).
  auto d = parseTorcsTrackXml(trackXml(segmentXml("zig", "<attstr name=\"type\" val=\"zig\"/>\n")),
                              "bad.xml");
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error().message.find("bad.xml:17:"), std::string::npos) << d.error().message;
  // Every truncation is an error or a description, never a crash.
  const std::string full = ovalXml();
  for (std::size_t n = 0; n < full.size(); n += 7) (void)parseTorcsTrackXml(full.substr(0, n), "t");
}

// A model of the oval: a road ribbon at height `roadY` (TORCS y → model −z,
// shifted by `offset`), with its edge vertices at the description's steps,
// plus scattered vertices that must not fool the registration.
Scene ribbonScene(const TorcsCentreline& c, glm::dvec2 offset, double roadY) {
  Scene s;
  s.name = "ribbon";
  s.materials.push_back(Material{});
  Mesh m;
  auto put = [&](const glm::dvec2& p) {
    Vertex v;
    v.position = glm::vec3(static_cast<float>(p.x + offset.x), static_cast<float>(roadY),
                           static_cast<float>(-p.y + offset.y));
    m.vertices.push_back(v);
  };
  for (const glm::dvec2& e : c.edgePoints) put(e);  // left, right, left, right …
  const std::uint32_t n = static_cast<std::uint32_t>(c.edgePoints.size());
  for (std::uint32_t k = 0; k + 1 < n; k += 2) {
    const std::uint32_t a = k, b = k + 1, cc = (k + 2) % n, d = (k + 3) % n;
    m.indices.insert(m.indices.end(), {a, b, cc, b, d, cc});
  }
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-150, 350);
  std::vector<Vertex> junk;
  for (int k = 0; k < 3000; ++k) {
    Vertex v;
    v.position = glm::vec3(static_cast<float>(u(rng)), 0.0f, static_cast<float>(u(rng)));
    m.vertices.push_back(v);
  }
  s.meshes.push_back(std::move(m));
  s.computeBounds();
  return s;
}

TEST(TorcsTrackXml, RegistrationFindsTheShiftAndTheDriveStaysOnTheRoad) {
  auto d = parseTorcsTrackXml(ovalXml(), "oval.xml");
  ASSERT_TRUE(d.ok());
  auto c = integrateTorcsCentreline(*d);
  ASSERT_TRUE(c.ok());
  const glm::dvec2 offset(63.25, 171.5);
  Ac3dModel model;
  model.scene = ribbonScene(*c, offset, 2.0);
  auto reg = registerTorcsCentreline(*c, model.scene);
  ASSERT_TRUE(reg.ok()) << reg.error().message;
  EXPECT_EQ(reg->zSign, -1.0);
  EXPECT_NEAR(reg->offset.x, offset.x, 1e-3);
  EXPECT_NEAR(reg->offset.y, offset.y, 1e-3);
  EXPECT_GT(reg->matchedFraction, 0.99);

  DrivePathOptions o;
  o.frames = 40;
  o.metresPerFrame = 5.0;  // 195 m
  o.eyeHeightMetres = 1.2;
  auto path = torcsDrivePath(model, *c, *reg, o);
  ASSERT_TRUE(path.ok()) << path.error().message;
  EXPECT_EQ(path->frames, 40);
  const auto cams = path->cameras();
  double driven = 0;
  for (std::size_t k = 0; k < cams.size(); ++k) {
    const glm::dvec3 e = cams[k].eye;
    EXPECT_NEAR(e.y, 3.2, 1e-3) << "frame " << k;
    // On the road: within half the width (6 m) of the centreline.
    const glm::dvec2 t(e.x - offset.x, -(e.z - offset.y));
    double best = 1e9;
    for (const auto& p : c->points) best = std::min(best, glm::length(p - t));
    EXPECT_LT(best, 1.0) << "frame " << k;
    if (k > 0) driven += glm::length(e - cams[k - 1].eye);
  }
  EXPECT_NEAR(driven, 5.0 * 39, 5.0);

  // A model that is not this track: an error, not a path through the void.
  Scene other = model.scene;
  for (Vertex& v : other.meshes[0].vertices) v.position.x *= 1.5f;
  EXPECT_FALSE(registerTorcsCentreline(*c, other).ok());
}

// Every track of the torcs-data package (needs `hybridwalk scenes fetch
// --outdoor`; fails, never skips, without it): its description parses,
// closes within 1 m and 0.1°, and lands on the model's vertices.
TEST(TorcsTrackReal, EveryTrackDescriptionClosesAndRegisters) {
  const std::string root = defaultSceneCacheDir() + "/root/usr/share/games/torcs";
  auto any = findTorcsTrack(root, "forza");
  ASSERT_TRUE(any.ok()) << any.error().message;
  const auto tracks = std::filesystem::path(*any).parent_path().parent_path().parent_path();
  int n = 0;
  for (const auto& cat : std::filesystem::directory_iterator(tracks))
    for (const auto& t : std::filesystem::directory_iterator(cat.path())) {
      const std::string name = t.path().filename().string();
      const std::string acc = (t.path() / (name + ".acc")).string();
      if (!std::filesystem::is_regular_file(acc)) continue;
      ++n;
      auto d = loadTorcsTrackXml(torcsDescriptionPathFor(acc));
      ASSERT_TRUE(d.ok()) << d.error().message;
      auto c = integrateTorcsCentreline(*d);
      ASSERT_TRUE(c.ok()) << c.error().message;
      EXPECT_LT(c->closureGapMetres, 1.0) << name;
      EXPECT_LT(c->closureDegrees, 0.1) << name;
      auto model = loadTorcsTrack(acc);
      ASSERT_TRUE(model.ok()) << model.error().message;
      auto reg = registerTorcsCentreline(*c, model->scene);
      ASSERT_TRUE(reg.ok()) << name << ": " << reg.error().message;
      EXPECT_GT(reg->matchedFraction, 0.95) << name;
    }
  EXPECT_GE(n, 20);
}

}  // namespace
}  // namespace hw::scenes
