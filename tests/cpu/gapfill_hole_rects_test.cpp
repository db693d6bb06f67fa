// Hole rectangles for walk --render-holes: tight rectangles over the tiles
// holding holes, the most holes first.
#include "gapfill/hole_rects.h"

#include <gtest/gtest.h>

namespace hw::gapfill {
namespace {

Image<std::uint8_t> blank(int w, int h) {
  Image<std::uint8_t> m(w, h);
  m.fill(0);
  return m;
}

void paint(Image<std::uint8_t>& m, int x0, int y0, int x1, int y1) {
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) m(x, y) = 1;
}

TEST(HoleRects, NoHolesNoRects) {
  std::vector<HoleRect> out{{PixelRect{0, 0, 1, 1}, 5}};
  std::vector<std::uint32_t> scratch;
  holeRects(blank(64, 48), 16, 1, 8, out, scratch);
  EXPECT_TRUE(out.empty());
}

TEST(HoleRects, BorderStripsBecomeThinRectanglesNotABoundingBox) {
  // A 3-pixel strip along the top and a 2-pixel column on the right: an
  // L-shape whose bounding box is the whole frame.
  Image<std::uint8_t> m = blank(128, 96);
  paint(m, 0, 0, 128, 3);
  paint(m, 126, 0, 128, 96);
  std::vector<HoleRect> out;
  std::vector<std::uint32_t> scratch;
  holeRects(m, 16, 8, 8, out, scratch);
  ASSERT_EQ(out.size(), 2u);
  // The top row of tiles (8 tiles; the corner tile belongs to it) and the
  // column below it.
  EXPECT_EQ(out[0].rect.x0, 0);
  EXPECT_EQ(out[0].rect.y0, 0);
  EXPECT_EQ(out[0].rect.x1, 128);
  EXPECT_EQ(out[0].rect.y1, 16);
  EXPECT_EQ(out[0].holes, 128 * 3 + 2 * 13);
  EXPECT_EQ(out[1].rect.x0, 112);
  EXPECT_EQ(out[1].rect.y0, 16);
  EXPECT_EQ(out[1].rect.x1, 128);
  EXPECT_EQ(out[1].rect.y1, 96);
  EXPECT_EQ(out[1].holes, 2 * 80);
  long long area = 0;
  for (const HoleRect& r : out) area += r.rect.area();
  EXPECT_EQ(area, 128 * 16 + 16 * 80);  // a fifth of the frame, not all of it
}

TEST(HoleRects, SparseTilesAreLeftToTheFallbackAndTheCountIsCapped) {
  Image<std::uint8_t> m = blank(64, 64);
  m(3, 3) = 1;                // one crack pixel: below 8 per tile
  paint(m, 20, 20, 24, 24);   // 16 pixels in tile (1, 1)
  paint(m, 40, 40, 43, 43);   // 9 pixels in tile (2, 2)
  paint(m, 50, 2, 60, 12);    // 100 pixels in tile (3, 0)
  std::vector<HoleRect> out;
  std::vector<std::uint32_t> scratch;
  holeRects(m, 16, 8, 8, out, scratch);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[0].holes, 100);
  EXPECT_EQ(out[1].holes, 16);
  EXPECT_EQ(out[2].holes, 9);
  holeRects(m, 16, 8, 2, out, scratch);  // the two with the most holes
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].rect.x0, 48);
  EXPECT_EQ(out[1].rect.x0, 16);
  holeRects(m, 16, 1, 8, out, scratch);  // one pixel suffices now
  EXPECT_EQ(out.size(), 4u);
}

TEST(HoleRects, EdgeTilesAreCutAtTheBorderAndRunsOfDifferentWidthStaySeparate) {
  // 40 x 40 with tiles of 16: the last tile column and row are 8 wide.
  Image<std::uint8_t> m = blank(40, 40);
  paint(m, 0, 0, 40, 40);
  std::vector<HoleRect> out;
  std::vector<std::uint32_t> scratch;
  holeRects(m, 16, 8, 8, out, scratch);
  ASSERT_EQ(out.size(), 1u);  // every tile: one run per row, all the same columns
  EXPECT_EQ(out[0].rect.x1, 40);
  EXPECT_EQ(out[0].rect.y1, 40);
  EXPECT_EQ(out[0].holes, 1600);
  // A staircase: row 0 tiles 0..1, row 1 tiles 0..2: two rectangles.
  Image<std::uint8_t> s = blank(48, 32);
  paint(s, 0, 0, 32, 16);
  paint(s, 0, 16, 48, 32);
  holeRects(s, 16, 8, 8, out, scratch);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].rect.x1, 48);
  EXPECT_EQ(out[0].rect.y0, 16);
  EXPECT_EQ(out[1].rect.x1, 32);
  EXPECT_EQ(out[1].rect.y1, 16);
}

}  // namespace
}  // namespace hw::gapfill
