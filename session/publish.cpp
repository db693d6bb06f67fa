#include "session/publish.h"

#include <stb_image_write.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <vector>

#include "core/file_io.h"
#include "keyframe/keyframe_db.h"
#include "scenes/camera_path.h"
#include "scenes/loader.h"
#include "session/bake.h"
#include "warp/warp_vertices.h"

namespace hw::session {
namespace {

using nlohmann::json;

void appendBytes(void* context, void* data, int size) {
  static_cast<std::string*>(context)->append(static_cast<const char*>(data),
                                             static_cast<std::size_t>(size));
}

// The keyframe's colour as an RGB PNG (the warp reads only RGB).
std::string colourPng(const Image<Rgba8>& colour) {
  std::vector<std::uint8_t> rgb(colour.size() * 3);
  for (std::size_t i = 0; i < colour.size(); ++i) {
    rgb[3 * i] = colour.data()[i].r;
    rgb[3 * i + 1] = colour.data()[i].g;
    rgb[3 * i + 2] = colour.data()[i].b;
  }
  std::string out;
  stbi_write_png_to_func(appendBytes, &out, colour.width(), colour.height(), 3, rgb.data(),
                         colour.width() * 3);
  return out;
}

template <class T>
void putLe(std::string& s, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));  // little-endian hosts only (as the keyframe database)
  s.append(b, sizeof(T));
}

// docs/publish.md "Mesh file": header, then the vertices.
std::string meshFile(const warp::WarpVertices& v) {
  std::string s;
  s.append(kWebMeshMagic, sizeof kWebMeshMagic);
  putLe<std::uint32_t>(s, static_cast<std::uint32_t>(kPublishVersion));
  putLe<std::uint32_t>(s, static_cast<std::uint32_t>(v.quads));
  putLe<std::uint32_t>(s, static_cast<std::uint32_t>(v.skyRects));
  putLe<std::uint32_t>(s, static_cast<std::uint32_t>(warp::kFloatsPerWarpVertex));
  s.append(reinterpret_cast<const char*>(v.data.data()), v.data.size() * sizeof(float));
  return s;
}

json vec3(const glm::dvec3& v) { return json::array({v.x, v.y, v.z}); }

json fileEntry(const std::string& name, const std::string& bytes) {
  char sum[16];
  std::snprintf(sum, sizeof sum, "%08x", hw32(bytes.data(), bytes.size()));
  return {{"file", name}, {"bytes", bytes.size()}, {"checksum", sum}};
}

std::string stem(int frame) {
  char b[32];
  std::snprintf(b, sizeof b, "kf_%06d", frame);
  return b;
}

}  // namespace

std::uint32_t hw32(const void* data, std::size_t bytes) {
  const auto* p = static_cast<const unsigned char*>(data);
  std::uint32_t h = 2166136261u;
  for (std::size_t i = 0; i < bytes; i += 4) {
    std::uint32_t w = 0;
    for (std::size_t k = 0; k < 4 && i + k < bytes; ++k) w |= std::uint32_t(p[i + k]) << (8 * k);
    h = (h ^ w) * 16777619u;
  }
  return h ^ static_cast<std::uint32_t>(bytes);
}

Result<PublishResult> publish(const PublishOptions& o) {
  namespace fs = std::filesystem;
  if (o.outDir.empty()) return makeError("publish: an output directory (--out) is required");
  auto dbR = keyframe::KeyframeDb::open(o.dbDir);
  if (!dbR) return dbR.error();
  keyframe::KeyframeDb& db = *dbR;
  const json& bf = db.index()["baked_from"];
  const std::string indexPath = o.dbDir + "/index.json";
  if (!bf.contains("scene") || !bf["scene"].is_string() || !bf.contains("frames") ||
      !bf["frames"].is_number_integer() || !bf.contains("resolution") ||
      !bf["resolution"].is_array() || bf["resolution"].size() != 2 ||
      !bf["resolution"][0].is_number_integer() || !bf["resolution"][1].is_number_integer() ||
      !bf.contains("depth_mode") || !bf["depth_mode"].is_string())
    return makeError(indexPath +
                     ": baked_from needs scene (string), frames (integer), resolution ([w, h]) "
                     "and depth_mode (string)");
  PublishResult r;
  r.scene = bf["scene"].get<std::string>();
  r.frames = bf["frames"].get<int>();
  r.width = bf["resolution"][0].get<int>();
  r.height = bf["resolution"][1].get<int>();
  DepthMode depthMode = kDefaultDepthMode;
  if (!parseDepthMode(bf["depth_mode"].get<std::string>().c_str(), &depthMode))
    return makeError(indexPath + ": baked_from.depth_mode " + bf["depth_mode"].dump() +
                     ", expected fixed24, float32 or float32-reversed");

  // The path: the file given, or the scene's default; at the database's size.
  scenes::CameraPath path;
  if (!o.pathFile.empty()) {
    auto p = scenes::loadCameraPath(o.pathFile);
    if (!p) return p.error();
    path = std::move(*p);
  } else {
    std::vector<std::string> notes;
    auto p = scenes::defaultPathFor(r.scene, {}, &notes);
    if (!p)
      return makeError("publish: the default path of scene '" + r.scene + "' (" +
                       p.error().message + "); give the baked path with --path");
    path = std::move(*p);
  }
  path.width = r.width;
  path.height = r.height;
  if (r.frames < 1 || r.frames > path.frames)
    return makeError(indexPath + ": baked for " + std::to_string(r.frames) +
                     " frames, the path has " + std::to_string(path.frames));
  keyframe::KeyframeDbProvenance want;
  const std::string pathJson = scenes::cameraPathToJson(path);
  want.pathHash = keyframe::hex64(keyframe::hw64(pathJson.data(), pathJson.size()));
  want.frames = r.frames;
  want.width = r.width;
  want.height = r.height;
  if (auto st = db.checkMatches(want, {"path_hash", "frames", "resolution"}); !st)
    return makeError(st.error().message +
                     "; publish needs the camera path the database was baked from (--path)");
  HW_TRY(db.checkSchedule(bakeKeyframeList(path, r.frames)));
  std::vector<Camera> cams = path.cameras();
  cams.resize(static_cast<std::size_t>(r.frames));
  db.setExpectation({[&cams](int f) { return cams[static_cast<std::size_t>(f)]; }, depthMode});

  // Every keyframe checked before anything is written: a damaged database
  // leaves no half-published folder.
  for (int frame : db.keyframeFrames()) {
    keyframe::CachedKeyframe kf;
    HW_TRY(db.read(frame, kf));
  }
  HW_TRY(ensureWritableDir(o.outDir));
  std::error_code ec;
  fs::remove(o.outDir + "/manifest.json", ec);
  for (const auto& f : fs::directory_iterator(o.outDir, ec)) {
    const std::string name = f.path().filename().string();
    if (name.rfind("kf_", 0) == 0 &&
        (f.path().extension() == ".png" || f.path().extension() == ".mesh"))
      fs::remove(f.path(), ec);
  }

  const Camera& c0 = cams.front();
  json manifest = {{"format", kPublishFormat},   {"version", kPublishVersion},
                   {"scene", r.scene},           {"db_checksum", db.index()["index_checksum"]},
                   {"path_hash", want.pathHash}, {"width", r.width},
                   {"height", r.height},         {"fov_y_radians", c0.fovYRadians},
                   {"near", c0.nearPlane},       {"far", c0.farPlane}};
  json frames = json::array();
  for (const Camera& c : cams)
    frames.push_back({{"eye", vec3(c.eye)},
                      {"right", vec3(c.right)},
                      {"up", vec3(c.up)},
                      {"forward", vec3(c.forward)}});
  json keyframes = json::array();
  for (int frame : db.keyframeFrames()) {
    keyframe::CachedKeyframe kf;
    HW_TRY(db.read(frame, kf));
    const std::string png = colourPng(kf.keyframe.colour);
    const warp::WarpVertices v = warp::warpVertices(kf.keyframe, kf.mesh);
    const std::string mesh = meshFile(v);
    const std::string base = stem(frame);
    HW_TRY(writeFileAtomic(o.outDir + "/" + base + ".png", png));
    HW_TRY(writeFileAtomic(o.outDir + "/" + base + ".mesh", mesh));
    r.bytes += png.size() + mesh.size();
    json colour = fileEntry(base + ".png", png);
    json meshJ = fileEntry(base + ".mesh", mesh);
    meshJ["quads"] = v.quads;
    meshJ["sky_rects"] = v.skyRects;
    keyframes.push_back({{"frame", frame},
                         {"eye", vec3(kf.keyframe.camera.eye)},
                         {"colour", colour},
                         {"mesh", meshJ}});
  }
  manifest["keyframes"] = std::move(keyframes);
  manifest["frames"] = std::move(frames);
  r.keyframes = static_cast<int>(manifest["keyframes"].size());
  const std::string js = webPlayerJs();
  const std::string text = manifest.dump(1) + "\n";
  // index.html carries the manifest's size and checksum, so an edited
  // manifest (a camera, a file's checksum) is caught too.
  std::string html = webIndexHtml();
  char sum[48];
  std::snprintf(sum, sizeof sum, "%zu %08x", text.size(), hw32(text.data(), text.size()));
  const auto at = html.find("@MANIFEST@");
  if (at == std::string::npos) return makeError("publish: web/index.html has no @MANIFEST@ (a bug)");
  html.replace(at, 10, sum);
  HW_TRY(writeFileAtomic(o.outDir + "/player.js", js));
  HW_TRY(writeFileAtomic(o.outDir + "/index.html", html));
  // Last: a folder without manifest.json is incomplete.
  HW_TRY(writeFileAtomic(o.outDir + "/manifest.json", text));
  r.bytes += html.size() + js.size() + text.size();
  return r;
}

}  // namespace hw::session
