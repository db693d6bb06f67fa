// The schedule oracle's exact search (bench/schedule_oracle.h): on random
// PSNR tables the dynamic programme finds the same fewest keyframes as
// trying every schedule, its schedule really has a median at or above the
// target, and bad schedules are refused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <random>
#include <vector>

#include "bench/schedule_oracle.h"

namespace hw::bench {
namespace {

SegmentTable randomTable(int frames, int maxGap, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(20.0, 40.0);
  SegmentTable t(frames, maxGap);
  for (int k0 = 0; k0 < frames; ++k0)
    for (int k1 = k0 + 2; k1 < frames && k1 - k0 <= maxGap; ++k1)
      for (int f = k0 + 1; f < k1; ++f) t.set(k0, k1, f, u(rng));
  return t;
}

// Fewest keyframes over every schedule (0 and frames-1 included, gaps <=
// maxGap) whose median is reached by more than half of the in-between
// frames; 0 = none.
int bruteForce(const SegmentTable& t, double target) {
  const int n = t.frames(), inner = n - 2;
  int best = 0;
  for (unsigned mask = 0; mask < (1u << inner); ++mask) {
    std::vector<int> keys{0};
    for (int i = 0; i < inner; ++i)
      if (mask & (1u << i)) keys.push_back(i + 1);
    keys.push_back(n - 1);
    bool ok = true;
    int good = 0;
    for (std::size_t i = 1; i < keys.size() && ok; ++i) {
      if (keys[i] - keys[i - 1] > t.maxGap()) ok = false;
      for (int f = keys[i - 1] + 1; ok && f < keys[i]; ++f) good += t.at(keys[i - 1], keys[i], f) >= target;
    }
    const int inBetween = n - static_cast<int>(keys.size());
    if (!ok || inBetween < 1 || good < inBetween / 2 + 1) continue;
    if (best == 0 || static_cast<int>(keys.size()) < best) best = static_cast<int>(keys.size());
  }
  return best;
}

TEST(ScheduleOracle, DynamicProgrammeMatchesEverySchedule) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 40; ++trial) {
    const int frames = 6 + trial % 9, maxGap = 2 + trial % 5;  // up to 14 frames: 4096 schedules
    const SegmentTable t = randomTable(frames, maxGap, rng);
    ASSERT_TRUE(t.complete());
    for (double target : {22.0, 28.0, 30.0, 33.0, 38.0}) {
      const OracleSchedule o = fewestKeyframesForMedian(t, target);
      const int expect = bruteForce(t, target);
      ASSERT_EQ(static_cast<int>(o.keyframes.size()), expect)
          << "frames " << frames << " max gap " << maxGap << " target " << target;
      if (expect == 0) continue;
      auto p = schedulePsnr(t, o.keyframes);
      ASSERT_TRUE(p.ok()) << p.error().message;
      EXPECT_GE(p->median, target);
      EXPECT_GE(p->lowerMedian, target);
      EXPECT_EQ(p->inBetween, frames - expect);
      EXPECT_GE(o.good, p->inBetween / 2 + 1);
    }
  }
}

TEST(ScheduleOracle, NeverWorseThanFixedAndFarBetterOnAVaryingPath) {
  // PSNR falls with the distance to the nearer keyframe. Uniform: the same
  // fall everywhere. Varying: the first half of the path is 4x easier.
  const int frames = 61, maxGap = 20;
  for (bool varying : {false, true}) {
    SegmentTable t(frames, maxGap);
    for (int k0 = 0; k0 < frames; ++k0)
      for (int k1 = k0 + 2; k1 < frames && k1 - k0 <= maxGap; ++k1)
        for (int f = k0 + 1; f < k1; ++f) {
          const double d = std::min(f - k0, k1 - f);
          const double rate = varying && f < frames / 2 ? 0.25 : 1.0;
          t.set(k0, k1, f, 40.0 - rate * d);
        }
    std::vector<int> fixed;
    for (int k = 0; k < frames; k += 6) fixed.push_back(k);  // 0..60: 11 keyframes
    auto fp = schedulePsnr(t, fixed);
    ASSERT_TRUE(fp.ok()) << fp.error().message;
    const OracleSchedule o = fewestKeyframesForMedian(t, fp->lowerMedian);
    ASSERT_FALSE(o.keyframes.empty());
    auto op = schedulePsnr(t, o.keyframes);
    ASSERT_TRUE(op.ok()) << op.error().message;
    EXPECT_GE(op->lowerMedian, fp->lowerMedian);
    EXPECT_GE(op->median, fp->lowerMedian);
    // The fixed schedule itself qualifies, so the oracle never needs more.
    EXPECT_LE(o.keyframes.size(), fixed.size());
    if (varying) {
      EXPECT_LE(static_cast<double>(o.keyframes.size()), 0.7 * static_cast<double>(fixed.size()));
    }
  }
}

TEST(ScheduleOracle, RefusesSchedulesTheTableCannotAnswer) {
  std::mt19937 rng(1);
  const SegmentTable t = randomTable(10, 3, rng);
  EXPECT_FALSE(schedulePsnr(t, {}).ok());
  EXPECT_FALSE(schedulePsnr(t, {1, 4, 7, 9}).ok());     // not from 0
  EXPECT_FALSE(schedulePsnr(t, {0, 3, 6, 8}).ok());     // not to 9
  EXPECT_FALSE(schedulePsnr(t, {0, 4, 7, 9}).ok());     // gap 4 > 3
  EXPECT_FALSE(schedulePsnr(t, {0, 3, 3, 6, 9}).ok());  // not increasing
  EXPECT_TRUE(schedulePsnr(t, {0, 3, 6, 9}).ok());
  SegmentTable partial(10, 3);
  partial.set(0, 2, 1, 30.0);
  EXPECT_FALSE(partial.complete());
  EXPECT_FALSE(schedulePsnr(partial, {0, 2, 5, 8, 9}).ok());
  EXPECT_TRUE(fewestKeyframesForMedian(SegmentTable(2, 3), 10.0).keyframes.empty());
}

TEST(ScheduleOracle, TableCsvRoundTripsAndBadFilesNameTheLine) {
  std::mt19937 rng(3);
  const SegmentTable t = randomTable(9, 3, rng);
  std::string csv = "k0,k1,frame,psnr\n";
  for (int k0 = 0; k0 < 9; ++k0)
    for (int k1 = k0 + 2; k1 < 9 && k1 - k0 <= 3; ++k1)
      for (int f = k0 + 1; f < k1; ++f) {
        char b[96];
        std::snprintf(b, sizeof b, "%d,%d,%d,%.17g\n", k0, k1, f, t.at(k0, k1, f));
        csv += b;
      }
  auto back = readSegmentTable(csv, "t.csv", 9, 3);
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(back->at(2, 5, 4), t.at(2, 5, 4));
  EXPECT_EQ(back->at(6, 8, 7), t.at(6, 8, 7));
  auto bad = [&](const std::string& text, int frames, int gap, const std::string& want) {
    auto r = readSegmentTable(text, "t.csv", frames, gap);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find(want), std::string::npos) << r.error().message;
  };
  bad("", 9, 3, "t.csv: empty");
  bad("frame,psnr\n", 9, 3, "t.csv:1: expected the header");
  bad(csv + "1,3,x,2\n", 9, 3, "expected 'k0,k1,frame,psnr'");
  bad(csv + "1,3,2,nan\n", 9, 3, "finite");
  bad(csv + "0,4,2,30\n", 9, 3, "outside a 9-frame path with gaps up to 3");
  bad(csv, 10, 3, "incomplete");   // another --frames
  bad(csv, 9, 4, "incomplete");    // another --max-gap
}

}  // namespace
}  // namespace hw::bench
