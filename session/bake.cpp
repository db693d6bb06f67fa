#include "session/bake.h"

#include <algorithm>
#include <filesystem>

#include "core/progress.h"
#include "core/file_io.h"
#include "keyframe/geometry_renderer.h"
#include "keyframe/keyframe_cache.h"

namespace hw::session {

int bakeFrames(const scenes::CameraPath& path, int maxFrames) {
  return maxFrames > 0 ? std::min(maxFrames, path.frames) : path.frames;
}

std::vector<int> bakeKeyframeList(const scenes::CameraPath& path, int frames) {
  // The walk's default schedule (bench/walk.cpp): every keyframeEvery-th frame
  // plus the last.
  return keyframe::KeyframeSchedule{frames, path.keyframeEvery, {}}.keyframes();
}

keyframe::KeyframeDbProvenance bakeProvenance(const std::string& sceneLabel, std::size_t triangles,
                                              const scenes::CameraPath& path, int frames,
                                              const keyframe::LodOptions& lod,
                                              DepthMode depthMode) {
  keyframe::KeyframeDbProvenance p;
  p.scene = sceneLabel;
  p.triangles = triangles;
  const std::string pathJson = scenes::cameraPathToJson(path);
  p.pathHash = keyframe::hex64(keyframe::hw64(pathJson.data(), pathJson.size()));
  p.frames = frames;
  p.width = path.width;
  p.height = path.height;
  p.depthMode = depthModeName(depthMode);
  p.mesh = keyframe::meshOptionsJson(lod);
  return p;
}

Result<std::vector<keyframe::KeyframeDbEntry>> bakeKeyframes(const scenes::Scene& scene,
                                                             const scenes::CameraPath& path,
                                                             const std::vector<int>& keyframes,
                                                             const BakeOptions& opt) {
  if (opt.outDir.empty()) return makeError("bake: an output directory (--out) is required");
  HW_TRY(ensureWritableDir(opt.outDir));
  keyframe::RenderOptions ropt;
  ropt.depthMode = opt.depthMode;
  auto renderer = keyframe::GeometryRenderer::create(scene, ropt);
  if (!renderer) return renderer.error();
  keyframe::LodBuilder builder;
  keyframe::Keyframe kf;
  keyframe::QuadMesh mesh;
  std::vector<keyframe::KeyframeDbEntry> entries;
  Progress progress(opt.progress, static_cast<int>(keyframes.size()), "bake");
  for (std::size_t i = 0; i < keyframes.size(); ++i) {
    const int frame = keyframes[i];
    keyframe::RenderStats rs;
    HW_TRY((*renderer)->renderKeyframe(path.cameraAt(frame), kf, &rs));
    HW_TRY(builder.build(kf, opt.lod, &mesh));
    const std::string bytes = keyframe::encodeKeyframe(frame, kf, mesh, rs);
    keyframe::KeyframeDbEntry e;
    e.frame = frame;
    e.file = keyframe::keyframeFileName(frame);
    e.bytes = bytes.size();
    e.checksum = *keyframe::keyframeFileChecksum(bytes, e.file);
    HW_TRY(writeFileAtomic(opt.outDir + "/" + e.file, bytes));
    entries.push_back(e);
    progress.update(static_cast<int>(i + 1));
  }
  return entries;
}

Status writeBakeIndex(const std::string& outDir, const keyframe::KeyframeDbProvenance& provenance,
                      const std::vector<keyframe::KeyframeDbEntry>& entriesIn) {
  std::vector<keyframe::KeyframeDbEntry> entries = entriesIn;
  std::sort(entries.begin(), entries.end(),
            [](const auto& a, const auto& b) { return a.frame < b.frame; });
  for (const auto& e : entries) {
    std::error_code ec;
    const std::string f = outDir + "/" + e.file;
    const auto size = std::filesystem::file_size(f, ec);
    if (ec)
      return makeError(f + ": " + ec.message() + " (expected the keyframe of frame " +
                       std::to_string(e.frame) + ")");
    if (size != e.bytes)
      return makeError(f + ": " + std::to_string(size) + " bytes, expected " +
                       std::to_string(e.bytes));
  }
  return writeFileAtomic(outDir + "/index.json",
                         keyframe::keyframeDbIndexJson(provenance, entries));
}

}  // namespace hw::session
