#include "session/hole_pass.h"

#include <cstring>
#include <limits>

#include "core/timer.h"
#include "gapfill/age.h"
#include "session/walk.h"

namespace hw::session {

void applyRendered(const keyframe::PixelRect& r, const Image<Rgba8>& colour, gapfill::Frame& frame,
                   InBetweenStep& step) {
  gapfill::applyRefresh(r, colour, frame);
  const auto w = static_cast<std::size_t>(frame.colour.width());
  for (int y = r.y0; y < r.y1; ++y)
    for (int x = r.x0; x < r.x1; ++x)
      step.clearLargeQuad(static_cast<std::size_t>(y) * w + static_cast<std::size_t>(x));
}

HoleTiling holeTiling(const WalkOptions& options) {
  return HoleTiling{options.holeTilePx, options.holeRectsMax};
}

Status HolePass::run(keyframe::GeometryRenderer& renderer, const Camera& cam, gapfill::Frame& frame,
                     InBetweenStep& step, const HoleTiling& tiling,
                     const std::function<int(int)>& maxRects,
                     HolePassResult* out, gapfill::GpuFrames* gpu) {
  *out = HolePassResult{};
  gapfill::holeRects(frame.holesBefore, tiling.tilePx, WalkOptions::holeTileMinPixels(tiling.tilePx),
                     tiling.maxFound > 0 ? tiling.maxFound : std::numeric_limits<int>::max(),
                     rects_, scores_);
  out->wanted = static_cast<int>(rects_.size());
  if (maxRects && out->wanted > 0) {
    const int keep = maxRects(out->wanted);
    if (keep >= 0 && keep < out->wanted) rects_.resize(static_cast<std::size_t>(keep));
  }
  const std::size_t n = rects_.size();
  px_.resize(n);
  if (colours_.size() < n) colours_.resize(n);
  for (std::size_t k = 0; k < n; ++k) px_[k] = rects_[k].rect;
  if (n > 0) {
    Stopwatch sd;
    keyframe::RenderStats rs;
    if (gpu) {
      HW_TRY(renderer.renderColourRectsTo(cam, px_.data(), static_cast<int>(n), gpu->copyTarget(),
                                          &rs));
      gpu->markValid(px_.data(), static_cast<int>(n));
    } else {
      HW_TRY(renderer.renderColourRects(cam, px_.data(), static_cast<int>(n), colours_.data(),
                                        &rs));
    }
    out->drawMs = sd.ms();
    out->triangles = static_cast<long long>(rs.trianglesDrawn);
  }
  for (std::size_t k = 0; k < n; ++k) {
    if (gpu) {
      const PixelRect& r = px_[k];
      for (int y = r.y0; y < r.y1; ++y)
        std::memset(&frame.valid(r.x0, y), 1, static_cast<std::size_t>(r.width()));
    } else {
      applyRendered(px_[k], colours_[k], frame, step);
    }
    out->holes += rects_[k].holes;
    out->area += px_[k].area();
  }
  out->drawn = static_cast<int>(n);
  return {};
}

}  // namespace hw::session
