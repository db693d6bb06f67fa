// Scene loading through Assimp: OBJ+MTL+PNG, PLY, glTF; Z-up conversion;
// every kind of bad file gives an error naming the file; scene specs.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "core/file_io.h"
#include "scenes/loader.h"
#include "scenes/triangle_grid.h"

namespace hw::scenes {
namespace {

namespace fs = std::filesystem;

class LoaderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("hw_loader_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
            "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& text) {
    const std::string p = (dir_ / name).string();
    std::ofstream(p, std::ios::binary) << text;
    return p;
  }

  // A box x ∈ [0, 1], y ∈ [0, 2], z ∈ [0, 3] with outward CCW quads (12
  // triangles after triangulation), textured with `texture` via box.mtl.
  std::string writeBoxObj(const std::string& texture, const std::string& name = "box.obj") {
    write("box.mtl", "newmtl crate\nKd 0.8 0.7 0.6\nmap_Kd " + texture + "\n");
    return write(name,
                 "mtllib box.mtl\n"
                 "v 0 0 0\nv 1 0 0\nv 1 2 0\nv 0 2 0\nv 0 0 3\nv 1 0 3\nv 1 2 3\nv 0 2 3\n"
                 "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                 "usemtl crate\n"
                 "f 1/1 4/4 3/3 2/2\n"    // z = 0, facing −z
                 "f 5/1 6/2 7/3 8/4\n"    // z = 3, facing +z
                 "f 1/1 5/2 8/3 4/4\n"    // x = 0
                 "f 2/1 3/2 7/3 6/4\n"    // x = 1
                 "f 4/1 8/2 7/3 3/4\n"    // y = 2
                 "f 1/1 2/2 6/3 5/4\n");  // y = 0
  }

  fs::path dir_;
};

Image<Rgba8> smallTexture(std::uint8_t alpha) {
  Image<Rgba8> img(8, 4);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 8; ++x)
      img(x, y) =
          Rgba8{static_cast<std::uint8_t>(x * 30), static_cast<std::uint8_t>(y * 60), 90, alpha};
  return img;
}

void expectNear(const glm::vec3& a, const glm::vec3& b) {
  EXPECT_NEAR(a.x, b.x, 1e-5f);
  EXPECT_NEAR(a.y, b.y, 1e-5f);
  EXPECT_NEAR(a.z, b.z, 1e-5f);
}

TEST_F(LoaderTest, ObjWithMtlAndPngTexture) {
  ASSERT_TRUE(writePng((dir_ / "crate.png").string(), smallTexture(255)).ok());
  const std::string obj = writeBoxObj("crate.png");
  auto s = loadSceneFile(obj);
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_EQ(s->triangleCount(), 12u);
  expectNear(s->boundsMin, {0, 0, 0});
  expectNear(s->boundsMax, {1, 2, 3});
  EXPECT_TRUE(s->warnings.empty());
  ASSERT_EQ(s->textures.size(), 1u);
  EXPECT_EQ(s->textures[0].image.width(), 8);
  EXPECT_EQ(s->textures[0].image.height(), 4);
  EXPECT_EQ(s->textures[0].image(7, 3), (Rgba8{210, 180, 90, 255}));
  const Material& m = s->materials[static_cast<std::size_t>(s->meshes[0].material)];
  EXPECT_EQ(m.texture, 0);
  EXPECT_FALSE(m.alphaTest);
  EXPECT_NEAR(m.baseColour.r, 0.8f, 1e-6f);
  // Normals: unit, outward (the box's centre is at (0.5, 1, 1.5)).
  for (const Mesh& mesh : s->meshes)
    for (std::size_t t = 0; t < mesh.indices.size(); t += 3) {
      const Vertex& a = mesh.vertices[mesh.indices[t]];
      EXPECT_NEAR(glm::length(a.normal), 1.0f, 1e-5f);
      const glm::vec3 centre = (a.position + mesh.vertices[mesh.indices[t + 1]].position +
                                mesh.vertices[mesh.indices[t + 2]].position) /
                               3.0f;
      EXPECT_GT(glm::dot(a.normal, centre - glm::vec3(0.5f, 1.0f, 1.5f)), 0.0f);
    }
  // v is flipped to "0 = top row": the OBJ's vt (0, 1) becomes uv (0, 0).
  bool sawTop = false;
  for (const Vertex& v : s->meshes[0].vertices) sawTop |= v.uv == glm::vec2(0.0f, 0.0f);
  EXPECT_TRUE(sawTop);
}

TEST_F(LoaderTest, TextureAlphaEnablesAlphaTest) {
  ASSERT_TRUE(writePng((dir_ / "leaf.png").string(), smallTexture(0)).ok());
  auto s = loadSceneFile(writeBoxObj("leaf.png"));
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_TRUE(s->materials[static_cast<std::size_t>(s->meshes[0].material)].alphaTest);
}

TEST_F(LoaderTest, MissingTextureIsAPlaceholderAndAWarning) {
  auto s = loadSceneFile(writeBoxObj("nowhere.png"));
  ASSERT_TRUE(s.ok()) << s.error().message;
  ASSERT_EQ(s->warnings.size(), 1u);
  EXPECT_NE(s->warnings[0].find("nowhere.png"), std::string::npos) << s->warnings[0];
  ASSERT_EQ(s->textures.size(), 1u);
  EXPECT_FALSE(s->textures[0].image.empty());
  EXPECT_EQ(s->materials[static_cast<std::size_t>(s->meshes[0].material)].texture, 0);
}

TEST_F(LoaderTest, ZUpIsConvertedToYUp) {
  const std::string obj = writeBoxObj("crate.png");
  ASSERT_TRUE(writePng((dir_ / "crate.png").string(), smallTexture(255)).ok());
  LoadOptions o;
  o.zUp = true;
  auto s = loadSceneFile(obj, o);
  ASSERT_TRUE(s.ok()) << s.error().message;
  // (x, y, z) → (x, z, −y): height was z ∈ [0, 3].
  expectNear(s->boundsMin, {0, 0, -2});
  expectNear(s->boundsMax, {1, 3, 0});
}

TEST_F(LoaderTest, AsciiPly) {
  const std::string ply =
      write("tet.ply",
            "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
            "property float z\nelement face 4\nproperty list uchar int vertex_indices\n"
            "end_header\n"
            "0 0 0\n2 0 0\n0 2 0\n0 0 2\n"
            "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
  auto s = loadSceneFile(ply);
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_EQ(s->triangleCount(), 4u);
  expectNear(s->boundsMin, {0, 0, 0});
  expectNear(s->boundsMax, {2, 2, 2});
  for (const Mesh& m : s->meshes)
    for (const Vertex& v : m.vertices)
      EXPECT_NEAR(glm::length(v.normal), 1.0f, 1e-4f);  // generated
}

TEST_F(LoaderTest, BinaryPlyAndItsTruncations) {
  std::string bytes =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const std::size_t headerSize = bytes.size();
  const float v[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  bytes.append(reinterpret_cast<const char*>(v), sizeof v);
  bytes.push_back(3);
  const std::int32_t idx[3] = {0, 1, 2};
  bytes.append(reinterpret_cast<const char*>(idx), sizeof idx);
  auto s = loadSceneFile(write("tri.ply", bytes));
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_EQ(s->triangleCount(), 1u);
  // Every truncation of the body is an error, never a hang or a crash.
  for (std::size_t n = headerSize; n < bytes.size(); ++n) {
    const std::string f = write("cut.ply", bytes.substr(0, n));
    auto r = loadSceneFile(f);
    ASSERT_FALSE(r.ok()) << "cut at " << n;
    EXPECT_NE(r.error().message.find(f), std::string::npos);
  }
}

TEST_F(LoaderTest, GltfWithNodeTransform) {
  // One triangle (6 bytes of uint16 indices + 36 bytes of float positions),
  // its node translated by (10, 0, 0): the loader applies node transforms.
  const std::string gltf = write("tri.gltf", R"({
  "asset": {"version": "2.0"},
  "scene": 0, "scenes": [{"nodes": [0]}],
  "nodes": [{"mesh": 0, "translation": [10, 0, 0]}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 1}, "indices": 0}]}],
  "buffers": [{"byteLength": 44, "uri": "data:application/octet-stream;base64,AAABAAIAAAAAAAAAAAAAAAAAAAAAAIA/AAAAAAAAAAAAAAAAAACAPwAAAAA="}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 6},
                  {"buffer": 0, "byteOffset": 8, "byteLength": 36}],
  "accessors": [{"bufferView": 0, "componentType": 5123, "count": 3, "type": "SCALAR"},
                {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3",
                 "min": [0, 0, 0], "max": [1, 1, 0]}]
})");
  auto s = loadSceneFile(gltf);
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_EQ(s->triangleCount(), 1u);
  expectNear(s->boundsMin, {10, 0, 0});
  expectNear(s->boundsMax, {11, 1, 0});
}

TEST_F(LoaderTest, LargeMeshesAreSplitIntoChunks) {
  ASSERT_TRUE(writePng((dir_ / "crate.png").string(), smallTexture(255)).ok());
  LoadOptions o;
  o.maxTrianglesPerMesh = 4;
  auto s = loadSceneFile(writeBoxObj("crate.png"), o);
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_EQ(s->triangleCount(), 12u);
  EXPECT_GE(s->meshes.size(), 3u);
  for (const Mesh& m : s->meshes) EXPECT_LE(m.triangleCount(), 4u);
  expectNear(s->boundsMin, {0, 0, 0});
  expectNear(s->boundsMax, {1, 2, 3});
}

void expectErrorNaming(const Result<Scene>& r, const std::string& file, const char* what) {
  ASSERT_FALSE(r.ok()) << what;
  EXPECT_NE(r.error().message.find(file), std::string::npos) << what << ": " << r.error().message;
}

TEST_F(LoaderTest, BadFilesGiveErrorsNamingTheFile) {
  const std::string missing = (dir_ / "missing.obj").string();
  expectErrorNaming(loadSceneFile(missing), missing, "missing");

  const std::string empty = write("empty.obj", "");
  expectErrorNaming(loadSceneFile(empty), empty, "empty");

  const std::string unsupported = write("model.xyz123", "whatever\n");
  expectErrorNaming(loadSceneFile(unsupported), unsupported, "unsupported extension");
  EXPECT_NE(loadSceneFile(unsupported).error().message.find("unsupported"), std::string::npos);

  std::mt19937 rng(7);
  std::string junk(4096, '\0');
  for (char& c : junk) c = static_cast<char>(rng() & 0xff);
  for (const char* ext : {".ply", ".obj", ".gltf", ".glb", ".dae", ".3ds", ".fbx", ".stl"}) {
    const std::string garbage = write(std::string("garbage") + ext, junk);
    expectErrorNaming(loadSceneFile(garbage), garbage, ext);
  }

  const std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float "
      "z\n"
      "element face 4\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n2 0 0\n0 2 0\n0 "
      "0 2\n"
      "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  const std::string truncatedPly = write("truncated.ply", ply.substr(0, ply.size() / 2));
  expectErrorNaming(loadSceneFile(truncatedPly), truncatedPly, "truncated ply");
  // Every cut of the body that loses a record is an error (Assimp 5.2 alone
  // can hang on these), never a hang.
  for (std::size_t n = ply.find("end_header"); n + 2 < ply.size(); ++n) {
    const std::string cut = write("cut.ply", ply.substr(0, n));
    expectErrorNaming(loadSceneFile(cut), cut, "cut ascii ply");
  }
  const std::string truncatedGltf =
      write("truncated.gltf", R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"no)");
  expectErrorNaming(loadSceneFile(truncatedGltf), truncatedGltf, "truncated gltf");

  const std::string noMeshes = write("lines.obj", "v 0 0 0\nv 1 0 0\nl 1 2\n");
  expectErrorNaming(loadSceneFile(noMeshes), noMeshes, "no triangles");

  const std::string folder = dir_.string();
  expectErrorNaming(loadSceneFile(folder), folder, "directory");
}

TEST(LoadScene, UnknownNameListsBuiltins) {
  auto r = loadScene("nope");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("nope"), std::string::npos);
  EXPECT_NE(r.error().message.find("indoor"), std::string::npos);
  EXPECT_NE(r.error().message.find("outdoor"), std::string::npos);
  auto p = defaultPathFor("nope");
  ASSERT_FALSE(p.ok());
  EXPECT_NE(p.error().message.find("indoor"), std::string::npos);
}

TEST(LoadScene, BuiltinsWithTriangleCounts) {
  auto s = loadScene("indoor:20k");
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_NEAR(static_cast<double>(s->triangleCount()), 20e3, 20e3 * 0.3);
  auto o = loadScene("outdoor:0.05M");
  ASSERT_TRUE(o.ok()) << o.error().message;
  EXPECT_NEAR(static_cast<double>(o->triangleCount()), 50e3, 50e3 * 0.3);
  for (const char* bad :
       {"indoor:", "indoor:abc", "indoor:10q", "outdoor:0", "outdoor:-5k", "indoor:1e12"}) {
    auto r = loadScene(bad);
    ASSERT_FALSE(r.ok()) << bad;
    EXPECT_NE(r.error().message.find(bad), std::string::npos) << r.error().message;
  }
  for (const char* spec : {"indoor", "outdoor:1M"}) {
    auto p = defaultPathFor(spec);
    ASSERT_TRUE(p.ok()) << spec;
    EXPECT_EQ(p->frames, 120);
    EXPECT_EQ(p->keyframeEvery, 10);
  }
}

TEST_F(LoaderTest, FileSpecAndFlythrough) {
  ASSERT_TRUE(writePng((dir_ / "crate.png").string(), smallTexture(255)).ok());
  const std::string obj = writeBoxObj("crate.png");
  auto s = loadScene(obj);
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_EQ(s->triangleCount(), 12u);
  std::vector<std::string> notes;
  auto p = defaultPathFor(obj, DefaultPathOptions{}, &notes);
  ASSERT_TRUE(p.ok()) << p.error().message;
  EXPECT_GT(p->farPlane, p->nearPlane);
  // A closed box with outward faces: a path inside it would see only back
  // faces (culled, a one-colour frame); the default path orbits outside and
  // every key sees the box.
  const TriangleGrid grid(*s, 0.1);
  EXPECT_EQ(keysSeeingSurfaces(grid, *p), static_cast<int>(p->keys.size()));
  for (const CameraKey& k : p->keys) {
    bool outside = false;
    for (int a = 0; a < 3; ++a)
      outside = outside || k.eye[a] < s->boundsMin[a] || k.eye[a] > s->boundsMax[a];
    EXPECT_TRUE(outside);
  }
  bool said = false;
  for (const std::string& n : notes) said = said || n.find("orbiting outside") != std::string::npos;
  EXPECT_TRUE(said);
  // The path survives its own JSON format.
  EXPECT_TRUE(parseCameraPath(cameraPathToJson(*p), "fly.json").ok());
}

// One one-sided triangle: the default path frames it, swinging in front of
// it (an orbit would see its back, which is not drawn, half the time).
TEST_F(LoaderTest, DefaultPathOfOneTriangleFramesIt) {
  const std::string obj = write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  auto s = loadScene(obj);
  ASSERT_TRUE(s.ok()) << s.error().message;
  std::vector<std::string> notes;
  auto p = defaultPathFor(obj, DefaultPathOptions{}, &notes);
  ASSERT_TRUE(p.ok()) << p.error().message;
  const TriangleGrid grid(*s, 0.1);
  EXPECT_EQ(keysSeeingSurfaces(grid, *p), static_cast<int>(p->keys.size()));
  CameraPath first = *p;
  first.keys.resize(1);
  EXPECT_EQ(keysSeeingSurfaces(grid, first), 1);
  EXPECT_GT(p->keys[0].eye.z, 0.0);  // the triangle's front faces +z
}

// 20000 copies of one face are drawn once, with a warning saying so.
TEST_F(LoaderTest, RepeatedFacesAreDrawnOnce) {
  std::string text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n";
  for (int i = 0; i < 20000; ++i) text += i % 2 ? "f 1 2 3\n" : "f 2 3 1\n";
  text += "f 3 2 1\nf 2 4 3\n";  // the back of the first, and another face
  auto s = loadScene(write("repeat.obj", text));
  ASSERT_TRUE(s.ok()) << s.error().message;
  EXPECT_EQ(s->triangleCount(), 3u);
  ASSERT_FALSE(s->warnings.empty());
  EXPECT_NE(s->warnings.front().find("19999 of 20002 faces repeat"), std::string::npos)
      << s->warnings.front();
}

// A referenced file is looked up beside the model, whatever the working
// directory holds; one outside the model's folder is refused from anywhere.
TEST_F(LoaderTest, ReferencesResolveAgainstTheModelsFolder) {
  fs::create_directories(dir_ / "model");
  fs::create_directories(dir_ / "elsewhere");
  write("model/m.mtl", "newmtl m\nKd 1 0 0\n");
  write("elsewhere/m.mtl", "newmtl m\nKd 0 1 0\n");  // same name, another folder
  write("outside.mtl", "newmtl m\nKd 0 0 1\n");
  const std::string beside =
      write("model/beside.obj", "mtllib m.mtl\nusemtl m\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const std::string up = write(
      "model/up.obj", "mtllib ../outside.mtl\nusemtl m\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const fs::path cwd = fs::current_path();
  for (const fs::path& from : {dir_ / "elsewhere", dir_ / "model", fs::path("/")}) {
    fs::current_path(from);
    auto b = loadSceneFile(beside);
    auto u = loadSceneFile(up);
    fs::current_path(cwd);
    ASSERT_TRUE(b.ok()) << from << ": " << b.error().message;
    ASSERT_FALSE(b->meshes.empty());
    EXPECT_EQ(b->materials.at(static_cast<std::size_t>(b->meshes[0].material)).baseColour,
              glm::vec4(1, 0, 0, 1))
        << from;
    ASSERT_FALSE(u.ok()) << from;
    EXPECT_NE(u.error().message.find("outside the model's folder"), std::string::npos)
        << u.error().message;
  }
}

}  // namespace
}  // namespace hw::scenes
