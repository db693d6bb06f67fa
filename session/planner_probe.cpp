#include "session/planner_probe.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <glm/glm.hpp>
#include <limits>

#include "core/check.h"
#include "core/metrics.h"
#include "core/timer.h"
#include "gapfill/compose.h"
#include "keyframe/keyframe.h"
#include "warp/forward_splat.h"

namespace hw::session {

struct KeyframeProbe::Probe : warp::SplatSource {
  double medianDepth = 1;
};

struct KeyframeProbe::Scratch {
  warp::Layer a, b;
  // probeError: the composed probe and per-pixel sums for the blur.
  gapfill::Frame composed;
  std::vector<std::int32_t> sat;
};

struct KeyframeProbe::Warped {
  warp::Layer layer;
  long lastUse = 0;
};

KeyframeProbe::KeyframeProbe(keyframe::GeometryRenderer& renderer, std::function<Camera(int)> cameraOf,
                             int probeSize, ProbeErrorOptions error)
    : renderer_(renderer),
      cameraOf_(std::move(cameraOf)),
      probeSize_(probeSize),
      error_(error),
      scratch_(std::make_unique<Scratch>()) {
  HW_CHECK_GE(probeSize, 4);
  HW_CHECK_GE(error.supersample, 1);
  HW_CHECK_GE(error.blurRadius, 0);
  HW_CHECK_GE(error.shiftTolerance, 0);
}

KeyframeProbe::~KeyframeProbe() = default;

Camera KeyframeProbe::probeCamera(int frame) const {
  Camera c = cameraOf_(frame);
  const int longer = std::max(c.width, c.height);
  const double s = static_cast<double>(std::min(probeSize_, longer)) / longer;
  c.width = std::max(1, static_cast<int>(std::lround(c.width * s)));
  c.height = std::max(1, static_cast<int>(std::lround(c.height * s)));
  return c;
}

Result<const KeyframeProbe::Probe*> KeyframeProbe::probe(int frame) {
  auto it = probes_.find(frame);
  if (it != probes_.end()) return it->second.get();
  auto p = std::make_unique<Probe>();
  p->camera = probeCamera(frame);
  const int w = p->camera.width, h = p->camera.height;
  const int ss = error_.supersample;
  Camera rc = p->camera;
  rc.width = w * ss;
  rc.height = h * ss;
  keyframe::Keyframe kf;
  keyframe::RenderStats rs;
  HW_TRY(renderer_.renderKeyframe(rc, kf, &rs));
  renderMs_ += rs.drawMs + rs.readbackMs;
  ++probesRendered_;
  if (ss == 1) {
    p->colour = std::move(kf.colour);
    p->eyeZ = std::move(kf.eyeZ);
    p->covered = std::move(kf.covered);
  } else {
    // Box-filtered colour; a pixel is covered when most of its samples are,
    // at its nearest sample's depth (a depth average would float between
    // surfaces).
    p->colour = Image<Rgba8>(w, h);
    p->eyeZ = Image<float>(w, h);
    p->covered = Image<std::uint8_t>(w, h);
    const int n = ss * ss;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        int r = 0, g = 0, b = 0, a = 0, cov = 0;
        float zmin = std::numeric_limits<float>::infinity();
        for (int j = 0; j < ss; ++j)
          for (int i = 0; i < ss; ++i) {
            const Rgba8 c = kf.colour(x * ss + i, y * ss + j);
            r += c.r, g += c.g, b += c.b, a += c.a;
            if (kf.covered(x * ss + i, y * ss + j)) {
              ++cov;
              zmin = std::min(zmin, kf.eyeZ(x * ss + i, y * ss + j));
            }
          }
        auto avg = [&](int v) { return static_cast<std::uint8_t>((v + n / 2) / n); };
        p->colour(x, y) = Rgba8{avg(r), avg(g), avg(b), avg(a)};
        const bool c = 2 * cov > n;
        p->covered(x, y) = c ? 1 : 0;
        p->eyeZ(x, y) = c ? zmin : 0.0f;
      }
  }
  p->point.resize(static_cast<std::size_t>(w) * h);
  std::vector<double> depths;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t s = static_cast<std::size_t>(y) * w + x;
      if (p->covered(x, y)) {
        p->point[s] = p->camera.unproject(x + 0.5, y + 0.5, p->eyeZ(x, y));
        depths.push_back(p->eyeZ(x, y));
      } else {
        p->point[s] = glm::normalize(p->camera.unproject(x + 0.5, y + 0.5, 1.0) - p->camera.eye);
      }
    }
  // All sky: parallax is nil, any depth works; use the far plane.
  p->medianDepth = depths.empty() ? p->camera.farPlane : std::max(median(depths), 1e-6);
  const Probe* raw = p.get();
  probes_.emplace(frame, std::move(p));
  return raw;
}

namespace {
// FrameFeatures::relDistance: the eye's translation from the nearer keyframe
// relative to that keyframe's median scene depth.
double relativeDistance(const glm::dvec3& eye, const KeyframeProbe::Probe& a,
                        const KeyframeProbe::Probe& b) {
  return std::min(glm::length(eye - a.camera.eye) / a.medianDepth,
                  glm::length(eye - b.camera.eye) / b.medianDepth);
}
}  // namespace

Result<FrameFeatures> KeyframeProbe::features(int k0, int k1, int frame) {
  const auto key = std::make_tuple(k0, k1, frame);
  if (auto it = memo_.find(key); it != memo_.end()) return it->second;
  auto ra = probe(k0);
  if (!ra) return ra.error();
  auto rb = probe(k1);
  if (!rb) return rb.error();
  const Probe* pa = *ra;
  const Probe* pb = *rb;
  Stopwatch sw;
  const Camera t = probeCamera(frame);
  const Probe* fg = gapfill::chooseForeground(t.eye, pa->camera.eye, pb->camera.eye) == 0 ? pa : pb;
  const Probe* bg = fg == pa ? pb : pa;
  FrameFeatures f;
  f.relDistance = relativeDistance(t.eye, *pa, *pb);
  f.angleDeg =
      glm::degrees(std::acos(std::clamp(glm::dot(t.forward, fg->camera.forward), -1.0, 1.0)));
  warp::Layer& la = scratch_->a;
  warp::Layer& lb = scratch_->b;
  f.stretch = warp::forwardSplat(*fg, t, la);
  warp::forwardSplat(*bg, t, lb);
  long holes = 0, both = 0;
  double sq = 0;
  const int w = t.width, h = t.height;
  const std::uint8_t* ca = la.coverage.data();
  const std::uint8_t* cb = lb.coverage.data();
  const float* za = la.eyeZ.data();
  const float* zb = lb.eyeZ.data();
  auto hole = [&](int x, int y) {
    const std::size_t i = static_cast<std::size_t>(y) * w + x;
    return !ca[i] && !cb[i];
  };
  const std::size_t n = la.coverage.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (!ca[i] && !cb[i]) {
      // A one-pixel crack between covered pixels is splatting's, not a
      // disocclusion: the warp's quads close it.
      const int x = static_cast<int>(i % w), y = static_cast<int>(i / w);
      const bool crackX = x > 0 && x + 1 < w && !hole(x - 1, y) && !hole(x + 1, y);
      const bool crackY = y > 0 && y + 1 < h && !hole(x, y - 1) && !hole(x, y + 1);
      if (!crackX && !crackY) ++holes;
    }
    // Both sky (both at kSkyEyeZ), or surfaces within 5 % of each other.
    const bool same = ca[i] && cb[i] && std::abs(za[i] - zb[i]) < 0.05f * std::min(za[i], zb[i]);
    if (!same) continue;
    ++both;
    const Rgba8 qa = la.colour.pixels()[i], qb = lb.colour.pixels()[i];
    const double dr = qa.r - qb.r, dg = qa.g - qb.g, dbl = qa.b - qb.b;
    sq += (dr * dr + dg * dg + dbl * dbl) / 3.0;
  }
  f.holeFraction = static_cast<double>(holes) / static_cast<double>(n);
  f.disagreementMse = both ? sq / static_cast<double>(both) : 0.0;
  splatMs_ += sw.ms();
  memo_.emplace(key, f);
  return f;
}

Result<const KeyframeProbe::Warped*> KeyframeProbe::warped(int key, int frame) {
  const auto id = std::make_pair(key, frame);
  if (auto it = warpCache_.find(id); it != warpCache_.end()) {
    it->second->lastUse = ++warpTick_;
    return static_cast<const Warped*>(it->second.get());
  }
  auto rk = probe(key);
  if (!rk) return rk.error();
  const Camera t = probeCamera(frame);
  const std::size_t pixels = static_cast<std::size_t>(t.width) * static_cast<std::size_t>(t.height);
  // ~64 MB of layers (9 bytes a pixel); the planners sweep k0 forward, so the
  // warps of the last few k0 are what is reused.
  const std::size_t cap = std::max<std::size_t>(16, (64u << 20) / (9 * pixels));
  if (warpCache_.size() >= cap) {
    std::vector<long> uses;
    uses.reserve(warpCache_.size());
    for (const auto& [k, w] : warpCache_) uses.push_back(w->lastUse);
    const auto mid = uses.begin() + static_cast<std::ptrdiff_t>(uses.size() / 2);
    std::nth_element(uses.begin(), mid, uses.end());
    const long cut = *mid;
    for (auto it = warpCache_.begin(); it != warpCache_.end();)
      it = it->second->lastUse < cut ? warpCache_.erase(it) : std::next(it);
  }
  auto w = std::make_unique<Warped>();
  Stopwatch sw;
  warp::forwardSplat(**rk, t, w->layer);
  splatMs_ += sw.ms();
  w->lastUse = ++warpTick_;
  const Warped* raw = w.get();
  warpCache_.emplace(id, std::move(w));
  return raw;
}

Result<double> KeyframeProbe::relDistance(int k0, int k1, int frame) {
  const auto key = std::make_tuple(k0, k1, frame);
  if (auto it = distanceMemo_.find(key); it != distanceMemo_.end()) return it->second;
  auto ra = probe(k0);
  if (!ra) return ra.error();
  auto rb = probe(k1);
  if (!rb) return rb.error();
  const glm::dvec3 eye = cameraOf_(frame).eye;  // a path camera: not free, hence the memo
  const double d = relativeDistance(eye, **ra, **rb);
  distanceMemo_.emplace(key, d);
  return d;
}

Result<double> KeyframeProbe::probeError(int k0, int k1, int frame) {
  const auto key = std::make_tuple(k0, k1, frame);
  if (auto it = errorMemo_.find(key); it != errorMemo_.end()) return it->second;
  if (!error_.previousFill || frame <= k0 || frame >= k1) {
    auto e = composeAndCompare(k0, k1, frame, nullptr);
    if (!e) return e.error();
    errorMemo_.emplace(key, *e);
    return *e;
  }
  // The walk's chain: frame k0 shows keyframe k0, and each later frame takes
  // its holes from the one before. Continue the segment's chain, or start it
  // again from keyframe k0.
  if (chains_.size() > 512) chains_.clear();  // the planners sweep k0 forward
  Chain& ch = chains_[std::make_pair(k0, k1)];
  int start = ch.frame + 1;
  if (!(ch.frame > k0 && ch.frame < frame)) {
    auto rk = probe(k0);
    if (!rk) return rk.error();
    ch.image.colour = (*rk)->colour;
    ch.image.valid.resize(ch.image.colour.width(), ch.image.colour.height(), 1);
    start = k0 + 1;
  }
  for (int g = start; g <= frame; ++g) {
    auto e = composeAndCompare(k0, k1, g, &ch.image);
    if (!e) return e.error();
    ch.image = scratch_->composed;
    ch.frame = g;
    errorMemo_.emplace(std::make_tuple(k0, k1, g), *e);
  }
  return errorMemo_.at(key);
}

Result<double> KeyframeProbe::composeAndCompare(int k0, int k1, int frame,
                                                const gapfill::Frame* previous) {
  auto ra = probe(k0);
  if (!ra) return ra.error();
  auto rb = probe(k1);
  if (!rb) return rb.error();
  auto rf = probe(frame);
  if (!rf) return rf.error();
  const Probe& ref = **rf;
  const Camera t = probeCamera(frame);
  const int fgKey =
      gapfill::chooseForeground(t.eye, (*ra)->camera.eye, (*rb)->camera.eye) == 0 ? k0 : k1;
  const int bgKey = fgKey == k0 ? k1 : k0;
  auto rfg = warped(fgKey, frame);
  if (!rfg) return rfg.error();
  auto rbg = warped(bgKey, frame);  // touches fg's layer first: it survives the eviction
  if (!rbg) return rbg.error();
  Stopwatch sw;
  const int w = t.width, h = t.height;
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  // The walk's composition (overlay: the foreground where it covers, its sky
  // backdrop included, else the background); holes from `previous` when
  // given, as the walk fills them.
  gapfill::Frame& out = scratch_->composed;
  gapfill::compose((*rfg)->layer, &(*rbg)->layer, previous, gapfill::ComposeOptions{}, out);
  const Rgba8* comp = out.colour.data();
  const std::uint8_t* valid = out.valid.data();
  const int r = error_.blurRadius;
  double sum = 0;
  const int tol = error_.shiftTolerance;
  if (r == 0) {
    // Each composed pixel against the best-matching reference pixel within
    // `tol` (0: the same pixel).
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * w + x;
        if (!valid[i]) {
          sum += error_.holeMse;
          continue;
        }
        const Rgba8 c = comp[i];
        double best = std::numeric_limits<double>::infinity();
        for (int yy = std::max(0, y - tol); yy <= std::min(h - 1, y + tol); ++yy)
          for (int xx = std::max(0, x - tol); xx <= std::min(w - 1, x + tol); ++xx) {
            const Rgba8 q = ref.colour(xx, yy);
            const double er = c.r - q.r, eg = c.g - q.g, eb = c.b - q.b;
            best = std::min(best, (er * er + eg * eg + eb * eb) / 3.0);
          }
        sum += best;
      }
  } else {
    // Box means of the composed and the reference probe over the same
    // non-hole pixels of each window, from summed-area tables (7 channels:
    // composed RGB, reference RGB, count).
    const std::size_t sw1 = static_cast<std::size_t>(w) + 1;
    std::vector<std::int32_t>& sat = scratch_->sat;
    sat.assign(7 * sw1 * (static_cast<std::size_t>(h) + 1), 0);
    auto at = [&](int ch, int x, int y) -> std::int32_t& {
      return sat[(static_cast<std::size_t>(ch) * (static_cast<std::size_t>(h) + 1) +
                  static_cast<std::size_t>(y)) * sw1 + static_cast<std::size_t>(x)];
    };
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * w + x;
        std::int32_t v[7] = {0, 0, 0, 0, 0, 0, 0};
        if (valid[i]) {
          const Rgba8 c = comp[i], q = ref.colour(x, y);
          v[0] = c.r, v[1] = c.g, v[2] = c.b, v[3] = q.r, v[4] = q.g, v[5] = q.b, v[6] = 1;
        }
        for (int ch = 0; ch < 7; ++ch)
          at(ch, x + 1, y + 1) = v[ch] + at(ch, x, y + 1) + at(ch, x + 1, y) - at(ch, x, y);
      }
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        if (!valid[static_cast<std::size_t>(y) * w + x]) {
          sum += error_.holeMse;
          continue;
        }
        const int x0 = std::max(0, x - r), x1 = std::min(w, x + r + 1);
        const int y0 = std::max(0, y - r), y1 = std::min(h, y + r + 1);
        double box[7];
        for (int ch = 0; ch < 7; ++ch)
          box[ch] = at(ch, x1, y1) - at(ch, x0, y1) - at(ch, x1, y0) + at(ch, x0, y0);
        const double m = box[6];  // >= 1: the pixel itself
        const double er = (box[0] - box[3]) / m, eg = (box[1] - box[4]) / m,
                     eb = (box[2] - box[5]) / m;
        sum += (er * er + eg * eg + eb * eb) / 3.0;
      }
  }
  const double mse = sum / static_cast<double>(n);
  splatMs_ += sw.ms();
  return mse;
}

Result<FrameFeatures> predictorFeatures(KeyframeProbe& probe, Predictor p, int k0, int k1,
                                        int frame) {
  if (!isProbePredictor(p)) return probe.features(k0, k1, frame);
  auto e = probe.probeError(k0, k1, frame);
  if (!e) return e.error();
  if (p == Predictor::ProbePsnrFeatures) {
    auto all = probe.features(k0, k1, frame);
    if (!all) return all.error();
    FrameFeatures ff = *all;
    ff.probeMse = *e;
    return ff;
  }
  FrameFeatures ff;
  ff.probeMse = *e;
  if (p == Predictor::ProbePsnrDistance) {
    auto d = probe.relDistance(k0, k1, frame);
    if (!d) return d.error();
    ff.relDistance = *d;
  }
  return ff;
}

}  // namespace hw::session
