#pragma once
// LOD builder: binary subdivision of the Δ buffer into rectangles planar within
// τ, and one spatial quad per leaf (Zheng et al. 1999 §1.2; DESIGN.md "Binary
// subdivision"). Corners are a least-squares plane fit of z' evaluated at the
// leaf's outer pixel edges (the paper's half-pixel expansion).
#include <cstdint>
#include <span>
#include <vector>

#include "core/camera.h"
#include "core/image.h"
#include "core/result.h"
#include "keyframe/delta_buffer.h"
#include "keyframe/keyframe.h"
#include "keyframe/quad_mesh.h"

namespace hw::keyframe {

// How a region is judged planar (DESIGN.md "Binary subdivision", the known
// weakness; "edge-strip problem").
//  Stencil:     the paper's rule: a region is planar when no pixel in it has
//               |Δ²| > τ, each pixel's stencil (eq. 3, or per axis) reaching
//               across the region's border. Every pixel beside a depth edge is
//               dirty, so each edge leaves a one-pixel strip on both sides.
//  RegionLocal: only second differences whose three pixels all lie inside the
//               region count (one-sided at its borders): Δ²ₓ at columns
//               x0+1 … x1−2 and Δ²ᵧ at rows y0+1 … y1−2. With FivePoint, the
//               5-point sum is used where both stencils are inside (the
//               region's interior), and the single-axis term where only one is
//               (its border rows resp. columns); corner pixels have neither.
//               PerAxisMax is max(|Δ²ₓ|, |Δ²ᵧ|) over the stencils inside.
//               Two guards the stencils alone cannot give:
//                - coverage: a region holding both empty and covered pixels
//                  is never a leaf (every stencil touching an empty pixel is
//                  otherwise ignored);
//                - 2-wide regions: a region 2 pixels wide (tall) has no
//                  Δ²ₓ (Δ²ᵧ) inside, and any two columns fit a plane, so one
//                  straddling a depth step would pass as a steep plane (a
//                  rubber sheet from the near surface to the far one), and
//                  one straddling a crease as a twisted one. Such a region is
//                  dirty where, in some row (column), the full stencils of
//                  both its pixels are dirty. That also splits 2-pixel-thin
//                  objects into 1-wide columns: the data cannot tell them
//                  from a step. Where a full stencil is missing (image
//                  border, empty neighbour) there is no evidence, and such a
//                  2-wide leaf may straddle a step.
//               Cuts follow the paper's rule, with "the first k lines are
//               clean" meaning "the k-line part is region-locally planar", so
//               a cut lands exactly on a step instead of one line before it.
enum class Planarity : std::uint8_t { Stencil, RegionLocal };
const char* planarityName(Planarity p);  // "stencil", "region-local"
// Parses the names above; false (and *out untouched) for anything else.
bool parsePlanarity(const char* s, Planarity* out);

struct LodOptions {
  // Threshold on |Δ²z'| in z' units (2^24 scale, eq. 2). The paper's reference
  // points are 2^11 and 2^15. Must be finite and >= 0.
  double tau = 2048.0;
  DeltaCriterion criterion = DeltaCriterion::FivePoint;
  // When > 0 it replaces `tau`: the largest parallax error, in pixels per unit
  // of camera translation (scene units), that a leaf's non-planarity may
  // cause. Converted to z' units per keyframe (see tauFromParallax). Must be
  // finite and >= 0.
  double tauParallaxPx = 0.0;
  // Planarity test of the subdivision (see Planarity). Stencil is the paper's.
  Planarity planarity = Planarity::Stencil;
  // After subdivision, merge adjacent leaves with identical spans along their
  // shared side (in particular runs of 1×1 leaves into 1×N / N×1 strips)
  // when the union is planar: the least-squares plane of z' over the union
  // departs from every pixel by at most mergeToleranceZPrime. Greedy runs
  // along y, then x, repeated while anything merges (at most 4 passes), at
  // most kMaxMergeRun leaves per run; O(L log L) in the leaf count L plus two
  // passes over the pixels. Merged leaves are not planar by the Δ² test, so
  // Quad::maxDelta of a merged quad may exceed τ.
  bool mergeStrips = false;
  // Merge tolerance in z' units; 0 = automatic: max(τ/4, kMergeNoiseFloor),
  // τ in z' units (after tauParallaxPx). τ/4 keeps merged quads as flat as
  // the Δ² test keeps leaves (a leaf with |Δ²| ≤ τ bends by up to τ/8 per
  // pixel² from its tangent plane); the floor is above the depth noise of a
  // rendered plane (NOTES-GL.md: Laplacian residual 3–11, i.e. ±2–3 per
  // pixel). Must be finite and >= 0.
  double mergeToleranceZPrime = 0.0;
  // Gradient-following tolerance ("a fixed τ measures rasteriser
  // noise"): when > 0, a pixel p is dirty when |Δ²| > τ + tauGradient·g(p),
  // g(p) the local depth gradient in z' units per pixel (see
  // computeDepthGradient). Dimensionless: extra z' tolerance per z' unit per
  // pixel of gradient. Sub-pixel vertex snapping shifts each rendered
  // triangle's plane by a fraction of a pixel, so the Laplacian's noise on a
  // plane scales with |∇z'| (NOTES-GL.md). Applies to both planarities (every
  // stencil test, including the 2-wide step guards) and to the merge's
  // 2-line step guard; the merge tolerance itself stays absolute. 0 = off:
  // results bit-identical to the fixed τ. Must be finite and >= 0.
  double tauGradient = 0.0;
  // Split a leaf whose plane does not fit its own pixels, whatever τ says:
  // the Δ² test is local (each pixel may bend by up to τ), so a large leaf
  // on a gently curved surface (a pillar beside the viewer, a dome, a rolling
  // road) can pass it while its least-squares plane departs from its pixels
  // by about τ·L²/8 for a side of L pixels, and then warps to the wrong place
  // (docs/quad-validation.md). On: a region that passes the planarity test
  // but whose pixels depart from its least-squares z' plane by more than
  // misfitToleranceZPrime, or whose plane leaves the corner depth
  // bounds at its outer pixel edges (would be clamped: a plane through two
  // pixels across a depth step, which no stencil saw at an image border or
  // beside an empty pixel), is cut in the middle, in the direction the
  // subdivision would cut next, and its parts are tested again; the merge
  // (mergeStrips) refuses such unions too, and merges within the smaller of
  // the two tolerances. Off: the paper's leaves.
  bool splitMisfit = false;
  // splitMisfit's tolerance in z' units; 0 = automatic:
  // max(τ/kMisfitTauDivisor, kMergeNoiseFloor), τ in z' units (after
  // tauParallaxPx). With τ from a parallax bound p (px per scene unit of
  // camera motion) a pixel's residual r in z' units moves it by
  // p·r/τ px per unit, so τ/20 keeps a leaf within p/20 of its pixels:
  // 0.006 px per unit at the default p = 0.125, under 1 px up to 160 units
  // of sideways motion between keyframes; motion towards a surface
  // magnifies it (docs/quad-validation.md). Must be finite and >= 0.
  double misfitToleranceZPrime = 0.0;
};

// Robust local depth gradient, z' units per pixel, into `out` (resized only
// when its size differs; no allocation otherwise). Per axis, the smaller of
// the two one-sided absolute differences (|z(x+1) − z(x)|, |z(x) − z(x−1)|),
// so that a depth step does not raise its own tolerance; one-sided where a
// neighbour is invalid (valid == 0) or off the image, 0 when both are; then
// g = max over the two axes. Invalid pixels get 0; values (an overflowing
// difference too) are capped at FLT_MAX.
void computeDepthGradient(ImageView<const double> zPrime, ImageView<const std::uint8_t> valid,
                          Image<float>* out);

// Suggested LodOptions::tauGradient (CLI --tau-gradient help): a margin
// over the smallest value that makes rendered planes clean at small τ
// (printed by tests/gl/keyframe_lod_gl_test.cpp, grazing floor).
double suggestedTauGradient();
inline constexpr double kMergeNoiseFloor = 4.0;  // z' units
inline constexpr int kMaxMergeRun = 256;         // leaves per merged run
inline constexpr double kMisfitTauDivisor = 20.0;  // automatic misfitToleranceZPrime = τ/20

// The z'-unit threshold equivalent to a parallax bound p (pixels per scene
// unit of camera motion) for this camera.
// Derivation: eq. (2) gives z' = S·f/(f−n)·(1 − n/z), so for any second
// difference Δ²z' = −S·f·n/(f−n) · Δ²(1/z). A camera translation d
// (perpendicular to the ray) moves a point at depth z by fx·d/z pixels, so the
// mismatch between a surface and its planar quad (1/z is affine on a plane,
// Δ²(1/z) measures the departure from it) is ≈ fx·d·|Δ²(1/z)| pixels. Bounding
// fx·|Δ²(1/z)| ≤ p is therefore |Δ²z'| ≤ p·S·f·n / (fx·(f−n)).
double tauFromParallax(double parallaxPx, const Camera& camera);

// Reusable builder: keeps its buffers between builds, so rebuilding a keyframe
// of the same size does not allocate (except for growth of out->quads).
//
// Subdivision (paper §1.2): start with the whole image, cut alternately in x
// (first) and y; a region 1 pixel wide in the current direction is cut in the
// other. To place a cut, scan lines from one end until a line holds an element
// with |Δ²| > τ; if the clean part is at least 1/4 of the region, cut after the
// last clean line; otherwise try from the other end; otherwise cut in the
// middle. A region is a leaf when its max |Δ²| ≤ τ, or when it is 1×1.
// Empty pixels (covered == 0, or a non-finite z') belong to no quad: they are
// never "dirty" (kDeltaEmpty), while every covered pixel next to one is
// (kDeltaDiscontinuity), so a clean region is either fully covered (a leaf) or
// fully empty (dropped). This is exactly the paper's rule applied to a depth
// buffer whose background is a constant far plane, minus the background quads.
// LodOptions::planarity and mergeStrips select the variants; with
// their defaults the result is the paper's rule, exactly as above.
class LodBuilder {
 public:
  // Whole build. Bad input returns an error and leaves *out empty:
  //  - zPrime/covered of different sizes, or not camera.width × camera.height;
  //  - an empty image (0 pixels) or one with more than 2^30 pixels;
  //  - a camera with non-finite pose, fov outside (0, π), or not 0 < near < far;
  //  - tau / tauParallaxPx / mergeToleranceZPrime / misfitToleranceZPrime /
  //    tauGradient negative or non-finite;
  //  - an unknown criterion or planarity.
  // Non-finite z' at a covered pixel is treated as empty. Every corner of the
  // result is finite, with 0 < eyeZ (see clamping in recoverCorners).
  Status build(ImageView<const double> zPrime, ImageView<const std::uint8_t> covered,
               const Camera& camera, const LodOptions& options, QuadMesh* out);
  // Same on a keyframe; its colour (and eyeZ, if non-empty) must match too.
  Status build(const Keyframe& keyframe, const LodOptions& options, QuadMesh* out);

  // Corner recovery for caller-given rectangles instead of the subdivision's
  // leaves (baselines at a matched quad count: uniform tiles, one quad per
  // pixel; see baseline_mesh.h). Same validation as build(keyframe), plus an
  // error when a rectangle is empty (x0 >= x1 or y0 >= y1), not inside the
  // image, or holds an empty pixel (covered == 0 or non-finite z'). Overlap is
  // not checked. One quad per rectangle, in the given order, with the same
  // plane fit, evaluation at the outer pixel edges and clamping as build();
  // maxDelta is the max |Δ²| over the rectangle, with Δ computed by
  // options.criterion. options.tau / tauParallaxPx cut nothing here: they are
  // only validated and reported in the stats (subdivideMs is 0). leaves()
  // then holds `rects`. On error *out is left empty.
  Status buildFromRects(const Keyframe& keyframe, std::span<const PixelRect> rects,
                        const LodOptions& options, QuadMesh* out);

  // The three steps of build(), exposed for benchmarks and tools. Call
  // prepare() first; the views must outlive the following steps.
  // prepare: validates, computes the valid mask and the Δ buffer.
  Status prepare(ImageView<const double> zPrime, ImageView<const std::uint8_t> covered,
                 const Camera& camera, const LodOptions& options);
  // subdivide: the dirty-mask summed-area table(s), the binary subdivision and
  // (mergeStrips) the merge; fills leaves(). Returns its time in ms.
  double subdivide();
  // recoverCorners: one Quad per leaf into out (resets it). Returns ms.
  double recoverCorners(QuadMesh* out);

  // Results of the last prepare()/subdivide().
  const Image<float>& delta() const { return delta_; }
  const Image<std::uint8_t>& valid() const { return valid_; }
  // computeDepthGradient of the last prepare() when tauGradient > 0 (else
  // not computed: stale or empty).
  const Image<float>& gradient() const { return grad_; }
  const std::vector<PixelRect>& leaves() const { return leaves_; }
  // Leaves before mergeStrips (equal to leaves().size() without it).
  int leavesBeforeMerge() const { return leavesBeforeMerge_; }
  // Regions that passed the planarity test but were cut by splitMisfit.
  int misfitSplits() const { return misfitSplits_; }
  double mergeToleranceZPrime() const { return mergeTol_; }
  double misfitToleranceZPrime() const { return misfitTol_; }
  double tauZPrime() const { return tauZPrime_; }

 private:
  struct Region {
    int x0, y0, x1, y1;
    bool cutX;  // direction of the next cut: true = split the x range
  };
  // Dirty pixels (|Δ²| > τ) in [x0, x1) × [y0, y1), from the summed-area table.
  std::int32_t dirtyCount(int x0, int y0, int x1, int y1) const {
    const std::int32_t* a = sat_.data() + static_cast<std::ptrdiff_t>(y0) * satStride_;
    const std::int32_t* b = sat_.data() + static_cast<std::ptrdiff_t>(y1) * satStride_;
    return b[x1] - b[x0] - a[x1] + a[x0];
  }
  template <class Clean>
  int findCut(const Region& r, bool cutX, Clean regionClean) const;
  // Region-local planarity (Planarity::RegionLocal), O(1) from the tables.
  bool cleanLocal(int x0, int y0, int x1, int y1) const;
  void buildLocalTables();
  template <bool kLocal>
  void subdivideRegions();
  void mergeLeaves();
  // splitMisfit: some pixel of r departs from r's least-squares z' plane by
  // more than misfitTol_, or the plane clamps at r's outer corners.
  bool misfit(const PixelRect& r) const;
  struct Plane {
    double a, b, c;  // z' = a + b·(x − cx) + c·(y − cy), (cx, cy) the rect's centre
  };
  Plane fitPlane(const PixelRect& r) const;
  double maxResidual(const PixelRect& r, const Plane& p, double stopAbove) const;
  // The plane z' = a + b·(x − cx) + c·(y − cy) ((cx, cy) r's centre in pixel
  // indices) leaves recoverCorners' depth bounds at one of r's outer corners.
  bool cornersClamp(const PixelRect& r, double a, double b, double c) const;

  ImageView<const double> zPrime_;
  Camera camera_;
  LodOptions options_;
  double tauZPrime_ = 0;
  double mergeTol_ = 0;
  double misfitTol_ = 0;
  int leavesBeforeMerge_ = 0;
  int misfitSplits_ = 0;
  double deltaMs_ = 0;
  long long emptyPixels_ = 0;
  Image<std::uint8_t> valid_;
  Image<float> delta_;
  Image<float> grad_;  // depth gradient g(p), only when tauGradient > 0
  // The threshold at pixel index i (y·w + x): τ + tauGradient·g.
  double tauAt(std::ptrdiff_t i) const {
    return tauZPrime_ + options_.tauGradient * static_cast<double>(grad_.data()[i]);
  }
  std::vector<std::int32_t> sat_;  // (w+1)×(h+1) prefix counts of dirty pixels
  std::ptrdiff_t satStride_ = 0;
  // Region-local tables, (w+1)×(h+1) prefix counts each: valid pixels; dirty
  // interior (both stencils), x-only and y-only pixels; pairs (x, x+1) resp.
  // (y, y+1) whose full stencils are both dirty.
  enum LocalTable { kValid, kInner, kOnlyX, kOnlyY, kStepX, kStepY, kLocalTables };
  std::int32_t localCount(LocalTable t, int x0, int y0, int x1, int y1) const {
    if (x0 >= x1 || y0 >= y1) return 0;
    const std::int32_t* s = local_[t].data();
    const std::int32_t* a = s + static_cast<std::ptrdiff_t>(y0) * satStride_;
    const std::int32_t* b = s + static_cast<std::ptrdiff_t>(y1) * satStride_;
    return b[x1] - b[x0] - a[x1] + a[x0];
  }
  std::vector<std::int32_t> local_[kLocalTables];
  std::vector<std::int8_t> stateX_, stateY_;  // per pixel: 0 clean, 1 dirty, 2 missing
  std::vector<std::uint8_t> innerDirty_;      // per pixel: dirty with both stencils
  // A leaf with its least-squares plane z' = a + b·(x − cx) + c·(y − cy),
  // (cx, cy) its centre in pixel indices, and max |z' − plane| (or a bound).
  struct MergeLeaf {
    PixelRect r;
    double a, b, c, resid;
  };
  std::vector<MergeLeaf> merge_, mergeOut_;
  std::vector<Region> stack_;
  std::vector<PixelRect> leaves_;
  bool prepared_ = false;
};

// One-shot conveniences (allocate a builder each call).
Result<QuadMesh> buildQuadMesh(const Keyframe& keyframe, const LodOptions& options);
Result<QuadMesh> buildQuadMesh(ImageView<const double> zPrime,
                               ImageView<const std::uint8_t> covered, const Camera& camera,
                               const LodOptions& options);

}  // namespace hw::keyframe
