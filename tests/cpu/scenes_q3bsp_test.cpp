// Quake 3 BSP loader on maps the test builds: one polygon and one 3×3 patch
// in a .pk3 made with libzip, with a hand-written TGA. Checks triangle counts
// (2·L² per patch piece), the Z-up → Y-up conversion, windings against
// normals, texture lookup as the game does it, spawns; and that every kind of
// corrupt BSP or pk3 gives an error naming the file instead of a crash.
#include <gtest/gtest.h>
#include <unistd.h>
#include <zip.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "core/file_io.h"
#include "scenes/fetch.h"
#include "scenes/outdoor_scenes.h"
#include "scenes/q3bsp.h"

namespace hw::scenes {
namespace {

namespace fs = std::filesystem;

constexpr double kU = kQ3MetresPerUnit;

// ---------------------------------------------------------------------------
// A minimal IBSP 46 writer.

struct BspVert {
  float x, y, z, s, t, nx, ny, nz;
};
struct BspFace {
  int shader = 0, type = 1, firstVert = 0, numVerts = 0, firstIndex = 0, numIndexes = 0;
  int patchW = 0, patchH = 0;
};
struct BspShader {
  std::string name;
  int flags = 0, contents = 0;
};

struct TestBsp {
  std::string magic = "IBSP";
  int version = 46;
  std::string entities =
      "{\n\"classname\" \"worldspawn\"\n}\n"
      "{\n\"classname\" \"info_player_deathmatch\"\n\"origin\" \"10 20 30\"\n\"angle\" \"90\"\n}\n";
  std::vector<BspShader> shaders{{"textures/test/wall", 0, 1}};
  std::vector<BspVert> verts;
  std::vector<std::int32_t> indexes;
  std::vector<BspFace> faces;

  // A floor quad x ∈ [0, 100], y ∈ [0, 200] at z = 0 facing +z, wound
  // clockwise seen from above as Quake does; and a 3×3 patch arching along
  // x ∈ [0, 100] over y ∈ [300, 400], control height 50 in the middle
  // (the surface peaks at 25).
  TestBsp() {
    verts = {{0, 0, 0, 0, 0, 0, 0, 1},
             {0, 200, 0, 0, 2, 0, 0, 1},
             {100, 200, 0, 1, 2, 0, 0, 1},
             {100, 0, 0, 1, 0, 0, 0, 1}};
    indexes = {0, 1, 2, 0, 2, 3};
    faces.push_back({0, 1, 0, 4, 0, 6});
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i)
        verts.push_back(
            {50.0f * i, 300.0f + 50.0f * j, i == 1 ? 50.0f : 0.0f, 0.5f * i, 0.5f * j, 0, 0, 1});
    BspFace patch;
    patch.type = 2, patch.firstVert = 4, patch.numVerts = 9, patch.patchW = 3, patch.patchH = 3;
    faces.push_back(patch);
  }

  std::string bytes() const {
    std::string lumps[17];
    lumps[0] = entities + std::string(1, '\0');
    for (const BspShader& s : shaders) {
      std::string rec(72, '\0');
      std::memcpy(rec.data(), s.name.data(), std::min<std::size_t>(s.name.size(), 64));
      std::memcpy(rec.data() + 64, &s.flags, 4);
      std::memcpy(rec.data() + 68, &s.contents, 4);
      lumps[1] += rec;
    }
    for (const BspVert& v : verts) {
      std::string rec(44, '\0');
      const float f[10] = {v.x, v.y, v.z, v.s, v.t, 0, 0, v.nx, v.ny, v.nz};
      std::memcpy(rec.data(), f, 40);
      rec[40] = rec[41] = rec[42] = rec[43] = static_cast<char>(255);
      lumps[10] += rec;
    }
    lumps[11].assign(reinterpret_cast<const char*>(indexes.data()), indexes.size() * 4);
    for (const BspFace& f : faces) {
      std::int32_t rec[26] = {};
      rec[0] = f.shader, rec[1] = -1, rec[2] = f.type, rec[3] = f.firstVert, rec[4] = f.numVerts;
      rec[5] = f.firstIndex, rec[6] = f.numIndexes, rec[7] = -1;
      rec[24] = f.patchW, rec[25] = f.patchH;
      lumps[13].append(reinterpret_cast<const char*>(rec), sizeof rec);
    }
    std::string out = magic.substr(0, 4);
    out.resize(4, '\0');
    out.append(reinterpret_cast<const char*>(&version), 4);
    std::int32_t offset = 8 + 17 * 8;
    std::string body;
    for (const std::string& l : lumps) {
      const std::int32_t len = static_cast<std::int32_t>(l.size());
      out.append(reinterpret_cast<const char*>(&offset), 4);
      out.append(reinterpret_cast<const char*>(&len), 4);
      body += l;
      offset += len;
    }
    return out + body;
  }
};

void setLump(std::string& bsp, int lump, std::int32_t offset, std::int32_t length) {
  std::memcpy(bsp.data() + 8 + 8 * lump, &offset, 4);
  std::memcpy(bsp.data() + 12 + 8 * lump, &length, 4);
}

// An uncompressed 32-bit TGA, top-left origin, from RGBA pixels.
std::string tga(int w, int h, const std::vector<Rgba8>& px) {
  std::string t(18, '\0');
  t[2] = 2;  // uncompressed true-colour
  t[12] = static_cast<char>(w), t[13] = static_cast<char>(w >> 8);
  t[14] = static_cast<char>(h), t[15] = static_cast<char>(h >> 8);
  t[16] = 32;
  t[17] = 0x28;  // 8 alpha bits, top-left origin
  for (const Rgba8& p : px)
    t += {static_cast<char>(p.b), static_cast<char>(p.g), static_cast<char>(p.r),
          static_cast<char>(p.a)};
  return t;
}

const std::vector<Rgba8> kWallPixels = {
    {255, 0, 0, 255}, {0, 255, 0, 255}, {0, 0, 255, 255}, {255, 255, 255, 255}};

// Writes a zip with libzip; entries are (name, bytes).
void writeZip(const std::string& path,
              const std::vector<std::pair<std::string, std::string>>& files) {
  int err = 0;
  zip_t* z = zip_open(path.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &err);
  ASSERT_NE(z, nullptr) << "zip_open error " << err;
  for (const auto& [name, data] : files) {
    zip_source_t* src = zip_source_buffer(z, data.data(), data.size(), 0);
    ASSERT_NE(src, nullptr);
    ASSERT_GE(zip_file_add(z, name.c_str(), src, ZIP_FL_OVERWRITE), 0) << zip_strerror(z);
  }
  ASSERT_EQ(zip_close(z), 0) << zip_strerror(z);
}

class Q3BspTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("hw_q3bsp_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // pk3 with maps/test.bsp and textures/test/wall.tga.
  std::string writePk3(const std::string& name, const std::string& bsp) {
    const std::string path = (dir_ / name).string();
    writeZip(path, {{"maps/test.bsp", bsp}, {"textures/test/wall.tga", tga(2, 2, kWallPixels)}});
    return path;
  }
  std::string writeRaw(const std::string& name, const std::string& bytes) {
    const std::string path = (dir_ / name).string();
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
  }

  fs::path dir_;
};

Q3Options withPk3s(std::vector<std::string> pk3s, int level = 8) {
  Q3Options o;
  o.pk3Paths = std::move(pk3s);
  o.patchSubdivisions = level;
  return o;
}

const Mesh* meshOf(const Scene& s, const std::string& shader) {
  for (const Mesh& m : s.meshes)
    if (s.materials[static_cast<std::size_t>(m.material)].name == shader) return &m;
  return nullptr;
}

// ---------------------------------------------------------------------------

TEST_F(Q3BspTest, LoadsPolygonPatchTextureAndSpawnFromPk3) {
  const std::string pk3 = writePk3("test.pk3", TestBsp().bytes());
  for (int level : {1, 4, 8}) {
    auto map = loadQ3Map("test", withPk3s({pk3}, level));
    ASSERT_TRUE(map.ok()) << map.error().message;
    const Scene& s = map->scene;
    // 2 for the quad, 2·L² for the single 3×3 patch piece.
    EXPECT_EQ(s.triangleCount(), 2u + 2u * static_cast<std::size_t>(level * level)) << level;
    EXPECT_EQ(map->stats.patches, 1u);
    EXPECT_EQ(map->stats.missingTextures, 0u);
    EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
    // (x, y, z) → (x, z, −y) metres; the arch peaks at 25 units.
    EXPECT_NEAR(s.boundsMin.x, 0.0, 1e-5);
    EXPECT_NEAR(s.boundsMin.y, 0.0, 1e-5);
    EXPECT_NEAR(s.boundsMin.z, -400 * kU, 1e-5);
    EXPECT_NEAR(s.boundsMax.x, 100 * kU, 1e-5);
    EXPECT_NEAR(s.boundsMax.y, level % 2 == 0 ? 25 * kU : 0.0, 1e-5);
    EXPECT_NEAR(s.boundsMax.z, 0.0, 1e-5);
  }

  auto map = loadQ3Map("test", withPk3s({pk3}));
  ASSERT_TRUE(map.ok()) << map.error().message;
  const Scene& s = map->scene;
  ASSERT_EQ(s.textures.size(), 1u);
  const Texture& t = s.textures[0];
  ASSERT_EQ(t.image.width(), 2);
  ASSERT_EQ(t.image.height(), 2);
  EXPECT_EQ(t.image(0, 0), kWallPixels[0]);  // row 0 = top, as the TGA's origin says
  EXPECT_EQ(t.image(1, 1), kWallPixels[3]);
  EXPECT_NE(t.name.find("textures/test/wall.tga"), std::string::npos) << t.name;

  ASSERT_EQ(map->spawns.size(), 1u);
  const Q3Spawn& sp = map->spawns[0];
  EXPECT_EQ(sp.classname, "info_player_deathmatch");
  EXPECT_NEAR(sp.origin.x, 10 * kU, 1e-9);
  EXPECT_NEAR(sp.origin.y, 30 * kU, 1e-9);
  EXPECT_NEAR(sp.origin.z, -20 * kU, 1e-9);
  EXPECT_NEAR(sp.eye.y, (30 + Q3Options{}.eyeHeightUnits) * kU, 1e-9);
  // Yaw 90° looks along Quake +y, which is our −z.
  EXPECT_NEAR(sp.forward.x, 0.0, 1e-9);
  EXPECT_NEAR(sp.forward.z, -1.0, 1e-9);
}

// Every triangle is counter-clockwise seen from its front: its geometric
// normal agrees with its vertices' normals, and the floor and the arch's
// top face up (+Y).
TEST_F(Q3BspTest, WindingIsCounterClockwiseAndAgreesWithNormals) {
  auto map = parseQ3Bsp(TestBsp().bytes(), "test.bsp", nullptr, {});
  ASSERT_TRUE(map.ok()) << map.error().message;
  EXPECT_EQ(map->stats.windingDisagreements, 0u);
  std::size_t checked = 0;
  for (const Mesh& m : map->scene.meshes)
    for (std::size_t i = 0; i < m.indices.size(); i += 3) {
      const Vertex& a = m.vertices[m.indices[i]];
      const Vertex& b = m.vertices[m.indices[i + 1]];
      const Vertex& c = m.vertices[m.indices[i + 2]];
      const glm::vec3 g = glm::cross(b.position - a.position, c.position - a.position);
      EXPECT_GT(glm::dot(g, a.normal + b.normal + c.normal), 0.0f);
      EXPECT_GT(g.y, 0.0f);  // all of this map faces up
      ++checked;
    }
  EXPECT_EQ(checked, 2u + 128u);
  // The arch's normals are unit length and tilt toward ±x away from its ridge.
  for (const Mesh& m : map->scene.meshes)
    for (const Vertex& v : m.vertices) {
      EXPECT_NEAR(glm::length(v.normal), 1.0f, 1e-4f);
      if (v.position.x < 0.2f * 100 * kU && v.position.z < -300 * kU + 1e-4) {
        EXPECT_LT(v.normal.x, -0.1f);
      }
    }
  // A texture resolver that is never given returns placeholders + warnings.
  EXPECT_EQ(map->stats.missingTextures, 1u);
  EXPECT_EQ(map->scene.warnings.size(), 1u);
}

TEST_F(Q3BspTest, PatchUvsInterpolateControlPoints) {
  auto map = parseQ3Bsp(TestBsp().bytes(), "test.bsp", nullptr, {});
  ASSERT_TRUE(map.ok()) << map.error().message;
  // Control st are (0.5 i, 0.5 j), linear in the grid, so the patch's uv is
  // linear in position: s = x / 100, t = (y − 300) / 100 (Quake units).
  for (const Mesh& m : map->scene.meshes)
    for (const Vertex& v : m.vertices) {
      const double qx = v.position.x / kU, qy = -v.position.z / kU;
      if (qy < 250) continue;  // the floor quad
      EXPECT_NEAR(v.uv.x, qx / 100.0, 1e-4);
      EXPECT_NEAR(v.uv.y, (qy - 300.0) / 100.0, 1e-4);
    }
}

TEST_F(Q3BspTest, SkipsSkyNodrawFogAndToolShadersAndBillboards) {
  for (const BspShader& skip : std::vector<BspShader>{{"textures/skies/blue", 0, 0},
                                                      {"textures/x/nice", 0x4, 0},
                                                      {"textures/x/nice", 0x80, 0},
                                                      {"textures/x/nice", 0, 0x40},
                                                      {"textures/common/caulk", 0, 1},
                                                      {"textures/common/weapclip", 0, 1},
                                                      {"textures/common/trigger", 0, 1}}) {
    TestBsp b;
    b.shaders.push_back(skip);
    b.faces[1].shader = 1;  // the patch
    auto map = parseQ3Bsp(b.bytes(), "test.bsp", nullptr, {});
    ASSERT_TRUE(map.ok()) << map.error().message;
    EXPECT_EQ(map->scene.triangleCount(), 2u) << skip.name << " " << skip.flags;
    EXPECT_EQ(map->stats.skippedFaces, 1u);
  }
  TestBsp b;
  b.faces[0].type = 4;  // billboard
  auto map = parseQ3Bsp(b.bytes(), "test.bsp", nullptr, {});
  ASSERT_TRUE(map.ok()) << map.error().message;
  EXPECT_EQ(map->scene.triangleCount(), 128u);

  b.faces[1].type = 4;
  auto none = parseQ3Bsp(b.bytes(), "test.bsp", nullptr, {});
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.error().message.find("no drawable faces"), std::string::npos);
}

TEST_F(Q3BspTest, GroupsFacesPerMaterialAndChunk) {
  Q3Options o;
  o.chunkSizeUnits = 250;  // floor centre (50, 100) and patch centre (50, 350) in different cells
  auto map = parseQ3Bsp(TestBsp().bytes(), "test.bsp", nullptr, o);
  ASSERT_TRUE(map.ok()) << map.error().message;
  EXPECT_EQ(map->scene.meshes.size(), 2u);
  o.chunkSizeUnits = 4096;
  map = parseQ3Bsp(TestBsp().bytes(), "test.bsp", nullptr, o);
  ASSERT_TRUE(map.ok()) << map.error().message;
  EXPECT_EQ(map->scene.meshes.size(), 1u);
}

// Later pk3s override earlier ones; a shader script's image stage, cull and
// alphaFunc are used; .tga is preferred to .jpg; a missing texture is a
// placeholder plus a warning naming the shader.
TEST_F(Q3BspTest, TexturesResolvedAsTheGameDoes) {
  TestBsp b;
  b.shaders.push_back({"textures/test/scripted", 0, 1});
  b.shaders.push_back({"textures/test/missing", 0, 1});
  b.faces[1].shader = 1;
  BspFace third = b.faces[0];
  third.shader = 2;
  b.faces.push_back(third);
  const std::vector<Rgba8> grey(4, Rgba8{128, 128, 128, 255});
  const std::string a = (dir_ / "pak0.pk3").string(), c = (dir_ / "pak1.pk3").string();
  writeZip(a, {{"maps/test.bsp", b.bytes()},
               {"textures/test/wall.tga", tga(2, 2, grey)},
               {"textures/test/glass.tga", tga(2, 2, kWallPixels)}});
  writeZip(c, {{"TEXTURES/Test/Wall.TGA", tga(2, 2, kWallPixels)},  // case-insensitive
               {"scripts/test.shader",
                "// comment\ntextures/test/scripted\n{\n  cull none\n  {\n    map $lightmap\n  }\n"
                "  {\n    map textures/test/glass.tga\n    alphaFunc GE128\n  }\n}\n"}});
  auto map = loadQ3Map("test", withPk3s({a, c}));
  ASSERT_TRUE(map.ok()) << map.error().message;
  const Scene& s = map->scene;
  const Mesh* wall = meshOf(s, "textures/test/wall");
  const Mesh* scripted = meshOf(s, "textures/test/scripted");
  const Mesh* missing = meshOf(s, "textures/test/missing");
  ASSERT_TRUE(wall && scripted && missing);
  const Material& mw = s.materials[static_cast<std::size_t>(wall->material)];
  const Material& ms = s.materials[static_cast<std::size_t>(scripted->material)];
  EXPECT_EQ(s.textures[static_cast<std::size_t>(mw.texture)].image(0, 0), kWallPixels[0])
      << "the later pk3's wall.tga should win";
  EXPECT_NE(s.textures[static_cast<std::size_t>(ms.texture)].name.find("glass.tga"),
            std::string::npos);
  EXPECT_TRUE(ms.twoSided);
  EXPECT_TRUE(ms.alphaTest);
  EXPECT_FALSE(mw.twoSided);
  EXPECT_EQ(map->stats.missingTextures, 1u);
  ASSERT_EQ(s.warnings.size(), 2u);
  EXPECT_NE(s.warnings[0].find("textures/test/missing"), std::string::npos) << s.warnings[0];
  // What the scripted shader does that is not drawn: its lightmap stage.
  EXPECT_NE(s.warnings[1].find("shader features not drawn"), std::string::npos) << s.warnings[1];
  EXPECT_NE(s.warnings[1].find("lightmaps (1)"), std::string::npos) << s.warnings[1];
}

// Two shaders drawing the same image: it is decoded once and kept once (the
// loader's resolver answers the second with sameAsEarlier, no copy), and both
// materials use the one texture; a sky shader may reuse an image too.
TEST_F(Q3BspTest, SharedImageIsDecodedAndKeptOnce) {
  TestBsp b;
  b.shaders.push_back({"textures/test/alias", 0, 1});
  b.faces[1].shader = 1;
  const std::string a = (dir_ / "pak0.pk3").string();
  writeZip(a, {{"maps/test.bsp", b.bytes()},
               {"textures/test/wall.tga", tga(2, 2, kWallPixels)},
               {"scripts/test.shader",
                "textures/test/alias\n{\n  {\n    map textures/test/wall.tga\n  }\n}\n"}});
  auto map = loadQ3Map("test", withPk3s({a}));
  ASSERT_TRUE(map.ok()) << map.error().message;
  const Scene& s = map->scene;
  ASSERT_EQ(s.materials.size(), 2u);
  EXPECT_EQ(s.textures.size(), 1u);
  EXPECT_EQ(s.materials[0].texture, s.materials[1].texture);
  EXPECT_EQ(map->stats.missingTextures, 0u);
  EXPECT_EQ(s.textures[0].image.width(), 2);

  TestBsp sky;
  sky.shaders.push_back({"textures/skies/blue", 0x4, 0});
  sky.faces[1].shader = 1;
  int calls = 0;
  auto shared = parseQ3Bsp(sky.bytes(), "s.bsp", [&](const std::string&) {
    Q3Texture t;
    t.path = "p.pk3:textures/one.tga";
    if (calls++ == 0)
      t.image = Image<Rgba8>(2, 2);
    else
      t.sameAsEarlier = true;
    return t;
  });
  ASSERT_TRUE(shared.ok()) << shared.error().message;
  EXPECT_EQ(calls, 2);
  EXPECT_EQ(shared->stats.skyFaces, 1u);
  EXPECT_EQ(shared->scene.textures.size(), 1u);
  EXPECT_EQ(shared->stats.missingTextures, 0u);
}

// A stage's tcMod scale multiplies the texture coordinates; a sky face is
// drawn (unlit, flagged sky, left out of ray queries) when its shader has an
// image, and skipped as before when not.
TEST_F(Q3BspTest, TcModScaleAndSkyFaces) {
  TestBsp b;
  auto plain = parseQ3Bsp(b.bytes(), "t.bsp", [](const std::string&) {
    Q3Texture t;
    t.image = Image<Rgba8>(2, 2);
    return t;
  });
  auto scaled = parseQ3Bsp(b.bytes(), "t.bsp", [](const std::string&) {
    Q3Texture t;
    t.image = Image<Rgba8>(2, 2);
    t.uvScale = glm::vec2(2.0f, 0.5f);
    return t;
  });
  ASSERT_TRUE(plain.ok() && scaled.ok());
  const Mesh& mp = plain->scene.meshes[0];
  const Mesh& ms = scaled->scene.meshes[0];
  ASSERT_EQ(mp.vertices.size(), ms.vertices.size());
  bool nonzero = false;
  for (std::size_t k = 0; k < mp.vertices.size(); ++k) {
    EXPECT_FLOAT_EQ(ms.vertices[k].uv.x, 2.0f * mp.vertices[k].uv.x);
    EXPECT_FLOAT_EQ(ms.vertices[k].uv.y, 0.5f * mp.vertices[k].uv.y);
    nonzero = nonzero || mp.vertices[k].uv != glm::vec2(0.0f);
  }
  EXPECT_TRUE(nonzero);

  TestBsp sky;
  sky.shaders.push_back({"textures/skies/blue", 0x4, 0});
  sky.faces[1].shader = 1;
  auto drawn = parseQ3Bsp(sky.bytes(), "s.bsp", [](const std::string&) {
    Q3Texture t;
    t.image = Image<Rgba8>(2, 2);
    return t;
  });
  ASSERT_TRUE(drawn.ok()) << drawn.error().message;
  EXPECT_EQ(drawn->stats.skyFaces, 1u);
  EXPECT_EQ(drawn->stats.skippedFaces, 0u);
  std::size_t skyMaterials = 0;
  for (const Material& m : drawn->scene.materials)
    if (m.sky) {
      ++skyMaterials;
      EXPECT_TRUE(m.unlit);
    }
  EXPECT_EQ(skyMaterials, 1u);
  const TriangleGrid grid(drawn->scene);
  EXPECT_EQ(grid.triangleCount(), 2u);  // the sky patch is not a surface
  auto skipped = parseQ3Bsp(sky.bytes(), "s.bsp", nullptr);
  ASSERT_TRUE(skipped.ok());
  EXPECT_EQ(skipped->stats.skyFaces, 0u);
  EXPECT_EQ(skipped->stats.skippedFaces, 1u);
}

TEST_F(Q3BspTest, ListsMapsAndReadsSpawnsOnly) {
  const std::string pk3 = writePk3("test.pk3", TestBsp().bytes());
  auto maps = listQ3Maps({pk3});
  ASSERT_TRUE(maps.ok()) << maps.error().message;
  EXPECT_EQ(*maps, std::vector<std::string>{"test"});
  auto spawns = q3Spawns("test", withPk3s({pk3}));
  ASSERT_TRUE(spawns.ok()) << spawns.error().message;
  EXPECT_EQ(spawns->size(), 1u);
}

TEST_F(Q3BspTest, FindPk3sIsRecursiveAndAlphabetical) {
  fs::create_directories(dir_ / "b" / "sub");
  fs::create_directories(dir_ / "a");
  for (const char* p : {"b/sub/z.pk3", "b/pak1.PK3", "a/pak9.pk3", "b/pak0.pk3", "a/readme.txt"})
    writeRaw(p, "x");
  const auto found = findPk3s(dir_.string());
  ASSERT_EQ(found.size(), 4u);
  EXPECT_EQ(fs::path(found[0]).lexically_relative(dir_).string(), "a/pak9.pk3");
  EXPECT_EQ(fs::path(found[1]).lexically_relative(dir_).string(), "b/pak0.pk3");
  EXPECT_EQ(fs::path(found[2]).lexically_relative(dir_).string(), "b/pak1.PK3");
  EXPECT_EQ(fs::path(found[3]).lexically_relative(dir_).string(), "b/sub/z.pk3");
  EXPECT_TRUE(findPk3s((dir_ / "nope").string()).empty());
}

// The walk goes from spawn to spawn only where they see each other.
TEST_F(Q3BspTest, SpawnWalkFollowsLinesOfSight) {
  TestBsp b;
  b.entities =
      "{ \"classname\" \"info_player_deathmatch\" \"origin\" \"20 20 24\" \"angle\" \"0\" }\n"
      "{ \"classname\" \"info_player_start\" \"origin\" \"80 180 24\" }\n";
  auto open = parseQ3Bsp(b.bytes(), "t.bsp", nullptr, {});
  ASSERT_TRUE(open.ok()) << open.error().message;
  CameraPath p = q3SpawnWalk(*open);
  ASSERT_EQ(p.keys.size(), 2u);
  EXPECT_NEAR(glm::length(p.keys[0].eye - open->spawns[0].eye), 0.0, 1e-9);
  EXPECT_NEAR(glm::length(p.keys[1].eye - open->spawns[1].eye), 0.0, 1e-9);
  // Along the way, looking down at most 15° (this map is a bare floor:
  // looking level would see mostly void).
  const glm::dvec3 gaze = glm::normalize(p.keys[0].lookAt - p.keys[0].eye);
  EXPECT_LE(gaze.y, 1e-9);
  EXPECT_GE(gaze.y, -std::sin(15.0 * 3.14159265358979 / 180.0) - 1e-9);
  EXPECT_EQ(p.frames, 120);
  EXPECT_EQ(p.keyframeEvery, 10);
  EXPECT_DOUBLE_EQ(p.nearPlane, 0.05);

  // A wall at y = 100 (x ∈ [0, 100], z ∈ [0, 100]) between them.
  const int v0 = static_cast<int>(b.verts.size());
  b.verts.push_back({0, 100, 0, 0, 0, 0, -1, 0});
  b.verts.push_back({0, 100, 100, 0, 1, 0, -1, 0});
  b.verts.push_back({100, 100, 100, 1, 1, 0, -1, 0});
  b.verts.push_back({100, 100, 0, 1, 0, 0, -1, 0});
  const int i0 = static_cast<int>(b.indexes.size());
  b.indexes.insert(b.indexes.end(), {0, 1, 2, 0, 2, 3});
  b.faces.push_back({0, 1, v0, 4, i0, 6});
  auto walled = parseQ3Bsp(b.bytes(), "t.bsp", nullptr, {});
  ASSERT_TRUE(walled.ok()) << walled.error().message;
  p = q3SpawnWalk(*walled);
  ASSERT_EQ(p.keys.size(), 2u);  // the first spawn and 2 m along its yaw (+x)
  EXPECT_NEAR(p.keys[1].eye.x - p.keys[0].eye.x, 2.0, 1e-9);
  EXPECT_NEAR(p.keys[1].eye.z, p.keys[0].eye.z, 1e-9);
}

// Variants that are also the fuzz target's seed corpus (tests/fuzz/q3bsp/,
// written here when HW_Q3BSP_SEED_DIR names a folder): a polygon without
// meshverts (a fan), a billboard, a 5 × 3 patch (two pieces).
TEST_F(Q3BspTest, FanBillboardAndWidePatch) {
  const char* dir = std::getenv("HW_Q3BSP_SEED_DIR");
  std::vector<std::pair<std::string, TestBsp>> seeds;
  seeds.push_back({"minimal.bsp", TestBsp()});
  TestBsp sky;
  sky.shaders.push_back({"textures/skies/blue", 0x4, 0});
  sky.faces[1].shader = 1;
  seeds.push_back({"sky.bsp", sky});
  TestBsp fan;  // a polygon without meshverts, a billboard, a 5 × 3 patch
  fan.faces[0].numIndexes = 0;
  fan.faces.push_back({0, 4, 0, 1, 0, 0});
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 5; ++i)
      fan.verts.push_back(
          {25.0f * i, 500.0f + 50.0f * j, (i % 2) * 30.0f, 0.25f * i, 0.5f * j, 0, 0, 1});
  BspFace wide;
  wide.type = 2, wide.firstVert = 13, wide.numVerts = 15, wide.patchW = 5, wide.patchH = 3;
  fan.faces.push_back(wide);
  seeds.push_back({"fan_billboard_wide_patch.bsp", fan});
  const std::size_t expected[] = {2 + 128, 2, 2 + 128 + 2 * 128};
  for (std::size_t i = 0; i < seeds.size(); ++i) {
    const auto& [name, bsp] = seeds[i];
    auto map = parseQ3Bsp(bsp.bytes(), name, nullptr, {});
    ASSERT_TRUE(map.ok()) << name << ": " << map.error().message;
    EXPECT_EQ(map->scene.triangleCount(), expected[i]) << name;
    if (dir && *dir) {
      ASSERT_TRUE(writeFileAtomic((fs::path(dir) / name).string(), bsp.bytes()).ok());
    }
  }
}

// ---------------------------------------------------------------------------
// Corrupt input: an error that names the file, never a crash.

void expectError(const Result<Q3Map>& r, const std::vector<std::string>& needles) {
  ASSERT_FALSE(r.ok());
  for (const std::string& n : needles)
    EXPECT_NE(r.error().message.find(n), std::string::npos)
        << "missing '" << n << "' in: " << r.error().message;
}

TEST_F(Q3BspTest, EveryTruncationIsAnError) {
  const std::string bsp = TestBsp().bytes();
  for (std::size_t n = 0; n < bsp.size(); ++n) {
    auto r = parseQ3Bsp(std::string_view(bsp).substr(0, n), "test.bsp", nullptr, {});
    ASSERT_FALSE(r.ok()) << "length " << n;
    EXPECT_NE(r.error().message.find("test.bsp"), std::string::npos) << r.error().message;
  }
  // Through a pk3 too, at a few lengths.
  for (std::size_t n :
       {std::size_t{0}, std::size_t{100}, std::size_t{150}, bsp.size() / 2, bsp.size() - 1}) {
    const std::string pk3 = writePk3("cut" + std::to_string(n) + ".pk3", bsp.substr(0, n));
    auto r = loadQ3Map("test", withPk3s({pk3}));
    expectError(r, {"maps/test.bsp"});
  }
}

TEST_F(Q3BspTest, BadHeaderLumpsAndFaces) {
  {
    TestBsp b;
    b.magic = "VBSP";
    expectError(parseQ3Bsp(b.bytes(), "t.bsp", nullptr, {}), {"t.bsp", "IBSP", "VBSP"});
  }
  {
    TestBsp b;
    b.version = 47;
    expectError(parseQ3Bsp(b.bytes(), "t.bsp", nullptr, {}), {"t.bsp", "46", "47"});
  }
  {
    std::string bsp = TestBsp().bytes();
    setLump(bsp, 13, 100, 1 << 20);
    expectError(parseQ3Bsp(bsp, "t.bsp", nullptr, {}), {"t.bsp", "lump 13", "faces"});
    setLump(bsp, 10, -8, 44);
    expectError(parseQ3Bsp(bsp, "t.bsp", nullptr, {}), {"t.bsp", "lump 10", "offset -8"});
    bsp = TestBsp().bytes();
    setLump(bsp, 1, 144, 71);  // not a multiple of 72
    expectError(parseQ3Bsp(bsp, "t.bsp", nullptr, {}), {"t.bsp", "lump 1", "multiple of 72"});
  }
  {
    TestBsp b;
    b.indexes[4] = 4;  // the quad has 4 vertices: 0..3
    expectError(parseQ3Bsp(b.bytes(), "t.bsp", nullptr, {}),
                {"t.bsp", "face 0", "meshvert 4", "[0, 4)", "got 4"});
    b.indexes[4] = -1;
    expectError(parseQ3Bsp(b.bytes(), "t.bsp", nullptr, {}), {"face 0", "got -1"});
  }
  {
    TestBsp b;
    b.faces[0].numIndexes = 7;
    expectError(parseQ3Bsp(b.bytes(), "t.bsp", nullptr, {}), {"t.bsp", "face 0", "meshverts"});
    b.faces[0].numIndexes = 3;
    b.faces[0].firstVert = 11;  // 11 + 4 > 13 vertices
    expectError(parseQ3Bsp(b.bytes(), "t.bsp", nullptr, {}), {"face 0", "vertices", "13"});
  }
  {
    TestBsp b;
    b.faces[1].patchW = 2;
    b.faces[1].patchH = 4;  // 8 control points, even dimensions
    b.faces[1].numVerts = 8;
    expectError(parseQ3Bsp(b.bytes(), "t.bsp", nullptr, {}), {"t.bsp", "face 1", "odd", "2 × 4"});
    b.faces[1] = TestBsp().faces[1];
    b.faces[1].patchW = 5;  // 5 × 3 = 15 ≠ 9
    expectError(parseQ3Bsp(b.bytes(), "t.bsp", nullptr, {}), {"face 1", "15", "got 9"});
  }
  {
    TestBsp b;
    b.faces[1].shader = 3;
    expectError(parseQ3Bsp(b.bytes(), "t.bsp", nullptr, {}), {"face 1", "shader", "got 3"});
    b.faces[1].shader = 0;
    b.faces[1].type = 9;
    expectError(parseQ3Bsp(b.bytes(), "t.bsp", nullptr, {}), {"face 1", "surface type", "got 9"});
  }
  {
    TestBsp b;
    b.verts[2].x = std::numeric_limits<float>::quiet_NaN();
    expectError(parseQ3Bsp(b.bytes(), "t.bsp", nullptr, {}), {"t.bsp", "vertex 2", "non-finite"});
  }
  {
    TestBsp b;
    b.entities = "{ \"classname\" \"info_player_start\" \"origin\" \"1 2\" }";
    expectError(parseQ3Bsp(b.bytes(), "t.bsp", nullptr, {}), {"t.bsp", "entities", "origin"});
    // Finite but far past any map: a NaN camera path (and a CHECK) before.
    b.entities = "{ \"classname\" \"info_player_start\" \"origin\" \"1e300 0 0\" }";
    expectError(parseQ3Bsp(b.bytes(), "t.bsp", nullptr, {}), {"t.bsp", "origin", "1e7"});
    b.entities = "{ \"classname\" \"worldspawn\" ";
    expectError(parseQ3Bsp(b.bytes(), "t.bsp", nullptr, {}), {"t.bsp", "entities", "not closed"});
    b.entities = "{ \"classname\" \"worldspawn }";
    expectError(parseQ3Bsp(b.bytes(), "t.bsp", nullptr, {}), {"t.bsp", "entities"});
  }
}

TEST_F(Q3BspTest, HugePatchIsRefusedBeforeTessellating) {
  TestBsp b;
  Q3Options o;
  o.maxTriangles = 100;
  expectError(parseQ3Bsp(b.bytes(), "t.bsp", nullptr, o), {"t.bsp", "maxTriangles"});
}

TEST_F(Q3BspTest, BadPk3sAndMissingMaps) {
  const std::string good = writePk3("good.pk3", TestBsp().bytes());
  expectError(loadQ3Map("nosuch", withPk3s({good})),
              {"nosuch", "maps/nosuch.bsp", "good.pk3", "test"});
  expectError(loadQ3Map("test", withPk3s({})), {"no .pk3 files"});
  expectError(loadQ3Map("../test", withPk3s({good})), {"bare name"});
  expectError(loadQ3Map("test", withPk3s({(dir_ / "absent.pk3").string()})), {"absent.pk3"});

  std::mt19937 rng(7);
  std::string garbage(5000, '\0');
  for (char& c : garbage) c = static_cast<char>(rng());
  expectError(loadQ3Map("test", withPk3s({writeRaw("garbage.pk3", garbage)})), {"garbage.pk3"});

  auto bytes = readFile(good);
  ASSERT_TRUE(bytes.ok());
  for (std::size_t n : {std::size_t{0}, std::size_t{30}, bytes->size() / 2, bytes->size() - 30,
                        bytes->size() - 1}) {
    const std::string cut = writeRaw("cut" + std::to_string(n) + ".pk3", bytes->substr(0, n));
    expectError(loadQ3Map("test", withPk3s({good, cut})), {"cut" + std::to_string(n) + ".pk3"});
  }
  // Damaged compressed data inside an intact archive: the BSP is stored
  // deflated, so flipping bytes in the middle breaks its inflate or CRC.
  std::string damaged = *bytes;
  for (std::size_t i = 60; i < 300 && i < damaged.size(); i += 7) damaged[i] ^= 0x5a;
  auto r = loadQ3Map("test", withPk3s({writeRaw("damaged.pk3", damaged)}));
  if (!r.ok()) {
    EXPECT_NE(r.error().message.find("damaged.pk3"), std::string::npos) << r.error().message;
  }
}

}  // namespace
}  // namespace hw::scenes
