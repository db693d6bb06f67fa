#pragma once
// How each frame is drawn: by the geometry renderer, or by warping keyframes
// (a keyframe frame shows its keyframe; an in-between frame warps the two
// around it). With FrameMode::Auto a ModeChooser picks, per keyframe segment,
// whichever is predicted cheaper from costs measured in this run, so a scene
// that draws faster than it warps builds no keyframes at all.
#include <array>
#include <cstddef>
#include <string>

namespace hw::session {

// What the user asks for (`--mode`).
enum class FrameMode {
  Auto,      // per segment, the cheaper of geometry and warping (geometry when about even)
  Hybrid,    // every frame warped or a keyframe (the paper's pipeline; studies)
  Geometry,  // every frame drawn by the geometry renderer; no keyframes
};
const char* frameModeName(FrameMode m);
bool parseFrameMode(const std::string& s, FrameMode* out);  // "auto", "hybrid", "geometry"

// How one frame was drawn (report.json frames[].mode).
enum class FrameKind : char { Geometry = 0, Warp = 1, Keyframe = 2 };
const char* frameKindName(FrameKind k);  // "geometry", "warp", "keyframe"

struct ModeChooserOptions {
  // Warping starts when its predicted cost per frame is below enterBelow x
  // the geometry frame's, and stops when it rises above leaveAbove x. Both
  // below 1: at about equal cost the geometry (exact) is kept, and the gap
  // between them keeps the choice from flipping every segment.
  double enterBelow = 0.75;
  double leaveAbove = 0.9;
  // And the slow in-between frames: warping starts only while the
  // tailQuantile of the recent in-between frames is below tailEnterBelow x
  // the geometry frame's, and stops above tailLeaveAbove x. A scene where
  // warping saves a little on average but its slower frames (a keyframe
  // built alongside on the same cores, an upload) cost more than drawing is
  // drawn as geometry: warping must not make frames slower.
  double tailQuantile = 0.9;
  double tailEnterBelow = 1.0;
  double tailLeaveAbove = 1.1;
  // A warped segment whose first giveUpAfter in-between frames each cost
  // more than tailLeaveAbove x the geometry frame is given up: its other
  // frames are drawn as geometry (the keyframes' cost is already paid, the
  // warps' is not). The prediction that started it was wrong (say, an
  // optimistic calibration, or a keyframe built on the same cores); without
  // this, one such segment alone is over 5 % of a 120-frame walk. 0 = never.
  int giveUpAfter = 2;
  // The geometry cost the choice (and the hole budget) compares against:
  // the median of the last geometryRecent geometry samples of the kWindow
  // kept. A view that grows heavier (a room opening up ahead) makes the
  // next segment warp one segment after it shows, not after the median of
  // the whole window has caught up; the median of a few still ignores one
  // slow frame. kWindow: the whole window.
  std::size_t geometryRecent = 5;
  // The geometry cost of the view being decided, predicted from the
  // triangles it draws (GeometryRenderer::visibleTriangles) and the kWindow
  // geometry samples kept with their own triangle counts: interpolated
  // between the samples nearest below and above in triangles; above them in
  // proportion to the nearest, below them half its cost fixed and half in
  // proportion. A heavy stretch of the walk then no longer stands for the
  // lighter views after it (the samples keep their triangle counts), and a
  // view that grows heavier is seen before it is drawn.
  // false, or no triangle counts: the median of the last geometryRecent.
  bool geometryByTriangles = true;
};

// Predicts whether warping a segment of F frames (one keyframe frame and F-1
// in-between frames) costs less per frame than drawing those frames as
// geometry. Costs are the medians of the last kWindow samples of each kind
// (ms of frame work at the walk's resolution); the geometry's is the view's,
// from its triangles (ModeChooserOptions::geometryByTriangles), else the
// median of its last geometryRecent. Allocation-free.
class ModeChooser {
 public:
  static constexpr std::size_t kWindow = 15;
  explicit ModeChooser(ModeChooserOptions options = {}) : opt_(options) {}

  // A geometry render + readback, of a view drawing `triangles` (< 0: not known).
  void addGeometryMs(double ms, double triangles = -1) { geometry_.add(ms, triangles); }
  void addInBetweenMs(double ms);  // an in-between frame's work
  void addKeyframeMs(double ms) { keyframe_.add(ms); }    // a keyframe frame's work
  // A lower bound on an in-between frame's work (a one-quad warp, measured
  // before any keyframe exists): the in-between estimate until one is measured.
  void setWarpFloorMs(double ms) { floorMs_ = ms; }

  // The view the next choice is for draws `triangles` (< 0: not known).
  void setViewTriangles(double triangles) { viewTriangles_ = triangles; }
  double viewTriangles() const { return viewTriangles_; }
  // What the choice (and the hole budget) uses: geometryAtTriangles of the
  // view when options().geometryByTriangles and both are known, else
  // geometryRecentMs(). NaN: no sample yet.
  double geometryMs() const;
  // The median of the last options().geometryRecent geometry samples.
  double geometryRecentMs() const { return geometry_.quantile(0.5, opt_.geometryRecent); }
  double geometryWindowMs() const { return geometry_.median(); }  // of all kWindow kept
  // A geometry frame's ms for a view of `triangles`, from the samples kept
  // with triangle counts (ModeChooserOptions::geometryByTriangles). Samples
  // within 2 % of the nearest count on a side count as one, their median.
  // NaN: no such sample, or triangles < 0.
  double geometryAtTriangles(double triangles) const;
  double inBetweenMs() const;  // measured median, else the floor; NaN: neither
  bool inBetweenMeasured() const { return inBetween_.n > 0; }  // not just the floor
  // The options' tailQuantile of the recent in-between frames, else the floor.
  double inBetweenTailMs() const;
  // ms per frame of a warped segment of `framesPerSegment` (>= 1) frames: the
  // keyframe frame counts as measured, or as a geometry frame until one is.
  // NaN while the geometry or the in-between cost is unknown.
  double predictedWarpMs(double framesPerSegment) const;
  // Whether the next segment is warped, given whether this one is. Unknown
  // costs keep the current choice.
  bool warpNext(bool warpingNow, double framesPerSegment) const;
  // A segment starts: giveUp() counts its in-between frames from here.
  void startSegment();
  // Whether the warped segment under way should be given up
  // (ModeChooserOptions::giveUpAfter).
  bool giveUp() const;
  const ModeChooserOptions& options() const { return opt_; }

 private:
  struct Window {
    std::array<double, kWindow> v{};
    std::array<double, kWindow> tri{};  // the sample's triangles (< 0: not known)
    std::size_t n = 0, next = 0;
    void add(double ms, double triangles = -1);
    double median() const { return quantile(0.5); }
    // q in [0, 1], over the last `last` samples (all kept, at most kWindow);
    // NaN when empty.
    double quantile(double q, std::size_t last = kWindow) const;
  };
  ModeChooserOptions opt_;
  Window geometry_, inBetween_, keyframe_;
  double floorMs_ = -1;
  double viewTriangles_ = -1;
  int segmentFrames_ = 0;        // in-between frames since startSegment()
  double segmentMinMs_ = 0;      // the cheapest of them
};

}  // namespace hw::session
