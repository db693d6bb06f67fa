// Per-pixel age (gapfill/age.h): the update rule, the stale-tile scores and
// the choice of the region to re-render.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "gapfill/age.h"
#include "gapfill/compose.h"

namespace hw::gapfill {
namespace {

// A frame whose holes/valid masks are given row by row ('.' = layer pixel,
// 'h' = hole filled from the previous frame, 'u' = hole left unfilled).
Frame frameFromMask(const std::vector<const char*>& rows) {
  Frame f;
  const int h = static_cast<int>(rows.size());
  const int w = static_cast<int>(std::char_traits<char>::length(rows[0]));
  f.colour.resize(w, h);
  f.holesBefore.resize(w, h);
  f.valid.resize(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const char c = rows[static_cast<std::size_t>(y)][x];
      f.holesBefore(x, y) = c != '.';
      f.valid(x, y) = c != 'u';
    }
  return f;
}

TEST(PixelAge, KeyframePixelsAreZeroFilledPixelsAgeByOneUnfilledAreMax) {
  Frame prev = frameFromMask({"...", "...", "..."});
  prev.age.resize(3, 3);
  const std::uint8_t prevAges[9] = {0, 1, 2, 3, 4, 5, 254, 255, 7};
  for (int i = 0; i < 9; ++i) prev.age.data()[i] = prevAges[i];
  Frame out = frameFromMask({".hh", "hh.", "hhu"});
  const AgeStats s = updateAge(&prev, out);
  // (0,0) layer → 0; filled → previous + 1; 254 → 255; 255 saturates; unfilled → 255.
  const std::uint8_t want[9] = {0, 2, 3, 4, 5, 0, 255, 255, 255};
  for (int i = 0; i < 9; ++i) EXPECT_EQ(out.age.data()[i], want[i]) << "pixel " << i;
  EXPECT_EQ(s.stale, 7);
  EXPECT_EQ(s.maxAge, 255);
  const AgeStats again = ageStats(out.age);
  EXPECT_EQ(again.stale, s.stale);
  EXPECT_EQ(again.maxAge, s.maxAge);
}

TEST(PixelAge, RepeatedFillsCountFramesAndSaturateAt255) {
  Frame a = frameFromMask({"h."}), b = frameFromMask({"h."});
  a.age.resize(2, 1);
  a.age.fill(0);
  Frame* prev = &a;
  Frame* cur = &b;
  for (int frame = 1; frame <= 300; ++frame) {
    const AgeStats s = updateAge(prev, *cur);
    EXPECT_EQ(cur->age(0, 0), frame < 255 ? frame : 255) << "frame " << frame;
    EXPECT_EQ(cur->age(1, 0), 0);
    EXPECT_EQ(s.stale, 1);
    std::swap(prev, cur);
  }
}

TEST(PixelAge, NoPreviousFrameGivesZeroForLayerPixelsAndMaxForHoles) {
  Frame out = frameFromMask({".u", "h."});
  const AgeStats s = updateAge(nullptr, out);
  EXPECT_EQ(out.age(0, 0), 0);
  EXPECT_EQ(out.age(1, 0), kAgeMax);
  EXPECT_EQ(out.age(0, 1), kAgeMax);
  EXPECT_EQ(out.age(1, 1), 0);
  EXPECT_EQ(s.stale, 2);
}

TEST(PixelAge, TileScoresSumAgesAtOrAboveTheThreshold) {
  Image<std::uint8_t> age(5, 3);  // tiles of 2: 3 × 2, the last column and row cut
  age.fill(0);
  age(0, 0) = 1;  // below threshold 2: not counted
  age(1, 1) = 3;
  age(4, 2) = 9;  // tile (2, 1), one pixel wide and tall
  age(2, 0) = 2;
  std::vector<std::uint32_t> scores;
  int cols = 0, rows = 0;
  scoreStaleTiles(age, 2, 2, scores, &cols, &rows);
  ASSERT_EQ(cols, 3);
  ASSERT_EQ(rows, 2);
  const std::vector<std::uint32_t> want = {3, 2, 0, 0, 0, 9};
  EXPECT_EQ(scores, want);
  scoreStaleTiles(age, 1, 2, scores, &cols, &rows);
  EXPECT_EQ(scores[0], 4u);
}

TEST(PixelAge, RefreshRectTakesTheOldestTilesWithinThePixelBound) {
  // 4 × 4 tiles of 8 px on a 30 × 32 image (the last column is 6 px wide).
  const int cols = 4, rows = 4, tile = 8;
  std::vector<std::uint32_t> scores(16, 0);
  scores[0] = 50;       // tile (0, 0)
  scores[1] = 40;       // tile (1, 0)
  scores[15] = 45;      // tile (3, 3): far corner, cut to 6 px wide
  std::vector<int> order;
  PixelRect r;
  // Room for two tiles: (0,0) then (1,0); (3,3) would need the whole image.
  ASSERT_TRUE(chooseRefreshRect(scores, cols, rows, tile, 30, 32, 2 * 64, order, &r));
  EXPECT_EQ(r.x0, 0);
  EXPECT_EQ(r.y0, 0);
  EXPECT_EQ(r.x1, 16);
  EXPECT_EQ(r.y1, 8);
  // Room for everything: the bounding rectangle, cut at the border.
  ASSERT_TRUE(chooseRefreshRect(scores, cols, rows, tile, 30, 32, 30 * 32, order, &r));
  EXPECT_EQ(r.x1, 30);
  EXPECT_EQ(r.y1, 32);
  // Less than one tile: nothing.
  EXPECT_FALSE(chooseRefreshRect(scores, cols, rows, tile, 30, 32, 63, order, &r));
  // After the refresh its tiles score 0; the corner is next.
  clearTileScores(PixelRect{0, 0, 16, 8}, cols, tile, scores);
  EXPECT_EQ(scores[0], 0u);
  EXPECT_EQ(scores[1], 0u);
  ASSERT_TRUE(chooseRefreshRect(scores, cols, rows, tile, 30, 32, 64, order, &r));
  EXPECT_EQ(r.x0, 24);
  EXPECT_EQ(r.y0, 24);
  EXPECT_EQ(r.area(), 48);
  std::fill(scores.begin(), scores.end(), 0u);
  EXPECT_FALSE(chooseRefreshRect(scores, cols, rows, tile, 30, 32, 1 << 20, order, &r));
}

TEST(PixelAge, ApplyRefreshCopiesColourAndResetsAge) {
  Frame f = frameFromMask({"hhhh", "hhhh", "hhhu"});
  f.colour.fill(Rgba8{1, 2, 3, 255});
  f.age.resize(4, 3);
  f.age.fill(9);
  Image<Rgba8> patch(2, 2);
  patch.fill(Rgba8{200, 100, 50, 255});
  patch(1, 1) = Rgba8{7, 8, 9, 255};
  applyRefresh(PixelRect{2, 1, 4, 3}, patch, f);
  EXPECT_EQ(f.colour(2, 1), (Rgba8{200, 100, 50, 255}));
  EXPECT_EQ(f.colour(3, 2), (Rgba8{7, 8, 9, 255}));
  EXPECT_EQ(f.colour(1, 1), (Rgba8{1, 2, 3, 255}));
  EXPECT_EQ(f.age(3, 2), 0);
  EXPECT_EQ(f.valid(3, 2), 1);
  EXPECT_EQ(f.age(1, 2), 9);
  EXPECT_EQ(ageStats(f.age).stale, 12 - 4);
}

}  // namespace
}  // namespace hw::gapfill
