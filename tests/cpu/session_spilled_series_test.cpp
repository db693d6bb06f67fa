// SpilledSeries: a per-frame series whose older values go to a scratch file
// reads back exactly what was pushed, in order, and keeps at most one block
// in memory; without a file (or after a failed write) it is a plain vector.
#include "session/spilled_series.h"

#include <gtest/gtest.h>


#include <cmath>
#include <filesystem>

namespace hw::session {
namespace {

constexpr std::size_t kB = SpilledSeries<double>::kBlock;

TEST(SpilledSeries, ReadsBackEveryValueInOrder) {
  SpillFile file("");
  SpilledSeries<double> a;
  SpilledSeries<int> b;
  SpilledSeries<char> c;
  a.attach(&file);
  b.attach(&file);
  c.attach(&file);
  const std::size_t n = 5 * kB + 123;  // interleaved blocks of three series
  for (std::size_t i = 0; i < n; ++i) {
    a.push_back(0.5 * static_cast<double>(i));
    b.push_back(static_cast<int>(i) - 7);
    c.push_back(static_cast<char>(i % 2));
  }
  EXPECT_EQ(a.size(), n);
  EXPECT_EQ(file.size(), static_cast<std::int64_t>(5 * kB * (sizeof(double) + sizeof(int) + 1)));
  const auto va = a.values();
  const auto vb = b.values();
  const auto vc = c.values();
  ASSERT_EQ(va.size(), n);
  ASSERT_EQ(vb.size(), n);
  ASSERT_EQ(vc.size(), n);
  for (std::size_t i = 0; i < n; ++i) {
    ASSERT_EQ(va[i], 0.5 * static_cast<double>(i)) << i;
    ASSERT_EQ(vb[i], static_cast<int>(i) - 7) << i;
    ASSERT_EQ(vc[i], static_cast<char>(i % 2)) << i;
  }
  EXPECT_FALSE(file.readFailed());
}

TEST(SpilledSeries, ShortSeriesCreateNoFile) {
  const auto dir = std::filesystem::temp_directory_path() / "hw_spill_short_test";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  {
    SpillFile file(dir.string());
    SpilledSeries<double> a;
    a.attach(&file);
    for (std::size_t i = 0; i < kB; ++i) a.push_back(1.0);
    EXPECT_EQ(file.size(), 0);
    EXPECT_EQ(a.values().size(), kB);
  }
  EXPECT_TRUE(std::filesystem::is_empty(dir));
  std::filesystem::remove_all(dir);
}

TEST(SpilledSeries, LeavesNothingInTheDirectory) {
  const auto dir = std::filesystem::temp_directory_path() / "hw_spill_gone_test";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  {
    SpillFile file(dir.string());
    SpilledSeries<double> a;
    a.attach(&file);
    for (std::size_t i = 0; i < 3 * kB; ++i) a.push_back(std::nan(""));
    EXPECT_GT(file.size(), 0);
    EXPECT_TRUE(std::isnan(a.values()[kB]));
  }
  EXPECT_TRUE(std::filesystem::is_empty(dir));  // unnamed, or the fallback removed
  std::filesystem::remove_all(dir);
}

TEST(SpilledSeries, UnwritableDirectoryKeepsValuesInMemory) {
  SpillFile file("/proc/self/no-such-dir");
  SpilledSeries<double> a;
  a.attach(&file);
  const std::size_t n = 2 * kB + 5;
  for (std::size_t i = 0; i < n; ++i) a.push_back(static_cast<double>(i));
  const auto v = a.values();
  ASSERT_EQ(v.size(), n);
  for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(v[i], static_cast<double>(i));
  EXPECT_FALSE(file.readFailed());
}

TEST(SpilledSeries, WithoutFileIsAVector) {
  SpilledSeries<double> a;
  EXPECT_TRUE(a.empty());
  for (int i = 0; i < 10000; ++i) a.push_back(i);
  EXPECT_EQ(a.size(), 10000u);
  EXPECT_EQ(a.values()[9999], 9999.0);
}

}  // namespace
}  // namespace hw::session
