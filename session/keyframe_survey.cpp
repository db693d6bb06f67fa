#include "session/keyframe_survey.h"

#include <algorithm>

namespace hw::session {

KeyframeSurvey surveyKeyframes(const SurveySlot (&slots)[2], bool moving, long newestSerialPrev,
                               double newestDistancePrev) {
  KeyframeSurvey k;
  double s[2] = {1e300, 1e300};
  for (int i = 0; i < 2; ++i) {
    if (!slots[i].valid) continue;
    s[i] = slots[i].distance;
    if (s[i] < k.sNearest) k.nearest = i, k.sNearest = s[i];
    if (k.newest < 0 || slots[i].serial > slots[k.newest].serial) k.newest = i;
    if (s[i] < kUseless) ++k.useful;
  }
  if (k.newest >= 0) {
    k.sNewest = s[k.newest];
    k.sOther = s[1 - k.newest];
  }
  k.sFarthest = std::max(s[0], s[1]);
  k.receding =
      k.newest >= 0 && slots[k.newest].serial == newestSerialPrev && k.sNewest > newestDistancePrev;
  k.lost = k.nearest < 0 || k.sNearest > kLost;
  k.wanted = moving && (k.useful < 2 ||
                        (k.nearest == k.newest && k.sNewest > kPassedNewest && k.receding));
  return k;
}

}  // namespace hw::session
