// The free-camera keyframe policy (session/keyframe_survey.h) on numbers.
#include <gtest/gtest.h>

#include "session/keyframe_survey.h"

namespace {

using hw::session::surveyKeyframes;
using hw::session::SurveySlot;

TEST(KeyframeSurvey, NoKeyframeIsLost) {
  const SurveySlot none[2] = {};
  const auto k = surveyKeyframes(none, true, -1, 0);
  EXPECT_TRUE(k.lost);
  EXPECT_EQ(k.nearest, -1);
  EXPECT_EQ(k.newest, -1);
  EXPECT_TRUE(k.wanted);  // moving with fewer than two useful keyframes
}

TEST(KeyframeSurvey, NearestNewestAndReach) {
  const SurveySlot s[2] = {{true, 7, 0.4}, {true, 9, 1.2}};
  const auto k = surveyKeyframes(s, false, -1, 0);
  EXPECT_EQ(k.nearest, 0);
  EXPECT_EQ(k.newest, 1);
  EXPECT_DOUBLE_EQ(k.sNewest, 1.2);
  EXPECT_DOUBLE_EQ(k.sOther, 0.4);
  EXPECT_DOUBLE_EQ(k.sFarthest, 1.2);
  EXPECT_EQ(k.useful, 2);
  EXPECT_FALSE(k.lost);
  EXPECT_FALSE(k.wanted);  // not moving
  // Beyond kLost from both: lost; beyond kUseless: not useful.
  const SurveySlot far[2] = {{true, 1, hw::session::kLost + 0.1}, {true, 2, hw::session::kUseless}};
  const auto f = surveyKeyframes(far, true, -1, 0);
  EXPECT_TRUE(f.lost);
  EXPECT_EQ(f.useful, 1);
}

TEST(KeyframeSurvey, WantedOncePastTheNewestAndReceding) {
  // Two useful keyframes, the newest nearest: wanted only when the camera is
  // past kPassedNewest from it and farther than at the last frame.
  const SurveySlot s[2] = {{true, 3, 1.0}, {true, 4, 0.3}};
  EXPECT_TRUE(surveyKeyframes(s, true, 4, 0.28).wanted);
  EXPECT_FALSE(surveyKeyframes(s, true, 4, 0.31).wanted);  // coming closer
  EXPECT_FALSE(surveyKeyframes(s, true, 3, 0.28).wanted);  // another newest last frame
  const SurveySlot close[2] = {{true, 3, 1.0}, {true, 4, 0.2}};
  EXPECT_FALSE(surveyKeyframes(close, true, 4, 0.1).wanted);  // not past kPassedNewest
}

}  // namespace
