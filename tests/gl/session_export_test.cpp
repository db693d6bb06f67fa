// Keyframe export (bench/export.h, DESIGN.md "Keyframe export"): the folder
// holds exactly the contract's files; PNGs are RGB; the PFM depth is the
// renderer's eye z bit for bit; and the exported intrinsics + row-major
// world_from_camera (OpenCV axes) re-project pixels onto Camera::unproject.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "session/export.h"
#include "core/file_io.h"
#include "core/pfm.h"
#include "gl_fixture.h"
#include "keyframe/geometry_renderer.h"
#include "keyframe/keyframe.h"
#include "scenes/procedural.h"

namespace hw {
namespace {

using json = nlohmann::json;
namespace fs = std::filesystem;

const scenes::Scene& indoor() {
  static const scenes::Scene s = scenes::makeIndoorScene(20000);
  return s;
}

// 12 frames, a keyframe every 5: keyframes 0, 5, 10, 11; 8 in-between frames.
scenes::CameraPath shortPath() {
  scenes::CameraPath p = scenes::defaultIndoorPath();
  p.width = 64;
  p.height = 48;
  p.frames = 12;
  p.keyframeEvery = 5;
  return p;
}

std::string freshDir(const std::string& tag) {
  const fs::path d = fs::temp_directory_path() / ("hw_export_test_" + tag);
  fs::remove_all(d);
  return d.string();
}

json loadCameras(const std::string& dir) {
  auto text = readFile(dir + "/cameras.json");
  EXPECT_TRUE(text.ok()) << text.error().message;
  return text.ok() ? json::parse(*text) : json();
}

std::set<std::string> filesIn(const std::string& dir) {
  std::set<std::string> s;
  for (const auto& e : fs::directory_iterator(dir)) s.insert(e.path().filename().string());
  return s;
}

// PNG IHDR: 8-byte signature, chunk length, "IHDR", width, height (big-endian),
// bit depth, colour type (2 = RGB, 6 = RGBA).
struct PngHeader {
  int width = 0, height = 0, bitDepth = 0, colourType = -1;
};
PngHeader pngHeader(const std::string& file) {
  auto bytes = readFile(file);
  EXPECT_TRUE(bytes.ok()) << file;
  PngHeader h;
  if (!bytes.ok() || bytes->size() < 26 || bytes->compare(12, 4, "IHDR") != 0) return h;
  auto u8 = [&](std::size_t i) { return static_cast<unsigned char>((*bytes)[i]); };
  auto be32 = [&](std::size_t i) {
    return static_cast<int>(u8(i) << 24 | u8(i + 1) << 16 | u8(i + 2) << 8 | u8(i + 3));
  };
  h.width = be32(16);
  h.height = be32(20);
  h.bitDepth = u8(24);
  h.colourType = u8(25);
  return h;
}

// world_from_camera as exported (row-major) applied to a camera-frame point.
glm::dvec3 applyRowMajor(const json& m, const glm::dvec3& p) {
  glm::dvec3 out;
  for (int r = 0; r < 3; ++r)
    out[r] = m[r][0].get<double>() * p.x + m[r][1].get<double>() * p.y +
             m[r][2].get<double>() * p.z + m[r][3].get<double>();
  return out;
}

// OpenCV pinhole: pixel (u, v) at depth z → camera frame (x right, y down, z forward).
glm::dvec3 openCvPoint(const json& c, double u, double v, double z) {
  return {(u - c["cx"].get<double>()) / c["fx"].get<double>() * z,
          (v - c["cy"].get<double>()) / c["fy"].get<double>() * z, z};
}

void expectNear3(const glm::dvec3& got, const glm::dvec3& want, const std::string& where) {
  const double tol = 1e-6 * std::max(1.0, glm::length(want));
  EXPECT_LE(glm::length(got - want), tol)
      << where << ": got (" << got.x << ", " << got.y << ", " << got.z << ") want (" << want.x
      << ", " << want.y << ", " << want.z << ")";
}

TEST(ExportCameraJson, WorldFromCameraIsRowMajorWithOpenCvAxes) {
  // An asymmetric pose so that a transposed or column-major matrix shows.
  const Camera cam =
      Camera::lookAt({1.0, 2.0, 3.0}, {4.0, 1.0, -2.0}, {0, 1, 0}, 0.9, 80, 40, 0.25, 300.0);
  const json c = session::exportCameraJson("key_0042", cam);
  EXPECT_EQ(c["name"], "key_0042");
  EXPECT_EQ(c["width"], 80);
  EXPECT_EQ(c["height"], 40);
  EXPECT_EQ(c["fx"].get<double>(), cam.fx());
  EXPECT_EQ(c["fy"].get<double>(), cam.fy());
  EXPECT_EQ(c["cx"].get<double>(), 40.0);  // pixel centres at +0.5: the centre is w/2
  EXPECT_EQ(c["cy"].get<double>(), 20.0);
  EXPECT_EQ(c["near"].get<double>(), 0.25);
  EXPECT_EQ(c["far"].get<double>(), 300.0);
  const json& m = c["world_from_camera"];
  ASSERT_EQ(m.size(), 4u);
  for (int r = 0; r < 4; ++r) ASSERT_EQ(m[r].size(), 4u);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(m[k][0].get<double>(), cam.right[k]) << "column 0 = x (right)";
    EXPECT_EQ(m[k][1].get<double>(), -cam.up[k]) << "column 1 = y (down)";
    EXPECT_EQ(m[k][2].get<double>(), cam.forward[k]) << "column 2 = z (forward)";
    EXPECT_EQ(m[k][3].get<double>(), cam.eye[k]) << "column 3 = eye";
  }
  EXPECT_EQ(m[3], json({0.0, 0.0, 0.0, 1.0}));
  // The pinhole model with these numbers is Camera::unproject.
  for (double u : {0.5, 13.5, 79.5})
    for (double v : {0.5, 27.5, 39.5})
      for (double z : {0.3, 7.0, 250.0})
        expectNear3(applyRowMajor(m, openCvPoint(c, u, v, z)), cam.unproject(u, v, z), "unproject");
  EXPECT_EQ(session::exportKeyframeName(7), "key_0007");
  EXPECT_EQ(session::exportFrameName(123), "frame_0123");
}

class ExportTest : public test::GlTest {};

TEST_F(ExportTest, WritesExactlyTheContractFiles) {
  const std::string dir = freshDir("files");
  session::ExportOptions opt;
  opt.progress = false;
  const Status st = session::exportKeyframes(indoor(), shortPath(), dir, opt);
  ASSERT_TRUE(st.ok()) << st.error().message;

  std::set<std::string> want = {"cameras.json"};
  for (int k : {0, 5, 10, 11}) {
    want.insert(session::exportKeyframeName(k) + ".png");
    want.insert(session::exportKeyframeName(k) + ".depth.pfm");
  }
  for (int i : {1, 2, 3, 4, 6, 7, 8, 9}) want.insert(session::exportFrameName(i) + ".png");
  EXPECT_EQ(filesIn(dir), want);  // nothing else, no temporaries

  const json doc = loadCameras(dir);
  EXPECT_EQ(doc["format"], "hybridwalk-keyframes");
  EXPECT_EQ(doc["version"], 1);
  ASSERT_EQ(doc["keyframes"].size(), 4u);
  ASSERT_EQ(doc["in_between"].size(), 8u);
  const char* fields[] = {"name",       "width", "height", "fx",  "fy",
                          "cx",         "cy",    "near",   "far", "world_from_camera",
                          "is_keyframe"};
  const scenes::CameraPath path = shortPath();
  for (const char* list : {"keyframes", "in_between"}) {
    for (const json& c : doc[list]) {
      for (const char* f : fields) EXPECT_TRUE(c.contains(f)) << c["name"] << " lacks " << f;
      const Camera cam = path.cameraAt(c["frame"].get<int>());
      EXPECT_EQ(c,
                [&] {
                  json e = session::exportCameraJson(c["name"], cam);
                  for (const char* extra : {"frame", "is_keyframe", "keyframes"})
                    if (c.contains(extra)) e[extra] = c[extra];
                  return e;
                }())
          << "camera of " << c["name"] << " is not the path's";
      EXPECT_EQ(c["width"], 64);
      EXPECT_EQ(c["height"], 48);
    }
  }
  const json& k = doc["keyframes"];
  EXPECT_EQ(k[0]["name"], "key_0000");
  EXPECT_EQ(k[3]["name"], "key_0011");
  for (const json& c : k) EXPECT_EQ(c["is_keyframe"], true);
  const json& ib = doc["in_between"];
  EXPECT_EQ(ib[0]["name"], "frame_0001");
  EXPECT_EQ(ib[0]["keyframes"], json({"key_0000", "key_0005"}));
  EXPECT_EQ(ib[7]["name"], "frame_0009");
  EXPECT_EQ(ib[7]["keyframes"], json({"key_0005", "key_0010"}));
  for (const json& c : ib) EXPECT_EQ(c["is_keyframe"], false);

  for (const std::string& f : want) {
    if (!f.ends_with(".png")) continue;
    const PngHeader h = pngHeader(dir + "/" + f);
    EXPECT_EQ(h.colourType, 2) << f << " is not RGB";
    EXPECT_EQ(h.bitDepth, 8) << f;
    EXPECT_EQ(h.width, 64) << f;
    EXPECT_EQ(h.height, 48) << f;
  }
}

TEST_F(ExportTest, DepthAndColourAreTheRenderersBitForBit) {
  const std::string dir = freshDir("bits");
  session::ExportOptions opt;
  opt.progress = false;
  const scenes::CameraPath path = shortPath();
  ASSERT_TRUE(session::exportKeyframes(indoor(), path, dir, opt).ok());

  auto r = keyframe::GeometryRenderer::create(indoor());
  ASSERT_TRUE(r.ok()) << r.error().message;
  keyframe::Keyframe kf;
  for (int frame : {0, 5, 11}) {
    ASSERT_TRUE((*r)->renderKeyframe(path.cameraAt(frame), kf).ok());
    const std::string name = session::exportKeyframeName(frame);
    auto depth = readPfm(dir + "/" + name + ".depth.pfm");
    ASSERT_TRUE(depth.ok()) << depth.error().message;
    ASSERT_EQ(depth->width(), kf.eyeZ.width());
    ASSERT_EQ(depth->height(), kf.eyeZ.height());
    EXPECT_EQ(std::memcmp(depth->data(), kf.eyeZ.data(), kf.eyeZ.size() * sizeof(float)), 0)
        << name << ".depth.pfm differs from Keyframe::eyeZ";
    std::size_t covered = 0;
    for (int y = 0; y < kf.eyeZ.height(); ++y)
      for (int x = 0; x < kf.eyeZ.width(); ++x) {
        EXPECT_EQ((*depth)(x, y) > 0.0f, kf.covered(x, y) != 0) << name << " at " << x << "," << y;
        covered += kf.covered(x, y);
      }
    EXPECT_GT(covered, kf.eyeZ.size() / 2) << name;
    auto png = readPng(dir + "/" + name + ".png");
    ASSERT_TRUE(png.ok()) << png.error().message;
    for (std::size_t i = 0; i < kf.colour.size(); ++i) {
      Rgba8 want = kf.colour.data()[i];
      want.a = 255;  // RGB file: readPng fills alpha
      ASSERT_EQ(png->data()[i], want) << name << " pixel " << i;
    }
  }
  Image<Rgba8> ref;
  ASSERT_TRUE((*r)->renderColour(path.cameraAt(7), ref).ok());
  auto png = readPng(dir + "/frame_0007.png");
  ASSERT_TRUE(png.ok()) << png.error().message;
  for (std::size_t i = 0; i < ref.size(); ++i) {
    Rgba8 want = ref.data()[i];
    want.a = 255;
    ASSERT_EQ(png->data()[i], want) << "frame_0007 pixel " << i;
  }
}

TEST_F(ExportTest, ExportedPoseAndIntrinsicsReprojectOntoUnproject) {
  const std::string dir = freshDir("reproject");
  session::ExportOptions opt;
  opt.progress = false;
  opt.inBetween = false;
  const scenes::CameraPath path = shortPath();
  ASSERT_TRUE(session::exportKeyframes(indoor(), path, dir, opt).ok());
  const json doc = loadCameras(dir);
  ASSERT_EQ(doc["keyframes"].size(), 4u);
  for (const json& c : doc["keyframes"]) {
    const std::string name = c["name"];
    const Camera cam = path.cameraAt(c["frame"].get<int>());
    auto depth = readPfm(dir + "/" + name + ".depth.pfm");
    ASSERT_TRUE(depth.ok()) << depth.error().message;
    int checked = 0;
    for (int y = 0; y < depth->height(); y += 5)
      for (int x = 0; x < depth->width(); x += 7) {
        const double z = (*depth)(x, y);
        if (z <= 0.0) continue;
        const double u = x + 0.5, v = y + 0.5;
        expectNear3(applyRowMajor(c["world_from_camera"], openCvPoint(c, u, v, z)),
                    cam.unproject(u, v, z),
                    name + " pixel " + std::to_string(x) + "," + std::to_string(y));
        // And back: the world point projects to the pixel centre at depth z.
        const ProjectedPoint p = cam.project(cam.unproject(u, v, z));
        EXPECT_NEAR(p.u, u, 1e-9);
        EXPECT_NEAR(p.v, v, 1e-9);
        ++checked;
      }
    EXPECT_GT(checked, 40) << name;
  }
}

TEST_F(ExportTest, WithoutInBetweenAndWithMaxFramesOnlyTheKeyframesOfThePrefix) {
  const std::string dir = freshDir("prefix");
  session::ExportOptions opt;
  opt.progress = false;
  opt.inBetween = false;
  opt.maxFrames = 7;  // keyframes 0, 5 and the prefix's last frame, 6
  ASSERT_TRUE(session::exportKeyframes(indoor(), shortPath(), dir, opt).ok());
  EXPECT_EQ(filesIn(dir), (std::set<std::string>{
                              "cameras.json", "key_0000.png", "key_0000.depth.pfm", "key_0005.png",
                              "key_0005.depth.pfm", "key_0006.png", "key_0006.depth.pfm"}));
  const json doc = loadCameras(dir);
  EXPECT_EQ(doc["keyframes"].size(), 3u);
  ASSERT_TRUE(doc["in_between"].is_array());
  EXPECT_TRUE(doc["in_between"].empty());
}

TEST_F(ExportTest, UnwritableOutputIsAnErrorAndNothingIsWritten) {
  const std::string dir = freshDir("unwritable");
  fs::create_directories(dir);
  const std::string blocker = dir + "/a-file";
  std::ofstream(blocker) << "not a directory";
  session::ExportOptions opt;
  opt.progress = false;
  for (const std::string& out : {blocker, blocker + "/sub"}) {
    const Status st = session::exportKeyframes(indoor(), shortPath(), out, opt);
    ASSERT_FALSE(st.ok()) << out;
    EXPECT_NE(st.error().message.find(blocker), std::string::npos) << st.error().message;
  }
  EXPECT_EQ(filesIn(dir), std::set<std::string>{"a-file"});
  EXPECT_FALSE(session::exportKeyframes(indoor(), shortPath(), "", opt).ok());
}

}  // namespace
}  // namespace hw
