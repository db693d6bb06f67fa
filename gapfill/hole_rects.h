#pragma once
// Where to draw holes exactly: rectangles over the tiles that hold holes, for
// the geometry renderer to fill (walk --render-holes). Tight rectangles, not
// one bounding box: the holes a warp leaves are thin strips at the frame
// border and behind silhouettes, and a renderer's cost follows the area
// drawn.
#include <cstdint>
#include <vector>

#include "core/image.h"
#include "core/rect.h"

namespace hw::gapfill {

struct HoleRect {
  PixelRect rect;
  int holes = 0;  // hole pixels inside
};

// The tiles of tileSize x tileSize pixels (cut at the image border) holding
// at least minHolesPerTile non-zero pixels of `holes`, covered exactly by
// rectangles: each tile row's runs of such tiles, a run merged with the one
// right above it when both span the same columns. The maxRects with the most
// hole pixels are kept, in decreasing hole count (ties: top-left first).
// `out` and `scratch` are reused (allocation-free once grown).
// Preconditions (checked): tileSize >= 1, minHolesPerTile >= 1, maxRects >= 0.
void holeRects(const Image<std::uint8_t>& holes, int tileSize, int minHolesPerTile, int maxRects,
               std::vector<HoleRect>& out, std::vector<std::uint32_t>& scratch);

}  // namespace hw::gapfill
