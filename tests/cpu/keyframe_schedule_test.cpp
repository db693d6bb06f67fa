// KeyframeSchedule: fixed spacing and explicit (error-driven) keyframe lists.
#include <gtest/gtest.h>

#include "keyframe/keyframe_cache.h"

namespace hw::keyframe {
namespace {

TEST(KeyframeSchedule, FixedSpacingEndsOnTheLastFrame) {
  const KeyframeSchedule s{25, 10, {}};
  EXPECT_EQ(s.keyframes(), (std::vector<int>{0, 10, 20, 24}));
  EXPECT_EQ(s.bracket(5), std::make_pair(0, 10));
  EXPECT_EQ(s.bracket(21), std::make_pair(20, 24));
  EXPECT_EQ(s.bracket(10), std::make_pair(10, 10));
}

TEST(KeyframeSchedule, ExplicitListBracketsEveryFrame) {
  const KeyframeSchedule s{30, 10, {3, 4, 17}};
  EXPECT_EQ(s.keyframes(), (std::vector<int>{0, 3, 4, 17, 29}));
  EXPECT_EQ(s.bracket(1), std::make_pair(0, 3));
  EXPECT_EQ(s.bracket(5), std::make_pair(4, 17));
  EXPECT_EQ(s.bracket(28), std::make_pair(17, 29));
  EXPECT_FALSE(s.isKeyframe(10));  // the fixed spacing no longer applies
  for (int f = 0; f < 30; ++f) {
    const auto [a, b] = s.bracket(f);
    EXPECT_TRUE(s.isKeyframe(a) && s.isKeyframe(b)) << f;
    EXPECT_LE(a, f);
    EXPECT_GE(b, f);
  }
}

}  // namespace
}  // namespace hw::keyframe
