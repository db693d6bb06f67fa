// Camera path parsing (DESIGN.md "Camera path (JSON)") and constant-speed
// sampling: uniform Catmull-Rom through the eyes and, separately, through the
// look-at points, reparametrised by arc length of the eye curve.
#include "scenes/camera_path.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/file_io.h"
#include "core/json_guard.h"
#include "core/metrics.h"

namespace hw::scenes {
namespace {

using Json = nlohmann::json;

constexpr double kPi = 3.14159265358979323846;
// Sine of the smallest angle allowed between the view direction and `up`.
constexpr double kMinSinViewUp = 1e-6;
// Arc-length samples per curve segment; linear interpolation between them
// keeps frame spacing within ~0.1% of uniform for ordinary paths.
constexpr int kSamplesPerSegment = 128;

// The value a user wrote, briefly. Arrays and objects are summarised rather
// than dumped: dump() recurses, and a file of deeply nested arrays would
// overflow the stack here.
std::string describe(const Json& j) {
  if (j.is_array()) return "an array of " + std::to_string(j.size()) + " elements";
  if (j.is_object()) return "an object with " + std::to_string(j.size()) + " keys";
  std::string s = j.dump();
  if (s.size() > 60) s = s.substr(0, 57) + "...";
  if (j.is_string()) return "string " + s;
  if (j.is_boolean()) return "boolean " + s;
  if (j.is_null()) return "null";
  return s;
}

// Input limits (docs/bad-input.md, "Limits"). Frames below SSIM's window
// cannot be measured; a camera farther out than kMaxCoordinate makes the
// Catmull-Rom and look-at arithmetic overflow (1e308 gives inf − inf = NaN);
// the projection is built in single precision, so a subnormal near plane or a
// vanishing field of view gives an all-blank image.
constexpr int kMinPathSide = kSsimWindow;
constexpr double kMaxCoordinate = 1e9;
constexpr double kMinNear = 1e-6;
constexpr double kMaxFarOverNear = 1e8;
constexpr double kMinFovDeg = 1e-3;
constexpr int kMaxPathFrames = 1000000;
constexpr std::uint64_t kMaxPathFileBytes = 64ull << 20;

std::string fmtNum(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

struct Ctx {
  std::string source;
  Error fail(const std::string& key, const std::string& expected, const Json& got) const {
    return makeError(source + ": " + key + ": expected " + expected + ", got " + describe(got));
  }
  Error fail(const std::string& key, const std::string& what) const {
    return makeError(source + ": " + key + ": " + what);
  }
};

Error tooSmall(const Ctx& c, const std::string& key, int v) {
  return c.fail(key, "expected at least " + std::to_string(kMinPathSide) +
                         " pixels (the SSIM metric uses an " + std::to_string(kMinPathSide) + "x" +
                         std::to_string(kMinPathSide) + " window), got " + std::to_string(v));
}

Result<double> getNumber(const Ctx& c, const Json& j, const std::string& key) {
  if (!j.is_number()) return c.fail(key, "a number", j);
  const double v = j.get<double>();
  if (!std::isfinite(v)) return c.fail(key, "a finite number", j);
  return v;
}

Result<int> getInt(const Ctx& c, const Json& j, const std::string& key, int lo, int hi) {
  const std::string expected =
      "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  const std::string expectedLo = "an integer >= " + std::to_string(lo);
  const std::string& exp = hi == std::numeric_limits<int>::max() ? expectedLo : expected;
  if (!j.is_number_integer()) return c.fail(key, exp, j);
  if (j.is_number_unsigned()) {
    const auto u = j.get<std::uint64_t>();
    if (static_cast<std::int64_t>(std::min<std::uint64_t>(u, INT64_MAX)) < lo ||
        u > static_cast<std::uint64_t>(hi))
      return c.fail(key, exp, j);
    return static_cast<int>(u);
  }
  const auto v = j.get<std::int64_t>();
  if (v < lo || v > hi) return c.fail(key, exp, j);
  return static_cast<int>(v);
}

Result<glm::dvec3> getVec3(const Ctx& c, const Json& j, const std::string& key) {
  if (!j.is_array() || j.size() != 3) return c.fail(key, "an array of 3 numbers", j);
  glm::dvec3 v(0.0);
  for (int i = 0; i < 3; ++i) {
    const std::string name = key + "[" + std::to_string(i) + "]";
    auto x = getNumber(c, j[static_cast<std::size_t>(i)], name);
    if (!x) return x.error();
    if (std::abs(*x) > kMaxCoordinate)
      return c.fail(name,
                    "a coordinate of magnitude at most " + fmtNum(kMaxCoordinate) +
                        " (camera arithmetic beyond that overflows)",
                    j[static_cast<std::size_t>(i)]);
    v[i] = *x;
  }
  return v;
}

std::string fmtVec(const glm::dvec3& v) {
  std::ostringstream s;
  s << "[" << v.x << ", " << v.y << ", " << v.z << "]";
  return s.str();
}

bool parallel(const glm::dvec3& dir, const glm::dvec3& up) {
  const double ld = glm::length(dir), lu = glm::length(up);
  if (ld <= 0.0 || lu <= 0.0) return true;
  return glm::length(glm::cross(dir / ld, up / lu)) < kMinSinViewUp;
}

// Uniform Catmull-Rom on segment [p1, p2] with neighbours p0, p3, t in [0, 1].
glm::dvec3 catmullRom(const glm::dvec3& p0, const glm::dvec3& p1, const glm::dvec3& p2,
                      const glm::dvec3& p3, double t) {
  const double t2 = t * t, t3 = t2 * t;
  return 0.5 * ((2.0 * p1) + (-p0 + p2) * t + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * t2 +
                (-p0 + 3.0 * p1 - 3.0 * p2 + p3) * t3);
}

enum class Which { Eye, LookAt };

// Point at global parameter u in [0, n−1] (n = keys), end points duplicated.
glm::dvec3 curveAt(const std::vector<CameraKey>& keys, Which which, double u) {
  const int n = static_cast<int>(keys.size());
  auto pt = [&](int i) -> const glm::dvec3& {
    const CameraKey& k = keys[static_cast<std::size_t>(std::clamp(i, 0, n - 1))];
    return which == Which::Eye ? k.eye : k.lookAt;
  };
  if (n == 1) return pt(0);
  u = std::clamp(u, 0.0, static_cast<double>(n - 1));
  int seg = std::min(static_cast<int>(std::floor(u)), n - 2);
  const double t = u - seg;
  return catmullRom(pt(seg - 1), pt(seg), pt(seg + 1), pt(seg + 2), t);
}

// Cumulative arc length of one curve sampled kSamplesPerSegment times per
// segment: table[k] = length up to parameter k / kSamplesPerSegment.
std::vector<double> arcLengthTable(const std::vector<CameraKey>& keys, Which which) {
  const int segs = static_cast<int>(keys.size()) - 1;
  const int m = segs * kSamplesPerSegment;
  std::vector<double> table(static_cast<std::size_t>(m) + 1, 0.0);
  glm::dvec3 prev = curveAt(keys, which, 0.0);
  for (int k = 1; k <= m; ++k) {
    const glm::dvec3 p = curveAt(keys, which, static_cast<double>(k) / kSamplesPerSegment);
    table[static_cast<std::size_t>(k)] =
        table[static_cast<std::size_t>(k) - 1] + glm::length(p - prev);
    prev = p;
  }
  return table;
}

// Curve parameter at which the arc length reaches `s` (linear between samples).
double parameterAtLength(const std::vector<double>& table, double s) {
  const auto it = std::lower_bound(table.begin(), table.end(), s);
  if (it == table.begin()) return 0.0;
  if (it == table.end()) return static_cast<double>(table.size() - 1) / kSamplesPerSegment;
  const auto k = static_cast<std::size_t>(it - table.begin());
  const double a = table[k - 1], b = table[k];
  const double f = b > a ? (s - a) / (b - a) : 0.0;
  return (static_cast<double>(k - 1) + f) / kSamplesPerSegment;
}

// An up vector that is not parallel to `forward`: `up` itself when usable,
// else the world axis least aligned with the view direction.
glm::dvec3 safeUp(const glm::dvec3& forward, const glm::dvec3& up) {
  if (!parallel(forward, up)) return up;
  const glm::dvec3 f = glm::normalize(forward);
  const glm::dvec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  int best = 0;
  for (int i = 1; i < 3; ++i)
    if (std::abs(glm::dot(f, axes[i])) < std::abs(glm::dot(f, axes[best]))) best = i;
  return glm::cross(glm::cross(f, axes[best]), f);
}

}  // namespace

namespace {

// The arc-length table frames are spaced by: the eye curve's, or for a pure
// rotation (all eyes coincide) the look-at curve's. Empty for one key.
std::vector<double> spacingTable(const CameraPath& p) {
  if (p.keys.size() < 2 || p.frames < 2) return {};
  std::vector<double> table = arcLengthTable(p.keys, Which::Eye);
  const double scale = std::max(1.0, glm::length(p.keys.front().eye));
  if (table.back() <= 1e-9 * scale) table = arcLengthTable(p.keys, Which::LookAt);
  return table;
}

Camera cameraOnPath(const CameraPath& p, const std::vector<double>& table, int index) {
  HW_CHECK(!p.keys.empty());
  HW_CHECK_GE(index, 0);
  HW_CHECK_LT(index, std::max(p.frames, 1));
  const int n = static_cast<int>(p.keys.size());
  double u = 0.0;  // global curve parameter in [0, n−1]
  if (n > 1 && p.frames > 1) {
    const double frac = static_cast<double>(index) / (p.frames - 1);
    if (table.back() > 1e-12)
      u = parameterAtLength(table, frac * table.back());
    else
      u = frac * (n - 1);
  }
  if (index == p.frames - 1) u = n - 1;  // exactly at the last key
  const glm::dvec3 eye = curveAt(p.keys, Which::Eye, u);
  glm::dvec3 target = curveAt(p.keys, Which::LookAt, u);
  if (!(glm::length(target - eye) > 1e-9)) {
    // Curves cross here: keep the nearest key's viewing direction.
    const CameraKey& k =
        p.keys[static_cast<std::size_t>(std::clamp(static_cast<int>(std::lround(u)), 0, n - 1))];
    glm::dvec3 dir = k.lookAt - k.eye;
    if (!(glm::length(dir) > 0.0)) dir = glm::dvec3(0, 0, -1);
    target = eye + glm::normalize(dir);
  }
  const glm::dvec3 upHint =
      safeUp(target - eye, glm::length(p.up) > 0.0 ? p.up : glm::dvec3(0, 1, 0));
  return Camera::lookAt(eye, target, upHint, p.fovYDeg * kPi / 180.0, p.width, p.height,
                        p.nearPlane, p.farPlane);
}

}  // namespace

Camera CameraPath::cameraAt(int index) const {
  return cameraOnPath(*this, spacingTable(*this), index);
}

std::vector<Camera> CameraPath::cameras() const {
  const std::vector<double> table = spacingTable(*this);
  std::vector<Camera> out;
  out.reserve(static_cast<std::size_t>(std::max(frames, 1)));
  for (int i = 0; i < std::max(frames, 1); ++i) out.push_back(cameraOnPath(*this, table, i));
  return out;
}

Result<CameraPath> parseCameraPath(const std::string& jsonText, const std::string& source) {
  const Ctx c{source};
  auto parsed = parseJsonStrict(jsonText, source);
  if (!parsed) return parsed.error();
  const Json& root = *parsed;
  if (!root.is_object()) return c.fail("(top level)", "an object", root);

  static const char* const kKnown[] = {"width", "height", "fov_y_deg", "near",          "far",
                                       "up",    "keys",   "frames",    "keyframe_every"};
  for (const auto& item : root.items()) {
    if (std::find_if(std::begin(kKnown), std::end(kKnown),
                     [&](const char* k) { return item.key() == k; }) == std::end(kKnown))
      return c.fail(item.key(),
                    "unknown key (known: width, height, fov_y_deg, near, far, up, keys, frames, "
                    "keyframe_every)");
  }
  for (const char* required : {"keys", "frames"})
    if (!root.contains(required)) return c.fail(required, "missing (required)");

  CameraPath p;
  if (root.contains("width")) {
    auto v = getInt(c, root["width"], "width", 1, 16384);
    if (!v) return v.error();
    if (*v < kMinPathSide) return tooSmall(c, "width", *v);
    p.width = *v;
  }
  if (root.contains("height")) {
    auto v = getInt(c, root["height"], "height", 1, 16384);
    if (!v) return v.error();
    if (*v < kMinPathSide) return tooSmall(c, "height", *v);
    p.height = *v;
  }
  if (root.contains("fov_y_deg")) {
    auto v = getNumber(c, root["fov_y_deg"], "fov_y_deg");
    if (!v) return v.error();
    if (!(*v > 0.0 && *v < 180.0))
      return c.fail("fov_y_deg", "a number in (0, 180)", root["fov_y_deg"]);
    if (*v < kMinFovDeg)
      return c.fail("fov_y_deg",
                    "at least " + fmtNum(kMinFovDeg) +
                        " degrees (a narrower view has no representable projection in single "
                        "precision: frames would be blank)",
                    root["fov_y_deg"]);
    p.fovYDeg = *v;
  }
  if (root.contains("near")) {
    auto v = getNumber(c, root["near"], "near");
    if (!v) return v.error();
    if (!(*v > 0.0)) return c.fail("near", "a number > 0", root["near"]);
    if (*v < kMinNear)
      return c.fail("near",
                    "a number >= " + fmtNum(kMinNear) +
                        " (a nearer plane underflows the single-precision projection: frames "
                        "would be blank)",
                    root["near"]);
    p.nearPlane = *v;
  }
  if (root.contains("far")) {
    auto v = getNumber(c, root["far"], "far");
    if (!v) return v.error();
    if (std::abs(*v) > kMaxCoordinate)
      return c.fail("far", "a distance of at most " + fmtNum(kMaxCoordinate), root["far"]);
    p.farPlane = *v;
  }
  if (!(p.farPlane > p.nearPlane)) {
    std::ostringstream s;
    s << "expected far > near, got near " << p.nearPlane << " and far " << p.farPlane;
    return c.fail(root.contains("far") ? "far" : "near", s.str());
  }
  if (p.farPlane / p.nearPlane > kMaxFarOverNear) {
    std::ostringstream s;
    s << "expected far / near <= " << kMaxFarOverNear
      << " (the depth buffer has no resolution left beyond that), got near " << p.nearPlane
      << " and far " << p.farPlane;
    return c.fail(root.contains("far") ? "far" : "near", s.str());
  }
  if (root.contains("up")) {
    auto v = getVec3(c, root["up"], "up");
    if (!v) return v.error();
    if (glm::length(*v) <= 0.0) return c.fail("up", "a non-zero vector", root["up"]);
    p.up = *v;
  }
  {
    auto v = getInt(c, root["frames"], "frames", 1, std::numeric_limits<int>::max());
    if (!v) return v.error();
    if (*v > kMaxPathFrames)
      return c.fail("frames",
                    "at most " + std::to_string(kMaxPathFrames) +
                        " frames (one camera per frame is kept in memory)",
                    root["frames"]);
    p.frames = *v;
  }
  if (root.contains("keyframe_every")) {
    auto v =
        getInt(c, root["keyframe_every"], "keyframe_every", 1, std::numeric_limits<int>::max());
    if (!v) return v.error();
    p.keyframeEvery = *v;
  }

  const Json& keys = root["keys"];
  if (!keys.is_array() || keys.empty())
    return c.fail("keys", "a non-empty array of {eye, look_at}", keys);
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const std::string name = "keys[" + std::to_string(i) + "]";
    const Json& k = keys[i];
    if (!k.is_object())
      return c.fail(name, "an object {\"eye\": [x, y, z], \"look_at\": [x, y, z]}", k);
    for (const auto& item : k.items())
      if (item.key() != "eye" && item.key() != "look_at")
        return c.fail(name + "." + item.key(), "unknown key (known: eye, look_at)");
    for (const char* required : {"eye", "look_at"})
      if (!k.contains(required)) return c.fail(name + "." + required, "missing (required)");
    CameraKey key;
    auto eye = getVec3(c, k["eye"], name + ".eye");
    if (!eye) return eye.error();
    auto at = getVec3(c, k["look_at"], name + ".look_at");
    if (!at) return at.error();
    key.eye = *eye;
    key.lookAt = *at;
    if (key.eye == key.lookAt)
      return c.fail(name + ".look_at",
                    "expected a point different from eye, got " + fmtVec(key.lookAt) + " == eye");
    if (parallel(key.lookAt - key.eye, p.up))
      return c.fail(name + ".look_at", "view direction " + fmtVec(key.lookAt - key.eye) +
                                           " is parallel to up " + fmtVec(p.up));
    p.keys.push_back(key);
  }
  return p;
}

Result<CameraPath> loadCameraPath(const std::string& file) {
  auto text = readFile(file, kMaxPathFileBytes);
  if (!text) return text.error();
  return parseCameraPath(*text, file);
}

std::string cameraPathToJson(const CameraPath& path) {
  nlohmann::ordered_json j;
  j["width"] = path.width;
  j["height"] = path.height;
  j["fov_y_deg"] = path.fovYDeg;
  j["near"] = path.nearPlane;
  j["far"] = path.farPlane;
  j["up"] = {path.up.x, path.up.y, path.up.z};
  nlohmann::ordered_json keys = nlohmann::ordered_json::array();
  for (const CameraKey& k : path.keys) {
    nlohmann::ordered_json o;
    o["eye"] = {k.eye.x, k.eye.y, k.eye.z};
    o["look_at"] = {k.lookAt.x, k.lookAt.y, k.lookAt.z};
    keys.push_back(o);
  }
  j["keys"] = keys;
  j["frames"] = path.frames;
  j["keyframe_every"] = path.keyframeEvery;
  return j.dump(2) + "\n";
}

}  // namespace hw::scenes
