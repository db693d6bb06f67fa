// Outdoor scenes: our AC3D parser on a file the test writes (TORCS texture
// layers, strips with degenerate triangles, two-sided surfaces, kids with
// loc/rot), every truncation of it, SGI images, the triangle grid against
// brute force; then the real TORCS/MORSE/OpenArena scenes and the committed
// camera paths (these need `hybridwalk scenes fetch` incl. the outdoor
// packages, and fail — never skip — without them).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "core/file_io.h"
#include "scenes/camera_path.h"
#include "scenes/fetch.h"
#include "scenes/loader.h"
#include "scenes/outdoor_scenes.h"
#include "scenes/sgi_image.h"
#include "scenes/q3bsp.h"

namespace hw::scenes {
namespace {

namespace fs = std::filesystem;

const char* const kFetchHint =
    " — the scene cache lacks it: run `hybridwalk scenes fetch` with the outdoor packages "
    "(scenes::fetchScenePackages(cache, true, /*outdoor=*/true): morse-simulator-data, torcs-data)";

fs::path sourceDir() {
  if (const char* s = std::getenv("HW_SOURCE_DIR"); s && *s) return s;
  return fs::path(__FILE__).parent_path().parent_path().parent_path();  // tests/cpu/x.cpp → repo
}

class OutdoorTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("hw_outdoor_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
            "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

// world ─┬─ "ground" (loc 10 0 0): base.png + 3 more TORCS layers; a quad
//        │   (2 triangles) and a 5-ref strip (3 triangles, the first
//        │   degenerate: refs 1 0 1).
//        └─ group (loc 0 5 0) ── "kid" (rot: 90° about +Y, loc 1 0 0): one
//            two-sided triangle (SURF 0x20), material 1, no normals in the file.
const char* const kAcc =
    "AC3Db\n"
    "MATERIAL \"grey\" rgb 0.4 0.4 0.4  amb 0.8 0.8 0.8  emis 0.4 0.4 0.4  spec 0.5 0.5 0.5  "
    "shi 50  trans 0\n"
    "MATERIAL \"red\" rgb 1 0 0  amb 0.2 0.2 0.2  emis 0 0 0  spec 0 0 0  shi 10  trans 0\n"
    "OBJECT world\n"
    "kids 2\n"
    "OBJECT poly\n"
    "name \"ground\"\n"
    "texture \"base.png\" base\n"
    "texture \"shadow2.rgb\" tiled\n"
    "texture empty_texture_no_mapping skids\n"
    "texture \"ERROR\" shad\n"
    "loc 10 0 0\n"
    "numvert 5\n"
    "0 0 0 0 1 0\n"
    "1 0 0 0 1 0\n"
    "1 0 -1 0 1 0\n"
    "0 0 -1 0 1 0\n"
    "2 0 0 0 1 0\n"
    "numsurf 2\n"
    "SURF 0x10\n"
    "mat 0\n"
    "refs 4\n"
    "0 0 0 0.5 0.5\n"
    "1 1 0 0.5 0.5\n"
    "2 1 1 0.5 0.5\n"
    "3 0 1 0.5 0.5\n"
    "SURF 0x14\n"
    "mat 0\n"
    "refs 5\n"
    "1 1 0\n"
    "0 0 0\n"
    "1 1 0\n"
    "2 1 1\n"
    "4 2 0\n"
    "kids 0\n"
    "OBJECT group\n"
    "loc 0 5 0\n"
    "kids 1\n"
    "OBJECT poly\n"
    "name \"kid\"\n"
    "rot 0 0 -1  0 1 0  1 0 0\n"
    "loc 1 0 0\n"
    "numvert 3\n"
    "0 0 0\n"
    "1 0 0\n"
    "0 1 0\n"
    "numsurf 1\n"
    "SURF 0x20\n"
    "mat 1\n"
    "refs 3\n"
    "0 0 0\n"
    "1 1 0\n"
    "2 0 1\n"
    "kids 0\n";

void writeBaseTexture(const fs::path& dir) {
  Image<Rgba8> img(2, 2);
  img(0, 0) = Rgba8{255, 0, 0, 255};
  img(1, 0) = Rgba8{0, 255, 0, 0};  // a cut-out texel → alpha test
  img(0, 1) = Rgba8{0, 0, 255, 255};
  img(1, 1) = Rgba8{255, 255, 255, 255};
  ASSERT_TRUE(writePng((dir / "base.png").string(), img).ok());
}

bool hasVertex(const Scene& s, glm::vec3 p, Vertex* out = nullptr) {
  for (const Mesh& m : s.meshes)
    for (const Vertex& v : m.vertices)
      if (glm::length(v.position - p) < 1e-5f) {
        if (out) *out = v;
        return true;
      }
  return false;
}

TEST_F(OutdoorTest, Ac3dBaseLayerDegenerateStripsTwoSidedAndKidTransforms) {
  writeBaseTexture(dir_);
  auto m = parseAc3d(kAcc, "test.acc", dir_.string());
  ASSERT_TRUE(m.ok()) << m.error().message;
  const Scene& s = m->scene;
  EXPECT_EQ(s.triangleCount(), 5u);  // quad 2 + strip 2 + kid 1
  EXPECT_EQ(m->stats.degenerateTriangles, 1u);
  EXPECT_EQ(m->stats.objects, 4u);
  EXPECT_EQ(m->stats.multiLayerObjects, 1u);
  EXPECT_EQ(m->stats.twoSidedSurfaces, 1u);
  EXPECT_EQ(m->stats.missingTextures, 0u);
  EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();

  // Only the base layer is a texture; ERROR/shadow2.rgb are never looked up.
  ASSERT_EQ(s.textures.size(), 1u);
  EXPECT_EQ(s.textures[0].name, "base.png");
  bool sawTextured = false, sawTwoSided = false;
  for (std::size_t i = 0; i < s.materials.size(); ++i) {
    const Material& mat = s.materials[i];
    if (mat.texture >= 0) {
      sawTextured = true;
      EXPECT_EQ(m->materialTextureNames[i], "base.png");
      EXPECT_TRUE(mat.alphaTest);
      EXPECT_FLOAT_EQ(mat.alphaCutoff, 0.5f);
      EXPECT_FALSE(mat.twoSided);
    } else {
      sawTwoSided = true;
      EXPECT_TRUE(mat.twoSided);
      EXPECT_FLOAT_EQ(mat.baseColour.r, 1.0f);
      EXPECT_FLOAT_EQ(mat.baseColour.g, 0.0f);
    }
  }
  EXPECT_TRUE(sawTextured);
  EXPECT_TRUE(sawTwoSided);

  // loc: the ground moved by +10 in x; uv v flipped (AC3D v = 0 at the bottom).
  Vertex v;
  ASSERT_TRUE(hasVertex(s, {10, 0, 0}, &v));
  EXPECT_FALSE(hasVertex(s, {0, 0, 0}));
  ASSERT_TRUE(hasVertex(s, {11, 0, -1}, &v));
  EXPECT_NEAR(v.uv.x, 1.0f, 1e-6f);
  EXPECT_NEAR(v.uv.y, 0.0f, 1e-6f);
  EXPECT_NEAR(v.normal.y, 1.0f, 1e-6f);

  // Kid: rot maps x → −z, then loc (1, 0, 0), then the group's (0, 5, 0).
  EXPECT_TRUE(hasVertex(s, {1, 5, 0}));
  ASSERT_TRUE(hasVertex(s, {1, 5, -1}, &v));
  EXPECT_TRUE(hasVertex(s, {1, 6, 0}));
  // No normals in the file: from the triangle, unit length, along +x.
  EXPECT_NEAR(glm::length(v.normal), 1.0f, 1e-5f);
  EXPECT_NEAR(std::abs(v.normal.x), 1.0f, 1e-5f);

  // Windings are kept as written: the quad and the kid are counter-clockwise
  // about their normals; the strip (GL order) is wound facing −y while its
  // file normals say +y.
  std::size_t up = 0, down = 0;
  for (const Mesh& mesh : s.meshes)
    for (std::size_t i = 0; i < mesh.indices.size(); i += 3) {
      const glm::vec3 a = mesh.vertices[mesh.indices[i]].position;
      const glm::vec3 n = glm::cross(mesh.vertices[mesh.indices[i + 1]].position - a,
                                     mesh.vertices[mesh.indices[i + 2]].position - a);
      (glm::dot(n, mesh.vertices[mesh.indices[i]].normal) > 0 ? up : down)++;
    }
  EXPECT_EQ(up, 3u);
  EXPECT_EQ(down, 2u);
}

TEST_F(OutdoorTest, Ac3dMissingTextureIsACheckerAndAWarning) {
  auto m = parseAc3d(kAcc, "test.acc", dir_.string());  // no base.png written
  ASSERT_TRUE(m.ok()) << m.error().message;
  EXPECT_EQ(m->stats.missingTextures, 1u);
  ASSERT_EQ(m->scene.warnings.size(), 1u);
  EXPECT_NE(m->scene.warnings[0].find("base.png"), std::string::npos) << m->scene.warnings[0];
}

TEST_F(OutdoorTest, Ac3dBadInputGivesLineNumbersAndEveryTruncationIsHandled) {
  auto notAc = parseAc3d("OBJ\nv 0 0 0\n", "x.acc", dir_.string());
  ASSERT_FALSE(notAc.ok());
  EXPECT_NE(notAc.error().message.find("x.acc:1"), std::string::npos) << notAc.error().message;

  std::string badRef = kAcc;
  badRef.replace(badRef.find("4 2 0\n"), 6, "9 2 0\n");
  auto r = parseAc3d(badRef, "bad.acc", dir_.string());
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("bad.acc:34"), std::string::npos) << r.error().message;
  EXPECT_NE(r.error().message.find("numvert 5"), std::string::npos) << r.error().message;

  std::string badMat = kAcc;
  badMat.replace(badMat.find("mat 1\n"), 6, "mat 7\n");
  EXPECT_FALSE(parseAc3d(badMat, "m.acc", dir_.string()).ok());

  // Each prefix either parses (kids counts may run short, as TORCS allows)
  // or gives an error naming the file; never a crash.
  const std::string full = kAcc;
  for (std::size_t n = 0; n < full.size(); ++n) {
    auto t = parseAc3d(full.substr(0, n), "t.acc", dir_.string());
    if (!t.ok()) {
      EXPECT_EQ(t.error().message.rfind("t.acc", 0), 0u) << t.error().message;
    }
  }
}

// SGI image bytes: 512-byte header, then planes (verbatim) or RLE tables.
std::string sgiHeader(int storage, int x, int y, int z) {
  std::string h(512, '\0');
  h[0] = '\x01', h[1] = '\xDA', h[2] = static_cast<char>(storage), h[3] = 1;
  h[5] = 3;
  h[6] = static_cast<char>(x >> 8), h[7] = static_cast<char>(x);
  h[8] = static_cast<char>(y >> 8), h[9] = static_cast<char>(y);
  h[10] = static_cast<char>(z >> 8), h[11] = static_cast<char>(z);
  return h;
}

TEST(Outdoor, SgiVerbatimAndRle) {
  // 2×2 RGBA, verbatim; SGI's row 0 is the bottom.
  std::string v = sgiHeader(0, 2, 2, 4);
  const unsigned char planes[16] = {10, 20, 30, 40, 1, 2, 3, 4, 5, 6, 7, 8, 255, 0, 128, 255};
  v.append(reinterpret_cast<const char*>(planes), 16);
  auto img = decodeSgiImage(v, "v.rgb");
  ASSERT_TRUE(img.ok()) << img.error().message;
  EXPECT_EQ((*img)(0, 1).r, 10);  // bottom-left
  EXPECT_EQ((*img)(1, 0).r, 40);  // top-right
  EXPECT_EQ((*img)(1, 0).a, 255);
  EXPECT_EQ((*img)(0, 1).a, 255);
  EXPECT_EQ((*img)(1, 1).a, 0);

  // 3×1 grey, RLE: a run of 2 × 7 then a literal 9.
  std::string r = sgiHeader(1, 3, 1, 1);
  auto be32 = [&](unsigned x) {
    for (int s = 24; s >= 0; s -= 8) r.push_back(static_cast<char>((x >> s) & 0xFF));
  };
  be32(520);
  be32(5);
  r += std::string("\x02\x07\x81\x09\x00", 5);
  auto g = decodeSgiImage(r, "r.bw");
  ASSERT_TRUE(g.ok()) << g.error().message;
  EXPECT_EQ((*g)(0, 0).g, 7);
  EXPECT_EQ((*g)(1, 0).b, 7);
  EXPECT_EQ((*g)(2, 0).r, 9);

  for (std::size_t n = 0; n < r.size(); ++n) EXPECT_FALSE(decodeSgiImage(r.substr(0, n), "t").ok());
}

TEST(Outdoor, TriangleGridAgreesWithBruteForce) {
  Scene s;
  s.materials.push_back(Material{});
  Mesh m;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-5.0f, 5.0f);
  for (int t = 0; t < 200; ++t)
    for (int k = 0; k < 3; ++k) {
      m.vertices.push_back(Vertex{{u(rng), u(rng) * 0.3f, u(rng)}});
      m.indices.push_back(static_cast<std::uint32_t>(m.vertices.size() - 1));
    }
  s.meshes.push_back(m);
  const TriangleGrid grid(s, 0.7);
  for (int i = 0; i < 300; ++i) {
    const glm::dvec3 p(u(rng), u(rng), u(rng));
    double brute = 2.0;
    for (std::size_t k = 0; k < m.indices.size(); k += 3)
      brute = std::min(brute,
                       pointTriangleDistance(p, m.vertices[k].position, m.vertices[k + 1].position,
                                             m.vertices[k + 2].position));
    EXPECT_NEAR(grid.distanceToNearest(p, 2.0), brute, 1e-9);
  }
  // Two stacked floors: a ray from above hits both, highest first.
  Scene f;
  f.materials.push_back(Material{});
  for (float y : {2.0f, 5.0f}) {
    Mesh q;
    q.vertices = {Vertex{{0, y, 0}}, Vertex{{0, y, 4}}, Vertex{{4, y, 4}}, Vertex{{4, y, 0}}};
    q.indices = {0, 1, 2, 0, 2, 3};
    f.meshes.push_back(q);
  }
  const TriangleGrid fg(f);
  const auto hits = fg.hitsBelow({1.0, 10.0, 3.0});
  ASSERT_EQ(hits.size(), 2u);
  EXPECT_NEAR(hits[0], 5.0, 1e-9);
  EXPECT_NEAR(hits[1], 2.0, 1e-9);
  EXPECT_EQ(fg.hitsBelow({1.0, 3.0, 3.0}).size(), 1u);
  EXPECT_TRUE(fg.hitsBelow({9.0, 10.0, 3.0}).empty());
  EXPECT_TRUE(fg.segmentClear({1, 3.5, 1}, {3, 3.5, 3}, 1.0));
  EXPECT_FALSE(fg.segmentClear({1, 3.5, 1}, {3, 4.5, 3}, 1.0));
}

// Copies of one triangle (corners in any order) are one surface to the grid:
// a model of 20000 identical faces answers as one face does.
TEST(Outdoor, TriangleGridDropsCoincidentCopies) {
  Scene s;
  s.materials.push_back(Material{});
  Mesh m;
  m.vertices = {Vertex{{0, 1, 0}}, Vertex{{4, 1, 0}}, Vertex{{0, 1, 4}}, Vertex{{0, 3, 0}}};
  for (int k = 0; k < 20000; ++k) {
    if (k % 2)
      m.indices.insert(m.indices.end(), {0, 1, 2});
    else
      m.indices.insert(m.indices.end(), {2, 0, 1});
  }
  m.indices.insert(m.indices.end(), {0, 1, 3});  // a different (vertical) face
  s.meshes.push_back(m);
  const TriangleGrid grid(s, 0.5);
  EXPECT_EQ(grid.triangleCount(), 2u);
  const auto hits = grid.hitsBelow({1.0, 10.0, 1.0});
  ASSERT_EQ(hits.size(), 1u);
  EXPECT_NEAR(hits[0], 1.0, 1e-9);
  EXPECT_NEAR(grid.distanceToNearest({1.0, 1.5, 1.0}, 2.0), 0.5, 1e-9);
}

// ---------------------------------------------------------------- real data

Result<Scene> realScene(const std::string& spec) {
  auto s = loadScene(spec);
  if (!s.ok()) ADD_FAILURE() << spec << ": " << s.error().message << kFetchHint;
  return s;
}

TEST(OutdoorReal, TorcsForza) {
  auto file = outdoorSpecFile("torcs:forza", defaultSceneCacheDir());
  ASSERT_TRUE(file.has_value());
  ASSERT_TRUE(file->ok()) << file->error().message << kFetchHint;
  auto t = loadTorcsTrack(**file);
  ASSERT_TRUE(t.ok()) << t.error().message;
  EXPECT_GT(t->scene.triangleCount(), 50'000u);
  EXPECT_GT(t->stats.degenerateTriangles, 0u);  // the strips Assimp's validation rejects
  EXPECT_EQ(t->stats.missingTextures, 0u);
  for (const std::string& n : t->materialTextureNames) EXPECT_NE(n, "ERROR");
  std::size_t alpha = 0, twoSided = 0;
  for (const Material& m : t->scene.materials) {
    alpha += m.alphaTest;
    twoSided += m.twoSided;
  }
  EXPECT_GT(alpha, 10u);  // trees and fences
  EXPECT_GT(twoSided, 0u);
  // Y-up already (AC3D's own axes): the track is flat and wide.
  const glm::vec3 ext = t->scene.boundsMax - t->scene.boundsMin;
  EXPECT_LT(ext.y, 0.1f * std::max(ext.x, ext.z));
}

TEST(OutdoorReal, MorseTreesSkyBoxAndCollisionBoxesHidden) {
  auto s = realScene("morse:land-1/trees");
  ASSERT_TRUE(s.ok());
  EXPECT_GT(s->triangleCount(), 700'000u);
  // The SkyBox is a 500 m cube; the terrain spans ~120 × 150 m.
  EXPECT_LT(s->boundsMax.y - s->boundsMin.y, 50.0f);
  EXPECT_LT(s->boundsMax.x - s->boundsMin.x, 200.0f);
  for (const Mesh& m : s->meshes) {
    const std::string& mat = s->materials[static_cast<std::size_t>(m.material)].name;
    EXPECT_NE(mat, "SkyBoxMat");
    EXPECT_NE(mat, "DefaultMaterial");  // the BB_ collision cubes
  }
}

TEST(OutdoorReal, CommittedPathsParse) {
  for (const char* name : {"oa_dm5", "forza", "trees"}) {
    const fs::path p = sourceDir() / "paths" / (std::string(name) + ".json");
    auto path = loadCameraPath(p.string());
    ASSERT_TRUE(path.ok()) << p << ": " << path.error().message;
    EXPECT_EQ(path->frames, 240) << name;
    EXPECT_EQ(path->keyframeEvery, 10) << name;
    EXPECT_EQ(path->width, 512) << name;
    EXPECT_EQ(path->height, 512) << name;
    EXPECT_DOUBLE_EQ(path->fovYDeg, 60.0) << name;
    EXPECT_GE(path->keys.size(), 10u) << name;
  }
}

// Samples `n` cameras along the path at constant speed.
std::vector<glm::dvec3> sampleEyes(CameraPath path, int n) {
  path.frames = n;
  std::vector<glm::dvec3> eyes;
  for (int i = 0; i < n; ++i) eyes.push_back(path.cameraAt(i).eye);
  return eyes;
}

TEST(OutdoorReal, OaDm5PathKeepsClearOfWallsAtEyeHeight) {
  auto path = loadCameraPath((sourceDir() / "paths" / "oa_dm5.json").string());
  ASSERT_TRUE(path.ok()) << path.error().message;
  auto scene = realScene("q3:oa_dm5");
  ASSERT_TRUE(scene.ok());
  const TriangleGrid grid(*scene, 1.0);
  double minClear = 1e9, length = 0;
  const auto eyes = sampleEyes(*path, 2000);
  for (std::size_t i = 0; i < eyes.size(); ++i) {
    const double d = grid.distanceToNearest(eyes[i], 1.0);
    EXPECT_GE(d, 0.2) << "sample " << i << " at " << eyes[i].x << "," << eyes[i].y << ","
                      << eyes[i].z;
    minClear = std::min(minClear, d);
    if (i) length += glm::length(eyes[i] - eyes[i - 1]);
    // Walking: a floor 1.27 m (the game's eye height) below some part of
    // the player's 0.8 m box (rays at its centre and ±0.3 m), give or take
    // one stair step (16 units = 0.41 m; the eye climbs stairs linearly).
    double support = 1e9;
    for (const glm::dvec3 o : {glm::dvec3(0), glm::dvec3(0.3, 0, 0), glm::dvec3(-0.3, 0, 0),
                               glm::dvec3(0, 0, 0.3), glm::dvec3(0, 0, -0.3)}) {
      const auto hits = grid.hitsBelow(eyes[i] + o);
      if (!hits.empty()) support = std::min(support, std::abs(eyes[i].y - hits[0] - 1.27));
    }
    EXPECT_LE(support, 0.45) << "sample " << i << " at " << eyes[i].x << "," << eyes[i].y << ","
                             << eyes[i].z;
  }
  EXPECT_GT(length, 30.0);  // several rooms, not one
  RecordProperty("min_clearance_m", std::to_string(minClear));
}

TEST(OutdoorReal, ForzaPathDrivesOnTheRoad) {
  auto path = loadCameraPath((sourceDir() / "paths" / "forza.json").string());
  ASSERT_TRUE(path.ok()) << path.error().message;
  auto scene = realScene("torcs:forza");
  ASSERT_TRUE(scene.ok());
  const TriangleGrid grid(*scene, 4.0);
  for (const glm::dvec3& e : sampleEyes(*path, 200)) {
    const auto hits = grid.hitsBelow(e);
    ASSERT_FALSE(hits.empty()) << e.x << "," << e.z;
    EXPECT_NEAR(e.y - hits[0], 1.2, 0.35) << e.x << "," << e.z;
  }
}

TEST(OutdoorReal, TreesPathWalksAtEyeHeight) {
  auto path = loadCameraPath((sourceDir() / "paths" / "trees.json").string());
  ASSERT_TRUE(path.ok()) << path.error().message;
  auto scene = realScene("morse:land-1/trees");
  ASSERT_TRUE(scene.ok());
  const TriangleGrid grid(*scene);
  for (const CameraKey& k : path->keys) {
    const auto hits = grid.hitsBelow(k.eye);
    ASSERT_FALSE(hits.empty());
    EXPECT_NEAR(k.eye.y - hits.back(), 1.7, 1e-6);       // the lowest surface: the terrain
    EXPECT_GT(grid.distanceToNearest(k.eye, 0.5), 0.3);  // not inside a trunk or leaves
  }
}

}  // namespace
}  // namespace hw::scenes
