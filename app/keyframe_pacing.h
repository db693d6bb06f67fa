#pragma once
// When the async viewer (`view --async-keyframes`) asks its worker for the
// next keyframe, where it places it and how fast the worker builds it. Pure
// functions, in the viewer's pose-distance units s (ViewerOptions: the
// keyframe distance and the keyframe angle each count 1) and frames.
//
// Measured (indoor, 800x600, 120 frames of --play): in the path's turns the
// viewer moves 0.5-1.0 s per frame, so a keyframe requested only after the
// viewer passed the newest one (by 0.25, the synchronous viewer's rule) and
// placed 1 s ahead had 1-2 frames before the viewer was lost (no keyframe
// within 1.5 s), while the pacing spread its build over 5 frames (half the
// path's keyframe_every) and finished it in 2.5: 5-7 stalls per run.

namespace hw::app {

// The keyframe beyond the newest one, requested early: once the viewer is
// `fraction` of the way from the older keyframe (sOlder away; a huge value
// when there is none) to the newest (sNewest away), i.e. sOlder /
// (sOlder + sNewest) >= fraction (0.5: nearer the newest; 0: at once), or
// already past the newest, the next one is requested at `spacing` beyond
// the newest (sNewest + spacing from the viewer while it approaches the
// newest, spacing - sNewest once it is past it). Returns that distance from
// the viewer, or 0 when it is not time yet or nothing is left to place.
double earlyAheadDistance(double sNewest, double sOlder, bool recedingFromNewest, double spacing,
                          double fraction);

// Running estimate of the frames between the viewer's keyframe requests:
// a shorter interval is taken at once (the viewer sped up and needs
// keyframes sooner), a longer one a quarter of the way (one slow stretch
// does not slow the worker at the next turn). estimate <= 0: none yet.
double updateRequestInterval(double estimate, double interval);

// Frames the worker spreads a keyframe over (AsyncKeyframes::
// setFramesPerKeyframe): the request interval estimate, or fewer when the
// viewer, at stepPerFrame s per frame, will be lost (no keyframe within
// reach) sooner: distanceToLost / stepPerFrame frames from now, less one
// (the keyframe is due before that frame starts, and in a turn the viewer
// is often still speeding up); in [1, maxFrames].
double workerPacingFrames(double intervalEstimate, double distanceToLost, double stepPerFrame,
                          double maxFrames);

}  // namespace hw::app
