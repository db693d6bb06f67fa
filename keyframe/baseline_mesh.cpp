#include "keyframe/baseline_mesh.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

#include "core/check.h"

namespace hw::keyframe {

namespace {

// The covered pixels of a keyframe as a summed-area table (full/empty tiles in
// O(1)) and as maximal horizontal runs per row (mixed tiles in O(runs)).
// "Covered" is LodBuilder's valid: covered != 0 and finite z'.
struct Coverage {
  int w = 0, h = 0;
  std::vector<std::int64_t> sat;    // (w+1)×(h+1) prefix counts of covered pixels
  std::vector<int> runX0, runX1;    // runs [runX0, runX1), row-major, sorted in a row
  std::vector<std::size_t> rowRun;  // runs of row y: [rowRun[y], rowRun[y+1])

  std::int64_t count(int x0, int y0, int x1, int y1) const {
    const std::size_t s = static_cast<std::size_t>(w) + 1;
    return sat[y1 * s + x1] - sat[y1 * s + x0] - sat[y0 * s + x1] + sat[y0 * s + x0];
  }
};

bool consistentImages(const Keyframe& kf) {
  return kf.zPrime.width() > 0 && kf.zPrime.height() > 0 &&
         kf.covered.width() == kf.zPrime.width() && kf.covered.height() == kf.zPrime.height();
}

Coverage makeCoverage(const Keyframe& kf) {
  HW_CHECK(consistentImages(kf));
  Coverage c;
  c.w = kf.zPrime.width();
  c.h = kf.zPrime.height();
  const std::size_t s = static_cast<std::size_t>(c.w) + 1;
  c.sat.assign(s * (static_cast<std::size_t>(c.h) + 1), 0);
  c.rowRun.resize(static_cast<std::size_t>(c.h) + 1);
  for (int y = 0; y < c.h; ++y) {
    c.rowRun[y] = c.runX0.size();
    const double* z = kf.zPrime.view().row(y);
    const std::uint8_t* cov = kf.covered.view().row(y);
    std::int64_t* prev = c.sat.data() + y * s;
    std::int64_t* cur = prev + s;
    std::int64_t rowCount = 0;
    bool inRun = false;
    for (int x = 0; x < c.w; ++x) {
      const bool v = cov[x] != 0 && std::isfinite(z[x]);
      if (v && !inRun) c.runX0.push_back(x);
      if (!v && inRun) c.runX1.push_back(x);
      inRun = v;
      rowCount += v;
      cur[x + 1] = prev[x + 1] + rowCount;
    }
    if (inRun) c.runX1.push_back(c.w);
  }
  c.rowRun[c.h] = c.runX0.size();
  return c;
}

struct Scratch {
  std::vector<PixelRect> open, next;
};

// Calls emit(PixelRect) once per quad of the uniform mesh with tiles of s×s.
template <class Emit>
void forEachTileRect(const Coverage& c, int s, Scratch* scratch, Emit&& emit) {
  HW_CHECK_GE(s, 1);
  std::vector<PixelRect>& open = scratch->open;
  std::vector<PixelRect>& next = scratch->next;
  for (int ty0 = 0; ty0 < c.h; ty0 += std::min(s, c.h - ty0)) {
    const int ty1 = ty0 + std::min(s, c.h - ty0);
    for (int tx0 = 0; tx0 < c.w; tx0 += std::min(s, c.w - tx0)) {
      const int tx1 = tx0 + std::min(s, c.w - tx0);
      const std::int64_t n = c.count(tx0, ty0, tx1, ty1);
      if (n == 0) continue;  // empty-tile removal
      if (n == static_cast<std::int64_t>(tx1 - tx0) * (ty1 - ty0)) {
        emit(PixelRect{tx0, ty0, tx1, ty1});
        continue;
      }
      // Mixed tile: runs clipped to [tx0, tx1), continued downwards while the
      // next row has a run with exactly the same x range.
      open.clear();
      for (int y = ty0; y < ty1; ++y) {
        next.clear();
        const int* x0s = c.runX0.data();
        const int* x1s = c.runX1.data();
        const std::size_t rb = c.rowRun[y], re = c.rowRun[y + 1];
        // First run of the row ending after tx0 (ends are sorted in a row).
        std::size_t k = static_cast<std::size_t>(std::upper_bound(x1s + rb, x1s + re, tx0) - x1s);
        std::size_t j = 0;
        for (; k < re && x0s[k] < tx1; ++k) {
          const int p = std::max(x0s[k], tx0), q = std::min(x1s[k], tx1);
          bool continued = false;
          for (; j < open.size() && open[j].x0 <= p; ++j) {
            if (open[j].x0 == p && open[j].x1 == q) {
              next.push_back(PixelRect{p, open[j].y0, q, y + 1});
              continued = true;
              ++j;
              break;
            }
            emit(open[j]);
          }
          if (!continued) next.push_back(PixelRect{p, y, q, y + 1});
        }
        for (; j < open.size(); ++j) emit(open[j]);
        std::swap(open, next);
      }
      for (const PixelRect& r : open) emit(r);
    }
  }
}

long long countTileRects(const Coverage& c, int s, Scratch* scratch) {
  long long n = 0;
  forEachTileRect(c, s, scratch, [&n](const PixelRect&) { ++n; });
  return n;
}

Result<QuadMesh> buildMesh(const Keyframe& kf, const std::vector<PixelRect>& rects,
                           LodBuilder* builder, const LodOptions& options) {
  LodBuilder local;
  QuadMesh mesh;
  HW_TRY((builder != nullptr ? builder : &local)->buildFromRects(kf, rects, options, &mesh));
  return mesh;
}

}  // namespace

Result<QuadMesh> buildUniformTiles(const Keyframe& kf, int tileSize, LodBuilder* builder,
                                   const LodOptions& options) {
  if (tileSize < 1) {
    return makeError("uniform tiles: tile size must be >= 1 pixel, got " +
                     std::to_string(tileSize));
  }
  std::vector<PixelRect> rects;
  // Inconsistent images: no rectangles, and the builder reports the error.
  if (consistentImages(kf)) {
    const Coverage c = makeCoverage(kf);
    Scratch scratch;
    forEachTileRect(c, tileSize, &scratch, [&rects](const PixelRect& r) { rects.push_back(r); });
  }
  return buildMesh(kf, rects, builder, options);
}

Result<QuadMesh> buildPerPixel(const Keyframe& kf, LodBuilder* builder, const LodOptions& options) {
  std::vector<PixelRect> rects;
  if (consistentImages(kf)) {
    for (int y = 0; y < kf.zPrime.height(); ++y) {
      const double* z = kf.zPrime.view().row(y);
      const std::uint8_t* cov = kf.covered.view().row(y);
      for (int x = 0; x < kf.zPrime.width(); ++x) {
        if (cov[x] != 0 && std::isfinite(z[x])) rects.push_back(PixelRect{x, y, x + 1, y + 1});
      }
    }
  }
  return buildMesh(kf, rects, builder, options);
}

long long uniformTileQuadCount(const Keyframe& kf, int tileSize) {
  HW_CHECK_GE(tileSize, 1);
  const Coverage c = makeCoverage(kf);
  Scratch scratch;
  return countTileRects(c, tileSize, &scratch);
}

int tileSizeForQuadCount(const Keyframe& kf, long long targetQuads) {
  const Coverage c = makeCoverage(kf);
  Scratch scratch;
  const int maxSize = std::max(c.w, c.h);
  // Counts are >= 0, so a negative target picks what 0 picks (and cannot overflow).
  const long long target = std::max(targetQuads, 0LL);
  int best = 1;
  long long bestDiff = std::numeric_limits<long long>::max();
  for (int s = 1; s <= maxSize; ++s) {
    const long long n = countTileRects(c, s, &scratch);
    const long long diff = n > target ? n - target : target - n;
    if (diff < bestDiff) {
      bestDiff = diff;
      best = s;
      if (diff == 0) break;
    }
  }
  return best;
}

}  // namespace hw::keyframe
