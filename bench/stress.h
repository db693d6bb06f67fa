#pragma once
// Stress suite: depth precision of the three depth modes across
// far/near ratios and viewing angles on an analytic plane, and degenerate or
// extreme cameras pushed through the whole hybrid pipeline (keyframe → Δ²z'
// LOD mesh → backward warp → composition, Zheng et al. 1999 §1–2). Each
// measurement is a plain function returning a row, so the GL test and the
// `hybridwalk stress` report run the same code.
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/camera.h"
#include "core/result.h"

namespace hw::bench {

struct StressOptions {
  std::string outDir;  // required; stress.json, CSVs, PNG plots, index.html
  // Quick: 256² depth-precision images and no 4096×4096 case. Full: 512².
  // Degenerate cases run in all three depth modes either way.
  bool quick = false;
  bool progress = true;  // a progress line on stderr
  std::string glRenderer, glVersion;  // recorded in the machine block
};

// Runs both parts and writes the report. A GL context must be current.
// Returns the stress.json document. Errors: output directory, GL failures
// outside the cases (a case's own failure is a row with ok = false).
Result<nlohmann::json> runStress(const StressOptions& options);

// ---- Part 1: depth precision on a plane ------------------------------------

// Geometry (all lengths relative to the near plane n = 0.1): far f = ratio·n;
// a 64×64-cell textured plane, half-size 2f (its edges are never in view);
// the camera looks at it with `angleDeg` between the view direction and the
// plane's (negated) normal, the centre ray meeting it at distance f/4 — the
// far part of the range, where a scene with that ratio has its distant
// content and where z' is most compressed. Keyframes A and B are at ±2.5 %
// of that distance sideways; the in-between frame is at the midpoint.
struct DepthPrecisionSpec {
  DepthMode mode = DepthMode::Fixed24;
  double farNearRatio = 1e3;  // > 1
  double angleDeg = 0;        // [0, 89]
  int size = 512;             // square images, >= 16
  double tau = 2048.0;        // z' units (the paper's 2^11)
};

struct DepthPrecisionRow {
  DepthPrecisionSpec spec;
  // |Δ²z'| (eq. 3, z' units) over pixels whose 5-point stencil lies on the
  // plane (all five covered and inside the image), keyframes A and B pooled.
  double noiseP99 = 0, noiseMax = 0;
  long long noisePixels = 0;
  double quads = 0;          // mean quads per keyframe (A, B) at spec.tau
  int clampedCorners = 0;    // summed over A and B
  // Corner reprojection, px: each corner's world point as shipped to the GPU
  // (float) projected with its keyframe camera, against its pixel corner.
  double cornerReprojMaxPx = 0;
  double cornerReprojMaxPxDouble = 0;  // the same with the double corners
  // |corner − analytic ray–plane intersection at that pixel corner| divided by
  // the intersection's distance from the eye; corners whose ray misses the
  // plane (past the horizon) are counted apart. "Fitted": corners of leaves
  // at least 2×2, whose z' plane is a least-squares fit; the others (1×1 and
  // 1×N strips, mostly along the far-clip edge) have no slope across and are
  // off by up to the depth change over a pixel whatever the depth mode.
  double worldRelErrP50 = 0, worldRelErrP99 = 0, worldRelErrMax = 0;
  double fittedRelErrP50 = 0, fittedRelErrP99 = 0, fittedRelErrMax = 0;
  int cornersPastHorizon = 0;
  double coveredFraction = 0;          // of keyframe A's pixels, as read back
  double expectedCoveredFraction = 0;  // pixels whose centre ray meets the plane in (n, f)
  double psnr = 0;             // in-between frame vs the geometry reference (capped 99)
  double holeFraction = 0;     // before the fallback
  double ms = 0;
};

// Renders and measures one configuration. Needs a current GL context.
Result<DepthPrecisionRow> measureDepthPrecision(const DepthPrecisionSpec& spec);

// ---- Part 2: degenerate and extreme cameras --------------------------------

// One case: a valid frame (no NaN/Inf in z', eye z, quad corners or layer
// depth; every hole filled by the fallback; case checks hold) or a clear
// error, never a crash or hang.
struct StressCaseRow {
  std::string name;
  bool ok = false;
  std::string message;      // what was checked / what went wrong
  double holes = 0;         // hole fraction before the previous-frame fallback
  double psnr = 0;          // vs the geometry reference (capped 99; NaN if none)
  long long nanCount = 0;   // non-finite values found in any buffer or corner
  double ms = 0;            // wall time of the case
  bool expectError = false; // the case passes by returning a clear error
};

struct StressCaseOptions {
  DepthMode depthMode = DepthMode::Fixed24;
  bool quick = true;  // smaller images where the case allows it
  // When set, each case writes its frame, reference and foreground layer as
  // DIR/<slug>_{frame,reference,layer}.png (images of at most 1024² only).
  std::string imageDir;
};

// The case name as a file name: lower-case letters, digits and '_'.
std::string stressCaseSlug(const std::string& name);

struct StressCase {
  std::string name;
  bool slow = false;  // skipped in quick runs (4096×4096)
  std::function<StressCaseRow(const StressCaseOptions&)> run;
};

// The catalogue, in report order: in-between eye equal to a keyframe eye;
// both keyframes at one eye; a 180° turn; eye inside a box; geometry across
// the near plane; fov 1° and 170°; 1×1, 1×4096, 4096×1 and 4096×4096 images;
// keyframes whose views do not overlap; quads entirely behind the eye (and
// straddling it) clipped, never drawn as inverted sheets. Each needs a
// current GL context.
const std::vector<StressCase>& stressCases();

// Runs every case (skipping slow ones when quick) and returns the rows.
std::vector<StressCaseRow> runStressCases(const StressCaseOptions& options,
                                          bool includeSlow = false);

}  // namespace hw::bench
