// Outdoor specs ("torcs:NAME", "morse:ENV/FILE", .acc/.blend files) to
// scenes and default paths. See outdoor_scenes.h for the contracts.
#include "scenes/outdoor_scenes.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "scenes/fetch.h"
#include "scenes/floor_walk.h"
#include "scenes/model_common.h"
#include "scenes/torcs_track.h"

namespace hw::scenes {
namespace {

namespace fs = std::filesystem;
using detail::lower;

}  // namespace

std::optional<Result<std::string>> outdoorSpecFile(const std::string& spec,
                                                   const std::string& cacheDir) {
  const std::string l = lower(spec.substr(0, std::min<std::size_t>(spec.size(), 6)));
  const fs::path root = fs::path(cacheDir) / "root";
  if (l.rfind("torcs:", 0) == 0) {
    const std::string name = spec.substr(6);
    if (name.empty())
      return Result<std::string>(
          makeError("scene 'torcs:': expected a track name, e.g. torcs:forza"));
    return findTorcsTrack((root / "usr" / "share" / "games" / "torcs").string(), name);
  }
  if (l.rfind("morse:", 0) == 0) {
    std::string rel = spec.substr(6);
    if (fs::path(rel).extension() != ".blend") rel += ".blend";
    const fs::path p = root / "usr" / "share" / "morse" / "data" / "environments" / rel;
    std::error_code ec;
    if (rel.find("..") != std::string::npos || !fs::is_regular_file(p, ec))
      return Result<std::string>(makeError(
          "scene '" + spec + "': no " + p.string() +
          " (expected morse:ENV/FILE, e.g. morse:land-1/trees; run `hybridwalk scenes fetch "
          "--outdoor` to fetch morse-simulator-data)"));
    return Result<std::string>(p.string());
  }
  return std::nullopt;
}

std::optional<Result<Scene>> loadOutdoorFile(const std::string& path) {
  const std::string ext = lower(fs::path(path).extension().string());
  if (ext == ".acc") {
    auto m = loadTorcsTrack(path);
    if (!m) return Result<Scene>(m.error());
    return Result<Scene>(std::move(m->scene));
  }
  if (ext == ".blend") return loadBlendFile(path);
  return std::nullopt;
}

namespace {

// The file an outdoor spec or path names, and whether it is ours.
std::optional<Result<std::string>> outdoorFileOf(const std::string& spec) {
  std::error_code ec;
  if (!spec.empty() && fs::is_regular_file(spec, ec)) {
    const std::string ext = lower(fs::path(spec).extension().string());
    if (ext == ".acc" || ext == ".blend") return Result<std::string>(spec);
    return std::nullopt;
  }
  return outdoorSpecFile(spec, defaultSceneCacheDir());
}

}  // namespace

std::optional<Result<Scene>> loadOutdoorSpec(const std::string& spec) {
  auto file = outdoorFileOf(spec);
  if (!file) return std::nullopt;
  if (!*file) return Result<Scene>(file->error());
  return loadOutdoorFile(**file);
}

std::optional<Result<CameraPath>> outdoorDefaultPath(const std::string& spec,
                                                     const DefaultPathOptions& options,
                                                     std::vector<std::string>* notes) {
  auto file = outdoorFileOf(spec);
  if (!file) return std::nullopt;
  if (!*file) return Result<CameraPath>(file->error());
  if (lower(fs::path(**file).extension().string()) == ".acc") {
    DrivePathOptions o;
    o.metresPerFrame = options.metresPerFrame;
    if (options.eyeHeight > 0) o.eyeHeightMetres = options.eyeHeight;
    return torcsDefaultPath(**file, o, notes);
  }
  auto scene = loadBlendFile(**file);
  if (!scene) return Result<CameraPath>(scene.error());
  // On foot over the environment's floor (indoors under its roof); the
  // circle below where no floor is found.
  FloorWalkOptions fw;
  fw.eyeHeight = options.eyeHeight > 0 ? options.eyeHeight : 1.7;
  fw.frames = 240;
  auto floor = floorWalkPath(*scene, fw);
  if (floor) return floor;
  if (notes) notes->push_back(floor.error().message + "; walking a circle over the terrain instead");
  const TriangleGrid grid(*scene);
  const glm::dvec3 lo(scene->boundsMin), hi(scene->boundsMax), c = 0.5 * (lo + hi);
  const double r = 0.25 * std::min(hi.x - lo.x, hi.z - lo.z);
  std::vector<glm::dvec2> circle;
  for (int k = 0; k <= 24; ++k) {
    const double t = 2.0 * 3.14159265358979323846 * k / 24;
    circle.push_back({c.x + r * std::cos(t), c.z + r * std::sin(t)});
  }
  TerrainWalkOptions walk;
  if (options.eyeHeight > 0) walk.eyeHeightMetres = options.eyeHeight;
  return terrainWalkPath(grid, circle, walk);
}

}  // namespace hw::scenes
