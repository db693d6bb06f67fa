#include "session/export.h"
#include "core/progress.h"

#include <stb_image_write.h>  // implementation compiled in core/file_io.cpp

#include <algorithm>
#include <cstdio>
#include <string_view>
#include <vector>

#include "core/check.h"
#include "core/file_io.h"
#include "core/pfm.h"
#include "core/timer.h"
#include "keyframe/geometry_renderer.h"
#include "keyframe/keyframe.h"
#include "keyframe/keyframe_cache.h"

namespace hw::session {
namespace {

using json = nlohmann::json;

void appendBytes(void* ctx, void* data, int size) {
  static_cast<std::string*>(ctx)->append(static_cast<const char*>(data),
                                         static_cast<std::size_t>(size));
}

// The contract says RGB: alpha is dropped (the renderer writes 255 anyway).
Status writePngRgb(const std::string& file, const Image<Rgba8>& image) {
  if (image.empty()) return makeError("cannot write " + file + ": image is empty");
  std::vector<unsigned char> rgb(image.size() * 3);
  for (std::size_t i = 0; i < image.size(); ++i) {
    const Rgba8 p = image.data()[i];
    rgb[3 * i + 0] = p.r;
    rgb[3 * i + 1] = p.g;
    rgb[3 * i + 2] = p.b;
  }
  std::string bytes;
  if (!stbi_write_png_to_func(appendBytes, &bytes, image.width(), image.height(), 3, rgb.data(),
                              image.width() * 3))
    return makeError("cannot encode PNG " + file);
  return writeFileAtomic(file, bytes);
}

std::string numbered(const char* prefix, int frame) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%s_%04d", prefix, frame);
  return buf;
}


}  // namespace

std::string exportKeyframeName(int frame) { return numbered("key", frame); }
std::string exportFrameName(int frame) { return numbered("frame", frame); }

json exportCameraJson(const std::string& name, const Camera& camera) {
  const glm::dmat4 m = camera.worldFromCameraOpenCv();  // column-major: m[col][row]
  json rows = json::array();
  for (int r = 0; r < 4; ++r) rows.push_back({m[0][r], m[1][r], m[2][r], m[3][r]});
  return {{"name", name},
          {"width", camera.width},
          {"height", camera.height},
          {"fx", camera.fx()},
          {"fy", camera.fy()},
          {"cx", camera.cx()},
          {"cy", camera.cy()},
          {"near", camera.nearPlane},
          {"far", camera.farPlane},
          {"world_from_camera", rows}};
}

Status exportKeyframes(const scenes::Scene& scene, const scenes::CameraPath& path,
                       const std::string& outDir, const ExportOptions& options) {
  if (outDir.empty()) return makeError("keyframe export: no output directory given");
  if (options.maxFrames < 0)
    return makeError("keyframe export: max frames must be >= 0, got " +
                     std::to_string(options.maxFrames));
  HW_CHECK_GE(path.frames, 1);
  HW_CHECK_GE(path.keyframeEvery, 1);
  HW_TRY(ensureWritableDir(outDir));
  const int frames = options.maxFrames > 0 ? std::min(options.maxFrames, path.frames) : path.frames;
  const keyframe::KeyframeSchedule schedule{frames, path.keyframeEvery, {}};

  int total = 0;
  for (int i = 0; i < frames; ++i)
    if (options.inBetween || schedule.isKeyframe(i)) ++total;

  keyframe::RenderOptions ropt;
  ropt.depthMode = options.depthMode;
  auto rendererR = keyframe::GeometryRenderer::create(scene, ropt);
  if (!rendererR) return rendererR.error();
  keyframe::GeometryRenderer& renderer = **rendererR;

  const std::string dir = outDir.back() == '/' ? outDir : outDir + "/";
  json keyframes = json::array(), inBetween = json::array();
  keyframe::Keyframe kf;
  Image<Rgba8> colour;
  Progress progress(options.progress, total, "export");
  int done = 0;
  for (int i = 0; i < frames; ++i) {
    const bool isKey = schedule.isKeyframe(i);
    if (!isKey && !options.inBetween) continue;
    const Camera camera = path.cameraAt(i);
    if (isKey) {
      const std::string name = exportKeyframeName(i);
      HW_TRY(renderer.renderKeyframe(camera, kf));
      HW_TRY(writePngRgb(dir + name + ".png", kf.colour));
      HW_TRY(writePfm(dir + name + ".depth.pfm", kf.eyeZ));
      json c = exportCameraJson(name, camera);
      c["frame"] = i;
      c["is_keyframe"] = true;
      keyframes.push_back(std::move(c));
    } else {
      const std::string name = exportFrameName(i);
      HW_TRY(renderer.renderColour(camera, colour));
      HW_TRY(writePngRgb(dir + name + ".png", colour));
      const auto [k0, k1] = schedule.bracket(i);
      json c = exportCameraJson(name, camera);
      c["frame"] = i;
      c["is_keyframe"] = false;
      c["keyframes"] = {exportKeyframeName(k0), exportKeyframeName(k1)};
      inBetween.push_back(std::move(c));
    }
    progress.update(++done);
  }

  const json doc = {{"format", "hybridwalk-keyframes"},
                    {"version", 1},
                    {"keyframes", std::move(keyframes)},
                    {"in_between", std::move(inBetween)}};
  return writeFileAtomic(dir + "cameras.json", doc.dump(2) + "\n");
}

}  // namespace hw::session
