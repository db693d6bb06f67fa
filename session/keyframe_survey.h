#pragma once
// Where a free camera stands against its two keyframes (the viewer's and the
// library's free-camera policy): which keyframe is nearest and newest in pose
// distance, whether the camera is lost (none within reach, so a keyframe is
// rendered where it stands), and whether a new keyframe ahead is wanted
// (fewer than two worth warping, or the camera has passed the newest and is
// moving away from it). Plain numbers in, no GL.

namespace hw::session {

// Pose-distance thresholds (units: FreeKeyframeOptions / the viewer's
// keyframe distance and angle, added up): a keyframe farther than kUseless is
// not warped; with none within kLost the camera is lost; a new keyframe is
// wanted once the camera is farther than kPassedNewest from the newest.
inline constexpr double kPassedNewest = 0.25;
inline constexpr double kUseless = 2.0;
inline constexpr double kLost = 1.5;

// The two keyframe slots as the policy sees them.
struct SurveySlot {
  bool valid = false;
  long serial = 0;        // build order: the highest is the newest
  double distance = 0;    // pose distance to the camera (read when valid)
};

struct KeyframeSurvey {
  int nearest = -1, newest = -1;  // slot indices; -1: no valid slot
  int useful = 0;                 // slots within kUseless
  double sNearest = 1e300, sNewest = 1e300, sOther = 1e300, sFarthest = 1e300;
  bool receding = false;  // the newest is the last survey's newest and farther now
  bool lost = true;
  bool wanted = false;
};

// `moving`: the camera moved since the last frame. `newestSerialPrev`,
// `newestDistancePrev`: the newest slot's serial and distance at the last
// frame (-1: none).
KeyframeSurvey surveyKeyframes(const SurveySlot (&slots)[2], bool moving, long newestSerialPrev,
                               double newestDistancePrev);

}  // namespace hw::session
