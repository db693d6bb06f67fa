#include "gapfill/compose.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

#include "core/check.h"

namespace hw::gapfill {
namespace {

static_assert(sizeof(Rgba8) == 4, "Rgba8 is selected as one 32-bit word");

template <class T>
void ensureSize(Image<T>& im, int width, int height) {
  if (im.width() != width || im.height() != height) im.resize(width, height);
}

template <class A, class B>
void checkSameSize(const Image<A>& a, const Image<B>& b) {
  HW_CHECK_EQ(a.width(), b.width());
  HW_CHECK_EQ(a.height(), b.height());
}

// One pixel as a 32-bit word (memcpy: no aliasing questions, one load/store).
inline std::uint32_t load32(const Rgba8* p) {
  std::uint32_t v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

struct Counts {
  int fg = 0, bg = 0, prev = 0, holes = 0;
};

struct Inputs {
  const Rgba8* fgColour;
  const std::uint8_t* fgCoverage;
  const float* fgZ;
  const Rgba8* bgColour;
  const std::uint8_t* bgCoverage;
  const float* bgZ;
  const Rgba8* prevColour;
  const std::uint8_t* prevValid;
};

// One branch-free pass over all pixels; the variants are compile-time so the
// loop carries no null tests and vectorises.
template <bool kHasBg, bool kHasPrev, bool kMerge>
Counts composePixels(const Inputs& in, float keepFgFactor, std::size_t n,
                     Rgba8* __restrict outColour, std::uint8_t* __restrict outHoles,
                     std::uint8_t* __restrict outValid) {
  const std::uint32_t unfilled = std::bit_cast<std::uint32_t>(kUnfilledColour);
  int nf = 0, nb = 0, np = 0, nh = 0;
  // Non-short-circuit (&, |) on 0/1 values: every load is unconditional, so
  // the loop has no control flow and GCC vectorises it.
  for (std::size_t i = 0; i < n; ++i) {
    const int cf = in.fgCoverage[i] != 0;
    const int cb = kHasBg ? int(in.bgCoverage[i] != 0) : 0;
    int bgWins = 1 - cf;
    if constexpr (kMerge) bgWins |= int(in.bgZ[i] < keepFgFactor * in.fgZ[i]);
    const int takeB = cb & bgWins;
    const int takeF = cf & (1 - takeB);
    const int hole = (1 - cf) & (1 - cb);
    const int takeP = kHasPrev ? hole & int(in.prevValid[i] != 0) : 0;

    // Exactly one of the four masks is all-ones.
    const std::uint32_t mF = 0u - static_cast<std::uint32_t>(takeF);
    const std::uint32_t mB = 0u - static_cast<std::uint32_t>(takeB);
    const std::uint32_t mP = 0u - static_cast<std::uint32_t>(takeP);
    const std::uint32_t mU = ~(mF | mB | mP);
    std::uint32_t c = (load32(in.fgColour + i) & mF) | (unfilled & mU);
    if constexpr (kHasBg) c |= load32(in.bgColour + i) & mB;
    if constexpr (kHasPrev) c |= load32(in.prevColour + i) & mP;
    std::memcpy(static_cast<void*>(outColour + i), &c, sizeof c);
    outHoles[i] = static_cast<std::uint8_t>(hole);
    outValid[i] = static_cast<std::uint8_t>((1 - hole) | takeP);
    nf += takeF;
    nb += takeB;
    np += takeP;
    nh += hole;
  }
  return Counts{nf, nb, np, nh};
}

template <bool kHasBg, bool kHasPrev>
Counts dispatchMerge(bool merge, const Inputs& in, float keepFgFactor, std::size_t n, Frame& out) {
  if (merge)
    return composePixels<kHasBg, kHasPrev, true>(in, keepFgFactor, n, out.colour.data(),
                                                 out.holesBefore.data(), out.valid.data());
  return composePixels<kHasBg, kHasPrev, false>(in, keepFgFactor, n, out.colour.data(),
                                                out.holesBefore.data(), out.valid.data());
}

// The Blend weight (ComposeMode::Blend). A view's angular penalty is the
// chord between the unit rays (2 sin(θ/2) ≈ θ at the angles that matter) and
// its resolution penalty max(0, dKey/dFrame − 1).
inline float backgroundWeight(const glm::vec3& p, const glm::vec3& offF, const glm::vec3& offB,
                              float softness) {
  constexpr float kTiny = 1e-20f;
  const glm::vec3 aF = p - offF, aB = p - offB;
  const float dp = std::sqrt(glm::dot(p, p)) + kTiny;
  const float dF = std::sqrt(glm::dot(aF, aF)) + kTiny;
  const float dB = std::sqrt(glm::dot(aB, aB)) + kTiny;
  const glm::vec3 u = p / dp;
  const float penaltyF = glm::length(u - aF / dF) + std::max(0.0f, dF / dp - 1.0f);
  const float penaltyB = glm::length(u - aB / dB) + std::max(0.0f, dB / dp - 1.0f);
  // exp(−pB/s) / (exp(−pF/s) + exp(−pB/s)), clamped so exp cannot overflow.
  const float t = std::clamp((penaltyB - penaltyF) / softness, -80.0f, 80.0f);
  return 1.0f / (1.0f + std::exp(t));
}

inline std::uint8_t mixChannel(std::uint8_t a, std::uint8_t b, float w) {
  const float v = static_cast<float>(a) + (static_cast<float>(b) - static_cast<float>(a)) * w;
  return static_cast<std::uint8_t>(std::clamp(v + 0.5f, 0.0f, 255.0f));
}

// ComposeMode::Blend with a background. Branchy (the blend is per pixel
// geometry), but allocation-free.
Counts composeBlend(const Inputs& in, const ComposeOptions& opt, const BlendViews& views,
                    Frame& out, int* blended) {
  const Camera& cam = views.camera;
  const int w = cam.width, h = cam.height;
  const glm::vec3 U(cam.right), V(cam.up), W(cam.forward);
  const glm::vec3 offF(views.foregroundEye - cam.eye), offB(views.backgroundEye - cam.eye);
  const float fx = static_cast<float>(cam.fx()), fy = static_cast<float>(cam.fy());
  const float cx = static_cast<float>(cam.cx()), cy = static_cast<float>(cam.cy());
  const float tol = opt.depthTolerance, soft = opt.blendSoftness;
  constexpr float kSkyHalf = 0.5f * warp::kSkyEyeZ;
  int nf = 0, nb = 0, np = 0, nh = 0, nm = 0;
  for (int y = 0; y < h; ++y) {
    const glm::vec3 rowDir = W + ((cy - (static_cast<float>(y) + 0.5f)) / fy) * V;
    for (int x = 0; x < w; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(w) +
                            static_cast<std::size_t>(x);
      const bool cf = in.fgCoverage[i] != 0, cb = in.bgCoverage[i] != 0;
      Rgba8 c = kUnfilledColour;
      std::uint8_t hole = 0, valid = 1;
      if (cf && cb) {
        const float zf = in.fgZ[i], zb = in.bgZ[i];
        if (std::abs(zf - zb) <= tol * std::min(zf, zb)) {
          float wb = 0.5f;
          if (zf < kSkyHalf) {
            const glm::vec3 dir = rowDir + ((static_cast<float>(x) + 0.5f - cx) / fx) * U;
            wb = backgroundWeight(zf * dir, offF, offB, soft);
          }
          const Rgba8 a = in.fgColour[i], b = in.bgColour[i];
          c = Rgba8{mixChannel(a.r, b.r, wb), mixChannel(a.g, b.g, wb), mixChannel(a.b, b.b, wb),
                    a.a};
          ++nm;
          if (wb > 0.5f) ++nb; else ++nf;
        } else if (zb < zf) {
          c = in.bgColour[i];
          ++nb;
        } else {
          c = in.fgColour[i];
          ++nf;
        }
      } else if (cf) {
        c = in.fgColour[i];
        ++nf;
      } else if (cb) {
        c = in.bgColour[i];
        ++nb;
      } else {
        hole = 1;
        ++nh;
        if (in.prevColour && in.prevValid[i]) {
          c = in.prevColour[i];
          ++np;
        } else {
          valid = 0;
        }
      }
      out.colour.data()[i] = c;
      out.holesBefore.data()[i] = hole;
      out.valid.data()[i] = valid;
    }
  }
  *blended = nm;
  return Counts{nf, nb, np, nh};
}

}  // namespace

float blendBackgroundWeight(const glm::vec3& ray, const glm::vec3& foregroundEyeOffset,
                            const glm::vec3& backgroundEyeOffset, float softness) {
  HW_CHECK(softness > 0.0f);
  return backgroundWeight(ray, foregroundEyeOffset, backgroundEyeOffset, softness);
}

const char* composeModeName(ComposeMode m) {
  switch (m) {
    case ComposeMode::Overlay:
      return "overlay";
    case ComposeMode::DepthMerge:
      return "depth-merge";
    case ComposeMode::Blend:
      return "blend";
  }
  return "?";
}

bool parseComposeMode(const char* s, ComposeMode* out) {
  HW_CHECK(out != nullptr);
  if (s == nullptr) return false;
  for (ComposeMode m : {ComposeMode::Overlay, ComposeMode::DepthMerge, ComposeMode::Blend}) {
    if (std::strcmp(s, composeModeName(m)) == 0) {
      *out = m;
      return true;
    }
  }
  return false;
}

void compose(const warp::Layer& foreground, const warp::Layer* background, const Frame* previous,
             const ComposeOptions& options, const BlendViews* views, Frame& out) {
  HW_CHECK(previous != &out);
  const bool blend = options.mode == ComposeMode::Blend && background != nullptr;
  const bool merge =
      (options.mode == ComposeMode::DepthMerge && background != nullptr) || blend;
  const int w = foreground.colour.width();
  const int h = foreground.colour.height();
  checkSameSize(foreground.colour, foreground.coverage);
  if (background) {
    checkSameSize(foreground.colour, background->colour);
    checkSameSize(foreground.colour, background->coverage);
  }
  if (merge) {
    HW_CHECK(options.depthTolerance >= 0.0f && options.depthTolerance < 1.0f);
    checkSameSize(foreground.colour, foreground.eyeZ);
    checkSameSize(foreground.colour, background->eyeZ);
  }
  if (blend) {
    HW_CHECK(views != nullptr);
    HW_CHECK(options.blendSoftness > 0.0f);
    HW_CHECK_EQ(views->camera.width, w);
    HW_CHECK_EQ(views->camera.height, h);
  }
  if (previous) {
    checkSameSize(foreground.colour, previous->colour);
    checkSameSize(foreground.colour, previous->valid);
  }

  ensureSize(out.colour, w, h);
  ensureSize(out.holesBefore, w, h);
  ensureSize(out.valid, w, h);

  const Inputs in{foreground.colour.data(),
                  foreground.coverage.data(),
                  merge ? foreground.eyeZ.data() : nullptr,
                  background ? background->colour.data() : nullptr,
                  background ? background->coverage.data() : nullptr,
                  merge ? background->eyeZ.data() : nullptr,
                  previous ? previous->colour.data() : nullptr,
                  previous ? previous->valid.data() : nullptr};
  const float keepFgFactor = 1.0f - options.depthTolerance;
  const std::size_t n = out.colour.size();

  Counts c;
  out.blended = 0;
  if (blend) {
    c = composeBlend(in, options, *views, out, &out.blended);
  } else if (background) {
    c = previous ? dispatchMerge<true, true>(merge, in, keepFgFactor, n, out)
                 : dispatchMerge<true, false>(merge, in, keepFgFactor, n, out);
  } else {
    c = previous ? dispatchMerge<false, true>(false, in, keepFgFactor, n, out)
                 : dispatchMerge<false, false>(false, in, keepFgFactor, n, out);
  }

  out.fromForeground = c.fg;
  out.fromBackground = c.bg;
  out.fromPrevious = c.prev;
  out.unfilled = c.holes - c.prev;
  const double total = static_cast<double>(n);
  out.holeFractionBefore = n ? static_cast<double>(c.holes) / total : 0.0;
  out.holeFractionAfter = n ? static_cast<double>(out.unfilled) / total : 0.0;
}

int chooseForeground(const glm::dvec3& eye, const glm::dvec3& eyeA, const glm::dvec3& eyeB) {
  const double dA = glm::length(eye - eyeA);
  const double dB = glm::length(eye - eyeB);
  if (std::abs(dA - dB) <= kForegroundTieRelTol * (dA + dB)) return 0;
  return dA < dB ? 0 : 1;
}

}  // namespace hw::gapfill
