#include "warp/sky_rects.h"

namespace hw::warp {

void emptyRects(const Image<std::uint8_t>& covered, std::vector<keyframe::PixelRect>& out) {
  out.clear();
  // Indices into `out` of the rectangles that end at the previous row, in x order.
  std::vector<std::size_t> open, next;
  for (int y = 0; y < covered.height(); ++y) {
    next.clear();
    std::size_t o = 0;
    const std::uint8_t* row = &covered(0, y);
    for (int x = 0; x < covered.width();) {
      if (row[x]) {
        ++x;
        continue;
      }
      const int x0 = x;
      while (x < covered.width() && !row[x]) ++x;
      // Open rectangles are sorted by x0 and disjoint: advance to the first
      // that could match this run.
      while (o < open.size() && out[open[o]].x0 < x0) ++o;
      if (o < open.size() && out[open[o]].x0 == x0 && out[open[o]].x1 == x) {
        out[open[o]].y1 = y + 1;
        next.push_back(open[o]);
        ++o;
      } else {
        out.push_back(keyframe::PixelRect{x0, y, x, y + 1});
        next.push_back(out.size() - 1);
      }
    }
    open.swap(next);
  }
}

}  // namespace hw::warp
