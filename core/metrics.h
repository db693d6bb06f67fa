#pragma once
// Image-quality metrics of a frame against the geometry renderer's reference
// (DESIGN.md "What is measured"): MSE per channel, PSNR, SSIM (Wang et al.
// 2004), hole fraction, and the diff/side-by-side strips written for reports.
#include <cstdint>
#include <vector>

#include "core/file_io.h"
#include "core/image.h"

namespace hw {

// Contract shared by every comparison below: the two images (and the mask,
// where one is given) must have the same width and height; a mismatch is a
// precondition failure (HW_CHECK aborts with both sizes). Alpha is ignored;
// R, G, B are compared on the 0–255 scale. A mask selects the pixels where it
// is != 0.

// Mean squared error per channel, 0–255 scale (as the Rail-Track viewer's
// table reports). Sums are exact (64-bit integers).
struct ChannelMse {
  double r = 0, g = 0, b = 0;
  double mean() const { return (r + g + b) / 3.0; }
};

// Per-channel MSE over all pixels (0 for empty images), or over the masked
// pixels (NaN in every channel when the mask selects none).
ChannelMse channelMse(const Image<Rgba8>& a, const Image<Rgba8>& b);
ChannelMse channelMse(const Image<Rgba8>& a, const Image<Rgba8>& b,
                      const Image<std::uint8_t>& mask);

// Overall MSE: the mean over pixels and over R, G, B (= channelMse().mean()).
double mse(const Image<Rgba8>& a, const Image<Rgba8>& b);
double mse(const Image<Rgba8>& a, const Image<Rgba8>& b, const Image<std::uint8_t>& mask);

// PSNR in dB with peak 255: 10·log10(255² / MSE), MSE as in mse().
// Identical images (MSE 0) give +inf; reports that cannot hold inf use
// psnrCapped. An empty mask gives NaN.
constexpr double kPsnrPeak = 255.0;
double psnrFromMse(double mse);
double psnr(const Image<Rgba8>& a, const Image<Rgba8>& b);
double psnr(const Image<Rgba8>& a, const Image<Rgba8>& b, const Image<std::uint8_t>& mask);
// min(psnr, capDb): identical images report capDb (99 dB by default). NaN stays NaN.
double psnrCapped(const Image<Rgba8>& a, const Image<Rgba8>& b, double capDb = 99.0);
double psnrCapped(const Image<Rgba8>& a, const Image<Rgba8>& b, const Image<std::uint8_t>& mask,
                  double capDb = 99.0);

// SSIM of Wang, Bovik, Sheikh & Simoncelli 2004 (eq. 13) on Rec.601 luma
// Y = 0.299 R + 0.587 G + 0.114 B (not rounded to integers), with their
// standard parameters: an 11×11 circular-symmetric Gaussian window, σ = 1.5,
// weights normalised to sum 1; K1 = 0.01, K2 = 0.03, L = 255. The result is
// the mean SSIM over all "valid" windows, i.e. those lying entirely inside the
// image ((W−10)·(H−10) of them); no automatic down-sampling (unlike the
// authors' later MATLAB script). Identical images give exactly 1; values lie
// in [−1, 1]. Precondition (checked): same size, both sides ≥ 11 pixels.
// Separable filtering in float over a rolling 11-row buffer: O(W·H) memory
// traffic, a few ms at 512².
constexpr int kSsimWindow = 11;
constexpr double kSsimSigma = 1.5;
double ssim(const Image<Rgba8>& a, const Image<Rgba8>& b);
// What readPng must accept for images these metrics compare (`compare`):
// sides of at least kSsimWindow.
inline ImageLimits metricImageLimits() {
  ImageLimits l;
  l.minSide = kSsimWindow;
  l.minSideReason = " (SSIM needs an 11x11 window)";
  return l;
}

// Fraction of pixels where mask != 0, in [0, 1]; 0 for an empty mask.
double holeFraction(const Image<std::uint8_t>& mask);

// |a − b| per channel × gain, clamped to 255, opaque (alpha 255): the "diff"
// image of report strips (gain 4 makes a 16-level error clearly visible).
// Precondition: same size, gain ≥ 0.
Image<Rgba8> diffImage(const Image<Rgba8>& a, const Image<Rgba8>& b, int gain = 4);

// Images side by side, left to right, separated by gapPx columns of
// gapColour. Precondition (checked): at least one image, none null, all of
// equal height, gapPx ≥ 0. Width = Σ widths + gapPx·(count − 1).
Image<Rgba8> hstack(const std::vector<const Image<Rgba8>*>& images, int gapPx,
                    Rgba8 gapColour = Rgba8{255, 255, 255, 255});

// on where mask != 0, off elsewhere (for hole-mask strips).
Image<Rgba8> maskToImage(const Image<std::uint8_t>& mask, Rgba8 on, Rgba8 off);

}  // namespace hw
