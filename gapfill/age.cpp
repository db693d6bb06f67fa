#include "gapfill/age.h"

#include <algorithm>
#include <cstring>

#include "core/check.h"

namespace hw::gapfill {

AgeStats updateAge(const Frame* previous, Frame& out) {
  HW_CHECK(previous != &out);
  const int w = out.holesBefore.width(), h = out.holesBefore.height();
  HW_CHECK_EQ(out.valid.width(), w);
  HW_CHECK_EQ(out.valid.height(), h);
  if (previous) {
    HW_CHECK_EQ(previous->age.width(), w);
    HW_CHECK_EQ(previous->age.height(), h);
  }
  if (out.age.width() != w || out.age.height() != h) out.age.resize(w, h);
  const std::size_t n = out.age.size();
  const std::uint8_t* hole = out.holesBefore.data();
  const std::uint8_t* valid = out.valid.data();
  std::uint8_t* age = out.age.data();
  int stale = 0;
  unsigned maxAge = 0;
  if (previous) {
    const std::uint8_t* prev = previous->age.data();
    for (std::size_t i = 0; i < n; ++i) {
      const unsigned carried = std::min<unsigned>(prev[i] + 1u, kAgeMax);
      const unsigned a = hole[i] == 0 ? 0u : valid[i] != 0 ? carried : kAgeMax;
      age[i] = static_cast<std::uint8_t>(a);
      stale += a != 0;
      maxAge = std::max(maxAge, a);
    }
  } else {
    for (std::size_t i = 0; i < n; ++i) {
      const unsigned a = hole[i] == 0 ? 0u : kAgeMax;
      age[i] = static_cast<std::uint8_t>(a);
      stale += a != 0;
      maxAge = std::max(maxAge, a);
    }
  }
  return AgeStats{stale, static_cast<int>(maxAge)};
}

AgeStats ageStats(const Image<std::uint8_t>& age) {
  int stale = 0;
  unsigned maxAge = 0;
  const std::uint8_t* a = age.data();
  for (std::size_t i = 0; i < age.size(); ++i) {
    stale += a[i] != 0;
    maxAge = std::max<unsigned>(maxAge, a[i]);
  }
  return AgeStats{stale, static_cast<int>(maxAge)};
}

void scoreStaleTiles(const Image<std::uint8_t>& age, int staleAfter, int tileSize,
                     std::vector<std::uint32_t>& scores, int* cols, int* rows) {
  HW_CHECK(staleAfter >= 1 && tileSize >= 1 && cols != nullptr && rows != nullptr);
  const int w = age.width(), h = age.height();
  *cols = (w + tileSize - 1) / tileSize;
  *rows = (h + tileSize - 1) / tileSize;
  scores.assign(static_cast<std::size_t>(*cols) * static_cast<std::size_t>(*rows), 0u);
  const unsigned threshold = static_cast<unsigned>(std::min(staleAfter, 255));
  for (int y = 0; y < h; ++y) {
    const std::uint8_t* row = &age(0, y);
    std::uint32_t* tileRow = scores.data() + static_cast<std::size_t>(y / tileSize) * *cols;
    for (int tx = 0; tx < *cols; ++tx) {
      const int x0 = tx * tileSize, x1 = std::min(w, x0 + tileSize);
      std::uint32_t s = 0;
      for (int x = x0; x < x1; ++x) s += row[x] >= threshold ? row[x] : 0u;
      tileRow[tx] += s;
    }
  }
}

bool chooseRefreshRect(const std::vector<std::uint32_t>& scores, int cols, int rows, int tileSize,
                       int width, int height, long long maxPixels, std::vector<int>& order,
                       PixelRect* out) {
  HW_CHECK(out != nullptr && tileSize >= 1);
  HW_CHECK_EQ(scores.size(), static_cast<std::size_t>(cols) * static_cast<std::size_t>(rows));
  order.clear();
  for (int i = 0; i < static_cast<int>(scores.size()); ++i)
    if (scores[static_cast<std::size_t>(i)] > 0) order.push_back(i);
  if (order.empty()) return false;
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return scores[static_cast<std::size_t>(a)] > scores[static_cast<std::size_t>(b)];
  });
  auto tileRect = [&](int t) {
    const int tx = t % cols, ty = t / cols;
    return PixelRect{tx * tileSize, ty * tileSize, std::min(width, (tx + 1) * tileSize),
                               std::min(height, (ty + 1) * tileSize)};
  };
  PixelRect r = tileRect(order.front());
  if (r.area() > maxPixels) return false;
  for (std::size_t k = 1; k < order.size(); ++k) {
    const PixelRect t = tileRect(order[k]);
    const PixelRect u{std::min(r.x0, t.x0), std::min(r.y0, t.y0), std::max(r.x1, t.x1),
                                std::max(r.y1, t.y1)};
    if (u.area() <= maxPixels) r = u;
  }
  *out = r;
  return true;
}

void clearTileScores(const PixelRect& rect, int cols, int tileSize,
                     std::vector<std::uint32_t>& scores) {
  HW_CHECK(tileSize >= 1 && cols >= 1);
  for (int ty = rect.y0 / tileSize; ty * tileSize < rect.y1; ++ty)
    for (int tx = rect.x0 / tileSize; tx * tileSize < rect.x1; ++tx) {
      const std::size_t i = static_cast<std::size_t>(ty) * cols + tx;
      if (tx < cols && i < scores.size()) scores[i] = 0;
    }
}

void applyRefresh(const PixelRect& rect, const Image<Rgba8>& colour, Frame& frame) {
  HW_CHECK_EQ(colour.width(), rect.width());
  HW_CHECK_EQ(colour.height(), rect.height());
  HW_CHECK(rect.x0 >= 0 && rect.y0 >= 0 && rect.x1 <= frame.colour.width() &&
           rect.y1 <= frame.colour.height());
  const bool haveAge = frame.age.width() == frame.colour.width() &&
                       frame.age.height() == frame.colour.height();
  const bool haveValid = frame.valid.width() == frame.colour.width() &&
                         frame.valid.height() == frame.colour.height();
  const auto w = static_cast<std::size_t>(rect.width());
  for (int y = rect.y0; y < rect.y1; ++y) {
    std::memcpy(static_cast<void*>(&frame.colour(rect.x0, y)), &colour(0, y - rect.y0),
                w * sizeof(Rgba8));
    if (haveAge) std::memset(&frame.age(rect.x0, y), 0, w);
    if (haveValid) std::memset(&frame.valid(rect.x0, y), 1, w);
  }
}

}  // namespace hw::gapfill
