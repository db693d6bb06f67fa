#include "session/bake.h"

#include <algorithm>
#include <filesystem>

#include "core/progress.h"
#include "core/json_guard.h"
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

Result<BakeStart> prepareBakeDir(const std::string& outDir,
                                 const keyframe::KeyframeDbProvenance& provenance,
                                 const scenes::CameraPath& path, const std::vector<int>& keyframes,
                                 DepthMode depthMode, bool resume) {
  namespace fs = std::filesystem;
  const std::string index = outDir + "/index.json";
  const std::string plan = outDir + "/.chunks/plan.json";
  std::error_code ec;
  const bool hasIndex = fs::exists(fs::symlink_status(index, ec));
  const bool hasPlan = fs::exists(plan, ec);
  if (!resume) {
    // The earlier database: its index first (a folder without index.json is
    // an incomplete database), then the keyframe files that index names.
    std::vector<std::string> files;
    if (hasIndex) {
      if (auto text = readFile(index, 256ull << 20)) {
        auto j = nlohmann::json::parse(*text, nullptr, false);
        if (j.is_object() && j.contains("keyframes"))
          if (auto es = keyframe::parseKeyframeEntries(j["keyframes"], index))
            for (const auto& e : *es) files.push_back(e.file);
      }
      if (!fs::remove(index, ec) && ec)
        return makeError("cannot remove " + index + ": " + ec.message());
    }
    for (const auto& f : files) fs::remove(outDir + "/" + f, ec);
    return BakeStart::Fresh;
  }
  if (hasIndex) {
    Status usable = [&]() -> Status {
      auto db = keyframe::KeyframeDb::open(outDir);
      if (!db) return db.error();
      if (auto st = db->checkMatches(provenance); !st)
        return makeError("--resume: " + outDir + " holds the database of another bake: " +
                         st.error().message + "; run without --resume to replace it");
      if (auto st = db->checkSchedule(keyframes); !st)
        return makeError("--resume: " + outDir + " holds the database of another bake: " +
                         st.error().message + "; run without --resume to replace it");
      db->setExpectation({[&path](int f) { return path.cameraAt(f); }, depthMode});
      return db->checkFiles();
    }();
    if (usable) return BakeStart::Complete;
    const std::string& why = usable.error().message;
    if (why.rfind("--resume: ", 0) == 0) return usable.error();  // another bake: left as it is
    if (!hasPlan)
      return makeError("--resume: " + outDir + " holds a damaged database (" + why +
                       ") and no interrupted bake to resume (no " + plan +
                       "); run without --resume to bake it again");
    // A damaged index over an interrupted run: the chunks rewrite it.
    fs::remove(index, ec);
    return BakeStart::Resume;
  }
  if (!hasPlan)
    return makeError("--resume: " + plan + " not found and no index.json: there is no " +
                     "interrupted bake run in " + outDir + " (run without --resume)");
  return BakeStart::Resume;
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
