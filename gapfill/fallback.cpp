#include "gapfill/fallback.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/check.h"

namespace hw::gapfill {
namespace {

template <class T>
void ensureSize(Image<T>& im, int width, int height) {
  if (im.width() != width || im.height() != height) im.resize(width, height);
}

template <class A, class B>
void checkSameSize(const Image<A>& a, const Image<B>& b) {
  HW_CHECK_EQ(a.width(), b.width());
  HW_CHECK_EQ(a.height(), b.height());
}

}  // namespace

const char* fallbackName(Fallback f) {
  switch (f) {
    case Fallback::Copy:
      return "copy";
    case Fallback::Reproject:
      return "reproject";
  }
  return "?";
}

bool parseFallback(const char* s, Fallback* out) {
  HW_CHECK(out != nullptr);
  if (s == nullptr) return false;
  for (Fallback f : {Fallback::Copy, Fallback::Reproject}) {
    if (std::strcmp(s, fallbackName(f)) == 0) {
      *out = f;
      return true;
    }
  }
  return false;
}

void reprojectFrame(const Frame& previous, const Camera& target, Frame& out,
                    const Image<std::uint8_t>* wanted) {
  HW_CHECK(&previous != &out);
  checkSameSize(previous.colour, previous.valid);
  checkSameSize(previous.colour, previous.eyeZ);
  const int w = target.width, h = target.height;
  if (wanted) {
    HW_CHECK_EQ(wanted->width(), w);
    HW_CHECK_EQ(wanted->height(), h);
  }
  ensureSize(out.colour, w, h);
  ensureSize(out.valid, w, h);
  ensureSize(out.eyeZ, w, h);
  out.camera = target;
  out.valid.fill(0);

  // Previous camera coordinates (x, y, 1)·z → target camera coordinates:
  // c = z·(x·R0 + y·R1 + R2) + t, R_k the previous axes in the target's basis.
  // Float: 6e-8 relative, far inside a pixel at these resolutions.
  const Camera& src = previous.camera;
  auto inTarget = [&](const glm::dvec3& v) {
    return glm::vec3(glm::dot(v, target.right), glm::dot(v, target.up),
                     glm::dot(v, target.forward));
  };
  const glm::vec3 r0 = inTarget(src.right), r1 = inTarget(src.up), r2 = inTarget(src.forward);
  const glm::vec3 t = inTarget(src.eye - target.eye);
  const float sfx = static_cast<float>(src.fx()), sfy = static_cast<float>(src.fy());
  const float scx = static_cast<float>(src.cx()), scy = static_cast<float>(src.cy());
  const float tfx = static_cast<float>(target.fx()), tfy = static_cast<float>(target.fy());
  const float tcx = static_cast<float>(target.cx()), tcy = static_cast<float>(target.cy());
  const float fw = static_cast<float>(w), fh = static_cast<float>(h);
  constexpr float kSkyHalf = 0.5f * warp::kSkyEyeZ;
  const int sw = previous.colour.width(), sh = previous.colour.height();
  const Rgba8* __restrict inColour = previous.colour.data();
  const std::uint8_t* __restrict inValid = previous.valid.data();
  const float* __restrict inZ = previous.eyeZ.data();
  Rgba8* __restrict outColour = out.colour.data();
  std::uint8_t* __restrict outValid = out.valid.data();
  float* __restrict outZ = out.eyeZ.data();
  for (int y = 0; y < sh; ++y) {
    const glm::vec3 rowDir = ((scy - (static_cast<float>(y) + 0.5f)) / sfy) * r1 + r2;
    const std::size_t row = static_cast<std::size_t>(y) * static_cast<std::size_t>(sw);
    for (int x = 0; x < sw; ++x) {
      const std::size_t i = row + static_cast<std::size_t>(x);
      const float z = inZ[i];
      if (!inValid[i] || !(z > 0.0f)) continue;
      const glm::vec3 dir = ((static_cast<float>(x) + 0.5f - scx) / sfx) * r0 + rowDir;
      const bool sky = z >= kSkyHalf;
      const glm::vec3 c = sky ? dir : z * dir + t;
      if (!(c.z > 1e-6f)) continue;  // behind the target eye
      const float inv = 1.0f / c.z;
      const float u = tcx + tfx * c.x * inv, v = tcy - tfy * c.y * inv;
      if (!(u >= 0.0f && u < fw && v >= 0.0f && v < fh)) continue;
      const std::size_t o = static_cast<std::size_t>(static_cast<int>(v)) * static_cast<std::size_t>(w) +
                            static_cast<std::size_t>(static_cast<int>(u));
      const float cz = sky ? warp::kSkyEyeZ : c.z;
      if (outValid[o] && outZ[o] <= cz) continue;
      outValid[o] = 1;
      outZ[o] = cz;
      outColour[o] = inColour[i];
    }
  }

  // Cracks: where neighbouring points spread apart (the camera moved closer
  // or turned), an empty pixel inside written ones takes the nearest
  // neighbour. Pixels filled here are marked 2 so they feed no other.
  const std::uint8_t* want = wanted ? wanted->data() : nullptr;
  for (int y = 1; y + 1 < h; ++y) {
    for (int x = 1; x + 1 < w; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * static_cast<std::size_t>(w) +
                            static_cast<std::size_t>(x);
      if (outValid[i] || (want && want[i])) continue;
      int count = 0;
      std::size_t best = i;
      float bestZ = 0.0f;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const std::size_t j = static_cast<std::size_t>(y + dy) * static_cast<std::size_t>(w) +
                                static_cast<std::size_t>(x + dx);
          if (outValid[j] != 1) continue;
          ++count;
          const float zj = outZ[j];
          if (best == i || zj < bestZ) {
            best = j;
            bestZ = zj;
          }
        }
      if (count >= 4) {
        outValid[i] = 2;
        outZ[i] = bestZ;
        outColour[i] = outColour[best];
      }
    }
  }
}

FillStats fillHoles(const Frame& reprojected, const Frame* samePixel, Frame& out) {
  checkSameSize(out.colour, out.valid);
  checkSameSize(out.colour, reprojected.colour);
  checkSameSize(out.colour, reprojected.valid);
  checkSameSize(out.colour, reprojected.eyeZ);
  if (samePixel) {
    checkSameSize(out.colour, samePixel->colour);
    checkSameSize(out.colour, samePixel->valid);
  }
  const bool haveZ =
      out.eyeZ.width() == out.colour.width() && out.eyeZ.height() == out.colour.height();
  FillStats fs;
  const std::size_t n = out.colour.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (out.valid.data()[i]) continue;
    if (reprojected.valid.data()[i]) {
      out.colour.data()[i] = reprojected.colour.data()[i];
      if (haveZ) out.eyeZ.data()[i] = reprojected.eyeZ.data()[i];
      ++fs.reprojected;
    } else if (samePixel && samePixel->valid.data()[i]) {
      out.colour.data()[i] = samePixel->colour.data()[i];
      if (haveZ) out.eyeZ.data()[i] = 0.0f;
      ++fs.copied;
    } else {
      continue;
    }
    out.valid.data()[i] = 1;
  }
  const int filled = fs.reprojected + fs.copied;
  out.fromPrevious += filled;
  out.unfilled -= filled;
  out.holeFractionAfter = n ? static_cast<double>(out.unfilled) / static_cast<double>(n) : 0.0;
  return fs;
}

void layerDepth(const warp::Layer& fg, const warp::Layer* bg, bool nearer, Frame& out) {
  checkSameSize(fg.colour, fg.coverage);
  checkSameSize(fg.colour, fg.eyeZ);
  if (bg) {
    checkSameSize(fg.colour, bg->coverage);
    checkSameSize(fg.colour, bg->eyeZ);
  }
  ensureSize(out.eyeZ, fg.colour.width(), fg.colour.height());
  const std::size_t n = out.eyeZ.size();
  float* z = out.eyeZ.data();
  for (std::size_t i = 0; i < n; ++i) {
    const bool cf = fg.coverage.data()[i] != 0;
    const bool cb = bg && bg->coverage.data()[i] != 0;
    const float zf = fg.eyeZ.data()[i];
    const float zb = cb ? bg->eyeZ.data()[i] : 0.0f;
    z[i] = cf && cb ? (nearer ? std::min(zf, zb) : zf) : cf ? zf : cb ? zb : 0.0f;
  }
}

}  // namespace hw::gapfill
