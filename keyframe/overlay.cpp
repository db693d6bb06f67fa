#include "keyframe/overlay.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/check.h"
#include "keyframe/delta_buffer.h"

namespace hw::keyframe {

namespace {

std::uint8_t lerp8(std::uint8_t a, std::uint8_t b, float t) {
  return static_cast<std::uint8_t>(std::lround(a + (static_cast<float>(b) - a) * t));
}

Rgba8 blend(Rgba8 a, Rgba8 b, float t) {
  return Rgba8{lerp8(a.r, b.r, t), lerp8(a.g, b.g, t), lerp8(a.b, b.b, t), a.a};
}

}  // namespace

Image<Rgba8> drawQuadOverlay(const Image<Rgba8>& colour, const QuadMesh& mesh,
                             const OverlayOptions& o) {
  const int w = colour.width(), h = colour.height();
  HW_CHECK_EQ(mesh.width, w);
  HW_CHECK_EQ(mesh.height, h);
  // Leaf index per pixel (−1: in no quad).
  Image<int> owner(w, h, -1);
  for (std::size_t k = 0; k < mesh.quads.size(); ++k) {
    const PixelRect& r = mesh.quads[k].rect;
    HW_CHECK(r.x0 >= 0 && r.y0 >= 0 && r.x1 <= w && r.y1 <= h && r.x0 < r.x1 && r.y0 < r.y1);
    for (int y = r.y0; y < r.y1; ++y) {
      for (int x = r.x0; x < r.x1; ++x) owner(x, y) = static_cast<int>(k);
    }
  }
  Image<Rgba8> out = colour;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      if (owner(x, y) < 0) {
        Rgba8& p = out(x, y);
        p.r = static_cast<std::uint8_t>(p.r * o.emptyDim);
        p.g = static_cast<std::uint8_t>(p.g * o.emptyDim);
        p.b = static_cast<std::uint8_t>(p.b * o.emptyDim);
      }
    }
  }
  for (const Quad& q : mesh.quads) {
    const PixelRect& r = q.rect;
    if (r.width() == 1 && r.height() == 1) {
      out(r.x0, r.y0) = blend(out(r.x0, r.y0), o.onePixelTint, o.onePixelTintAmount);
      continue;
    }
    for (int x = r.x0; x < r.x1; ++x) {
      out(x, r.y0) = o.outline;
      if (r.y1 == h || owner(x, r.y1) < 0) out(x, r.y1 - 1) = o.outline;
    }
    for (int y = r.y0; y < r.y1; ++y) {
      out(r.x0, y) = o.outline;
      if (r.x1 == w || owner(r.x1, y) < 0) out(r.x1 - 1, y) = o.outline;
    }
  }
  return out;
}

Image<Rgba8> deltaToImage(ImageView<const float> delta, const DeltaImageOptions& o) {
  Image<Rgba8> out(delta.width, delta.height);
  const float scale = 255.0f / std::log2(1.0f + std::max(o.maxDelta, 1.0f));
  for (int y = 0; y < delta.height; ++y) {
    for (int x = 0; x < delta.width; ++x) {
      const float d = delta(x, y);
      Rgba8 c;
      if (d < 0.0f) {
        c = o.empty;
      } else if (!std::isfinite(d)) {
        c = o.discontinuity;
      } else {
        const float g = std::min(255.0f, std::log2(1.0f + d) * scale);
        const auto v = static_cast<std::uint8_t>(std::lround(g));
        c = Rgba8{v, v, v, 255};
        if (o.tau > 0.0f && d > o.tau) c = blend(c, Rgba8{255, 140, 0, 255}, 0.5f);
      }
      out(x, y) = c;
    }
  }
  return out;
}

}  // namespace hw::keyframe
