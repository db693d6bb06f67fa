#pragma once
// Δ buffer: the second-order difference of the depth buffer z' (Zheng et al.
// 1999 §1.2, eq. 3). Zero on any plane, because z' (eq. 2) is affine in pixel
// coordinates there; the LOD builder cuts the image where |Δ²z'| > τ.
#include <cstdint>
#include <limits>

#include "core/image.h"

namespace hw::keyframe {

// Which second difference is thresholded (DESIGN.md "Δ buffer").
//  FivePoint:  |4z'(i,j) − z'(i−1,j) − z'(i+1,j) − z'(i,j−1) − z'(i,j+1)|, eq. (3).
//              Cancels on a saddle (curving up in x, down in y).
//  PerAxisMax: max(|Δ²ₓz'|, |Δ²ᵧz'|) with Δ²ₓz' = 2z'(i,j) − z'(i−1,j) − z'(i+1,j);
//              cannot cancel, but is smaller than FivePoint where both share a sign.
enum class DeltaCriterion : std::uint8_t { FivePoint, PerAxisMax };
const char* deltaCriterionName(DeltaCriterion c);  // "five-point", "per-axis-max"
// Parses the names above; false (and *out untouched) for anything else.
bool parseDeltaCriterion(const char* s, DeltaCriterion* out);

// Value written at EMPTY pixels (covered == 0). Negative, so it is never above
// any threshold τ ≥ 0 and is distinguishable from every real |Δ²| (≥ 0). The
// builder relies on empty pixels never being "dirty": see lod_builder.h.
inline constexpr float kDeltaEmpty = -1.0f;
// Value written at a covered pixel whose stencil touches an empty neighbour
// (a silhouette: a discontinuity), or whose Δ² is not finite.
inline constexpr float kDeltaDiscontinuity = std::numeric_limits<float>::infinity();

// Computes |Δ²z'| per pixel into `out` (z' units, float).
//  zPrime:  z' in 2^24 units (eq. 2), any stride.
//  covered: nonzero where something was drawn; same size as zPrime (checked).
//  out:     same size as zPrime (checked); written in full. No allocation.
// Image borders: a neighbour outside the image is extrapolated linearly, i.e.
// the second difference along that axis is 0, so a plane touching the border
// stays planar (and a 1-wide image has Δ²ₓ = 0 everywhere).
// Empty pixels get kDeltaEmpty; a covered pixel with an empty neighbour in its
// stencil, or whose result is NaN/±inf (non-finite or overflowing z' in its
// stencil), gets kDeltaDiscontinuity. The output therefore never holds NaN.
void computeDeltaBuffer(ImageView<const double> zPrime, ImageView<const std::uint8_t> covered,
                        DeltaCriterion criterion, ImageView<float> out);

// Convenience: resizes *out to zPrime's size only when it differs.
void computeDeltaBuffer(ImageView<const double> zPrime, ImageView<const std::uint8_t> covered,
                        DeltaCriterion criterion, Image<float>* out);

}  // namespace hw::keyframe
