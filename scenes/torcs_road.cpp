#include "scenes/torcs_road.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <random>

#include "core/short_number.h"
#include "scenes/model_common.h"
#include "scenes/triangle_grid.h"

namespace hw::scenes {
namespace {

namespace fs = std::filesystem;
using detail::lower;

double polylineLength(const std::vector<glm::dvec3>& p, bool closed) {
  double len = 0;
  for (std::size_t i = 0; i + 1 < p.size(); ++i) len += glm::length(p[i + 1] - p[i]);
  if (closed && p.size() > 1) len += glm::length(p.front() - p.back());
  return len;
}

// Point at arc length s of a closed polyline (s wraps).
glm::dvec3 pointAtClosed(const std::vector<glm::dvec3>& p, const std::vector<double>& cum,
                         double total, double s) {
  s = std::fmod(s, total);
  if (s < 0) s += total;
  const auto it = std::upper_bound(cum.begin(), cum.end(), s);
  const std::size_t i = static_cast<std::size_t>(std::max<std::ptrdiff_t>(0, it - cum.begin() - 1));
  const glm::dvec3& a = p[i];
  const glm::dvec3& b = p[(i + 1) % p.size()];
  const double seg = (i + 1 < cum.size() ? cum[i + 1] : total) - cum[i];
  const double t = seg > 0 ? (s - cum[i]) / seg : 0.0;
  return a + (b - a) * t;
}

}  // namespace

Result<Ac3dModel> loadTorcsTrack(const std::string& accPath) {
  Ac3dOptions o;
  // tracks/CATEGORY/NAME/NAME.acc → the install root holds data/textures.
  const fs::path root = fs::path(accPath).parent_path().parent_path().parent_path().parent_path();
  o.textureDirs = {(root / "data" / "textures").string(), (root / "data" / "img").string()};
  return loadAc3dFile(accPath, o);
}

Result<std::string> findTorcsTrack(const std::string& root, const std::string& name) {
  std::error_code ec;
  std::vector<std::string> found;
  if (fs::is_directory(root, ec)) {
    fs::recursive_directory_iterator it(root, fs::directory_options::skip_permission_denied, ec);
    for (; !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
      const fs::path& p = it->path();
      if (p.extension() != ".acc" || p.stem() != p.parent_path().filename()) continue;
      if (p.parent_path().parent_path().parent_path().filename() != "tracks") continue;
      if (p.stem() == name) return p.string();
      found.push_back(p.stem().string());
    }
  }
  std::sort(found.begin(), found.end());
  std::string list;
  for (const auto& f : found) list += (list.empty() ? "" : ", ") + f;
  return makeError("TORCS track '" + name + "': no tracks/*/" + name + "/" + name + ".acc under " +
                   root +
                   (found.empty() ? " (no TORCS tracks there: run `hybridwalk scenes fetch "
                                    "--outdoor` to fetch torcs-data)"
                                  : " (tracks found: " + list + ")"));
}

Result<std::vector<glm::dvec3>> roadCentreline(const Ac3dModel& track,
                                               const DrivePathOptions& options, bool* closed) {
  if (closed) *closed = false;
  const Scene& s = track.scene;
  std::vector<bool> isRoad(s.materials.size(), false);
  for (std::size_t m = 0; m < s.materials.size() && m < track.materialTextureNames.size(); ++m) {
    const std::string stem = lower(fs::path(track.materialTextureNames[m]).stem().string());
    for (const std::string& r : options.roadTextureStems) {
      const std::string lr = lower(r);
      if (stem.rfind(lr, 0) == 0) isRoad[m] = true;
    }
  }
  // Uniform samples on the road, about four per m², fixed seed.
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  std::vector<glm::dvec3> pts;
  for (const Mesh& m : s.meshes) {
    if (!isRoad[static_cast<std::size_t>(m.material)]) continue;
    for (std::size_t i = 0; i + 2 < m.indices.size(); i += 3) {
      const glm::dvec3 a(m.vertices[m.indices[i]].position),
          b(m.vertices[m.indices[i + 1]].position), c(m.vertices[m.indices[i + 2]].position);
      const double area = 0.5 * glm::length(glm::cross(b - a, c - a));
      const int n = std::max(1, static_cast<int>(std::lround(4.0 * area)));
      for (int k = 0; k < n; ++k) {
        double u = uni(rng), v = uni(rng);
        if (u + v > 1) u = 1 - u, v = 1 - v;
        pts.push_back(a + (b - a) * u + (c - a) * v);
      }
    }
  }
  if (pts.size() < 100)
    return makeError(
        s.name + ": no road found (materials with base texture " +
        (options.roadTextureStems.empty() ? std::string("?") : options.roadTextureStems[0]) +
        "*); cannot trace a centreline");
  constexpr double kCell = 4.0;
  std::unordered_map<std::int64_t, std::vector<std::uint32_t>> grid;
  auto key = [](int x, int z) { return (static_cast<std::int64_t>(x) << 32) ^ (z & 0xffffffffLL); };
  for (std::size_t i = 0; i < pts.size(); ++i)
    grid[key(static_cast<int>(std::floor(pts[i].x / kCell)),
             static_cast<int>(std::floor(pts[i].z / kCell)))]
        .push_back(static_cast<std::uint32_t>(i));
  auto near = [&](const glm::dvec3& q, double r, auto&& fn) {
    const int x0 = static_cast<int>(std::floor((q.x - r) / kCell)),
              x1 = static_cast<int>(std::floor((q.x + r) / kCell));
    const int z0 = static_cast<int>(std::floor((q.z - r) / kCell)),
              z1 = static_cast<int>(std::floor((q.z + r) / kCell));
    for (int z = z0; z <= z1; ++z)
      for (int x = x0; x <= x1; ++x)
        if (auto it = grid.find(key(x, z)); it != grid.end())
          for (std::uint32_t i : it->second) {
            const glm::dvec2 d(pts[i].x - q.x, pts[i].z - q.z);
            if (glm::dot(d, d) <= r * r) fn(pts[i]);
          }
  };
  // Cross-section of the road through q perpendicular to dir: the
  // contiguous cluster of samples (gaps < 2 m) nearest q; nullopt if none within 6 m.
  constexpr double kHalfWidthMax = 20.0;
  constexpr double kMaxRoadWidth = 22.0;
  const double kMaxShift = 0.35 * std::max(0.5, options.stepMetres);
  auto section = [&](const glm::dvec3& q, const glm::dvec2& dir) -> std::optional<glm::dvec3> {
    const glm::dvec2 side(-dir.y, dir.x);
    std::vector<std::pair<double, double>> lat;  // lateral offset, height
    near(q, kHalfWidthMax, [&](const glm::dvec3& p) {
      const glm::dvec2 d(p.x - q.x, p.z - q.z);
      if (std::abs(glm::dot(d, dir)) < 1.5 && std::abs(p.y - q.y) < 3.0)
        lat.push_back({glm::dot(d, side), p.y});
    });
    if (lat.size() < 3) return std::nullopt;
    std::sort(lat.begin(), lat.end());
    std::size_t best = 0;
    for (std::size_t i = 1; i < lat.size(); ++i)
      if (std::abs(lat[i].first) < std::abs(lat[best].first)) best = i;
    std::size_t lo = best, hi = best;
    while (lo > 0 && lat[lo].first - lat[lo - 1].first < 2.0) --lo;
    while (hi + 1 < lat.size() && lat[hi + 1].first - lat[hi].first < 2.0) ++hi;
    if (std::abs(lat[best].first) > 6.0) return std::nullopt;
    double mid = 0.5 * (lat[lo].first + lat[hi].first);
    // Wider than a road (a paddock or car park beside it): keep going
    // straight rather than drift into it.
    if (lat[hi].first - lat[lo].first > kMaxRoadWidth) {
      mid = 0.0;
      lo = hi = best;
    }
    // At most ~20° of heading change per step: no jumping onto a road
    // running alongside.
    mid = std::clamp(mid, -kMaxShift, kMaxShift);
    double y = 0;
    for (std::size_t i = lo; i <= hi; ++i) y += lat[i].second;
    y /= static_cast<double>(hi - lo + 1);
    return glm::dvec3(q.x + side.x * mid, y, q.z + side.y * mid);
  };

  // Start: the road sample nearest to the samples' mean; direction: the
  // principal axis of the road around it.
  glm::dvec3 mean(0.0);
  for (const auto& p : pts) mean += p;
  mean /= static_cast<double>(pts.size());
  glm::dvec3 start = pts[0];
  for (const auto& p : pts)
    if (glm::length(glm::dvec2(p.x - mean.x, p.z - mean.z)) <
        glm::length(glm::dvec2(start.x - mean.x, start.z - mean.z)))
      start = p;
  double cxx = 0, cxz = 0, czz = 0;
  near(start, 25.0, [&](const glm::dvec3& p) {
    const double dx = p.x - start.x, dz = p.z - start.z;
    cxx += dx * dx, cxz += dx * dz, czz += dz * dz;
  });
  const double ang = 0.5 * std::atan2(2 * cxz, cxx - czz);
  glm::dvec2 dir(std::cos(ang), std::sin(ang));
  if (auto c = section(start, dir)) start = *c;

  std::vector<glm::dvec3> line{start};
  glm::dvec3 p = start;
  const double step = std::max(0.5, options.stepMetres);
  const std::size_t maxSteps = static_cast<std::size_t>(200'000.0 / step);
  for (std::size_t k = 0; k < maxSteps; ++k) {
    // Gaps (a start line or pit entry in another texture) are bridged by
    // looking up to kMaxGap steps straight ahead.
    constexpr int kMaxGap = 8;
    glm::dvec3 q = p;
    std::optional<glm::dvec3> c;
    for (int g = 1; g <= kMaxGap && !c; ++g) {
      q = glm::dvec3(p.x + dir.x * step * g, p.y, p.z + dir.y * step * g);
      c = section(q, dir);
    }
    if (!c) {
      if (static_cast<double>(line.size() - 1) * step >= options.traceMetres) return line;
      return makeError(s.name + ": the road ends " +
                       std::to_string(static_cast<int>(static_cast<double>(line.size()) * step)) +
                       " m along the centreline trace (at x=" + shortNumber(q.x) +
                       ", z=" + shortNumber(q.z) + "), before the " +
                       std::to_string(static_cast<int>(options.traceMetres)) + " m asked for");
    }
    glm::dvec2 nd(c->x - p.x, c->z - p.z);
    if (glm::length(nd) < 1e-6) return makeError(s.name + ": centreline trace stalled");
    dir = glm::normalize(nd);
    p = *c;
    if (line.size() > 20 && glm::length(glm::dvec2(p.x - start.x, p.z - start.z)) < 0.75 * step) {
      if (closed) *closed = true;
      return line;
    }
    line.push_back(p);
    if (static_cast<double>(line.size() - 1) * step >= options.traceMetres) return line;
  }
  return makeError(s.name + ": the centreline trace did not return to its start after " +
                   std::to_string(maxSteps) + " steps");
}

Result<CameraPath> drivePath(const Ac3dModel& track, const DrivePathOptions& options) {
  DrivePathOptions o = options;
  o.traceMetres =
      options.startMetres + options.lengthMetres + options.lookAheadMetres + 2 * options.stepMetres;
  bool closed = false;
  auto lineR = roadCentreline(track, o, &closed);
  if (!lineR) return lineR.error();
  std::vector<glm::dvec3> line = std::move(*lineR);
  if (options.reverse) {
    if (!closed)
      return makeError(track.scene.name +
                       ": cannot drive in reverse: the centreline did not close");
    std::reverse(line.begin(), line.end());
  }
  // Light smoothing of the traced points (ends kept on open traces).
  {
    const std::size_t n = line.size();
    std::vector<glm::dvec3> sm(line);
    for (std::size_t i = 0; i < n; ++i) {
      if (!closed && (i == 0 || i + 1 == n)) continue;
      sm[i] = 0.25 * line[(i + n - 1) % n] + 0.5 * line[i] + 0.25 * line[(i + 1) % n];
    }
    line = std::move(sm);
  }
  std::vector<double> cum(line.size(), 0.0);
  for (std::size_t i = 1; i < line.size(); ++i)
    cum[i] = cum[i - 1] + glm::length(line[i] - line[i - 1]);
  const double total = polylineLength(line, closed);
  const double length = std::clamp(options.lengthMetres, 1.0, total);
  const glm::dvec3 up(0, options.eyeHeightMetres, 0);
  CameraPath path;
  path.nearPlane = 0.5;
  path.farPlane = 1000.0;
  path.frames = options.frames;
  path.keyframeEvery = options.keyframeEvery;
  const int keys = std::max(2, static_cast<int>(std::ceil(length / options.stepMetres)) + 1);
  for (int k = 0; k < keys; ++k) {
    const double sArc = options.startMetres + length * k / (keys - 1);
    path.keys.push_back({pointAtClosed(line, cum, total, sArc) + up,
                         pointAtClosed(line, cum, total, sArc + options.lookAheadMetres) + up});
  }
  return path;
}

}  // namespace hw::scenes
