#include "gapfill/hole_rects.h"

#include <algorithm>

#include "core/check.h"

namespace hw::gapfill {

void holeRects(const Image<std::uint8_t>& holes, int tileSize, int minHolesPerTile, int maxRects,
               std::vector<HoleRect>& out, std::vector<std::uint32_t>& scratch) {
  HW_CHECK(tileSize >= 1 && minHolesPerTile >= 1 && maxRects >= 0);
  out.clear();
  const int w = holes.width(), h = holes.height();
  const int cols = (w + tileSize - 1) / tileSize, rows = (h + tileSize - 1) / tileSize;
  scratch.assign(static_cast<std::size_t>(cols) * static_cast<std::size_t>(rows), 0u);
  for (int y = 0; y < h; ++y) {
    const std::uint8_t* row = &holes(0, y);
    std::uint32_t* tileRow = scratch.data() + static_cast<std::size_t>(y / tileSize) * cols;
    for (int tx = 0, x0 = 0; tx < cols; ++tx, x0 += tileSize) {
      const int x1 = std::min(w, x0 + tileSize);
      std::uint32_t n = 0;
      for (int x = x0; x < x1; ++x) n += row[x] != 0;
      tileRow[tx] += n;
    }
  }
  const auto minHoles = static_cast<std::uint32_t>(minHolesPerTile);
  // Built in tile units. A run of a row extends the rectangle ending right
  // above it with the same columns (the runs of a row are disjoint: at most
  // one matches), else starts one.
  for (int ty = 0; ty < rows; ++ty) {
    const std::uint32_t* s = scratch.data() + static_cast<std::size_t>(ty) * cols;
    for (int tx = 0; tx < cols;) {
      if (s[tx] < minHoles) {
        ++tx;
        continue;
      }
      const int start = tx;
      int count = 0;
      for (; tx < cols && s[tx] >= minHoles; ++tx) count += static_cast<int>(s[tx]);
      auto above = std::find_if(out.begin(), out.end(), [&](const HoleRect& r) {
        return r.rect.y1 == ty && r.rect.x0 == start && r.rect.x1 == tx;
      });
      if (above != out.end()) {
        above->rect.y1 = ty + 1;
        above->holes += count;
      } else {
        out.push_back({PixelRect{start, ty, tx, ty + 1}, count});
      }
    }
  }
  // Tile units to pixels, cut at the border.
  for (HoleRect& r : out)
    r.rect = PixelRect{r.rect.x0 * tileSize, r.rect.y0 * tileSize,
                       std::min(w, r.rect.x1 * tileSize), std::min(h, r.rect.y1 * tileSize)};
  std::stable_sort(out.begin(), out.end(), [](const HoleRect& a, const HoleRect& b) {
    if (a.holes != b.holes) return a.holes > b.holes;
    return a.rect.y0 != b.rect.y0 ? a.rect.y0 < b.rect.y0 : a.rect.x0 < b.rect.x0;
  });
  if (out.size() > static_cast<std::size_t>(maxRects)) out.resize(static_cast<std::size_t>(maxRects));
}

}  // namespace hw::gapfill
