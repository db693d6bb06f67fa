#pragma once
// Per-pixel age and the choice of what to re-render (stable frame
// rate; after Qu et al. 2000 §3.1 "age buffer" and §3.4 "balancing the
// workload"). A pixel's age counts the frames its colour has been carried
// over from the previous frame since it was last taken from a keyframe layer
// or re-rendered by the geometry renderer: the holes of this pipeline are the
// pixels "warped too many times". A frame with time left re-renders the
// region whose pixels are oldest.
#include <cstdint>
#include <vector>

#include "core/image.h"
#include "core/rect.h"
#include "gapfill/compose.h"

namespace hw::gapfill {

constexpr std::uint8_t kAgeMax = 255;  // saturates; also "never rendered" (unfilled)

struct AgeStats {
  int stale = 0;   // pixels with age >= 1
  int maxAge = 0;  // 0..255
};

// out.age from out.holesBefore and out.valid (as compose() left them, or as
// the walk set them after near geometry or a keyframe) and previous->age:
//   holesBefore = 0 (a keyframe layer covers the pixel)      → 0
//   hole filled from the previous frame (valid = 1)           → previous age + 1, saturating at 255
//   hole left unfilled (valid = 0) or no previous frame      → 255
// Preconditions (checked): holesBefore and valid have one size; previous (if
// given) has an age image of that size, and is not &out. Allocation-free when
// out.age already has that size.
AgeStats updateAge(const Frame* previous, Frame& out);

// Counts over an age image.
AgeStats ageStats(const Image<std::uint8_t>& age);

// Per tile of tileSize × tileSize pixels (edge tiles are cut at the image
// border), the sum of the ages of pixels with age >= staleAfter (>= 1). Tiles
// in row-major order, *cols × *rows of them; `scores` is resized (reused).
void scoreStaleTiles(const Image<std::uint8_t>& age, int staleAfter, int tileSize,
                     std::vector<std::uint32_t>& scores, int* cols, int* rows);

// The region to re-render: tiles taken in decreasing score (ties: lower
// index first), their bounding rectangle grown while its area stays within
// maxPixels; tiles whose addition would exceed it are passed over. Returns
// false (and *out unchanged) when no tile has a score > 0 or the best tile
// alone exceeds maxPixels. `order` is scratch (reused). The rectangle is
// tile-aligned, cut at the image border.
bool chooseRefreshRect(const std::vector<std::uint32_t>& scores, int cols, int rows, int tileSize,
                       int width, int height, long long maxPixels, std::vector<int>& order,
                       PixelRect* out);

// Sets the scores of the tiles inside a tile-aligned rectangle to 0 (after
// it was re-rendered).
void clearTileScores(const PixelRect& rect, int cols, int tileSize,
                     std::vector<std::uint32_t>& scores);

// A re-rendered rectangle: its colour (rect-sized, row 0 = the rect's top)
// goes into frame.colour, its pixels get age 0 and valid = 1.
void applyRefresh(const PixelRect& rect, const Image<Rgba8>& colour, Frame& frame);

}  // namespace hw::gapfill
