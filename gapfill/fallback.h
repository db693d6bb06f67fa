#pragma once
// What fills the pixels neither keyframe layer covers. The paper (Zheng et
// al. 1999 §2.2) copies the same pixel of the previous frame, which is right
// only while the camera barely moves; the reprojected fallback forward-warps
// the previous composed frame to the current camera with its depth (one
// point per pixel, z-buffered; cf. Mark, McMillan & Bishop 1997), and copies
// the same pixel only where that leaves nothing.
#include "core/camera.h"
#include "gapfill/compose.h"
#include "warp/layer.h"

namespace hw::gapfill {

enum class Fallback {
  Copy,       // the paper's: the same pixel of the previous frame
  Reproject,  // the previous frame reprojected with its depth, else Copy
};
const char* fallbackName(Fallback f);  // "copy", "reproject"
// False (and *out unchanged) for an unknown name or null s.
bool parseFallback(const char* s, Fallback* out);

// previous.colour at previous.eyeZ (along previous.camera's W; 0 = unknown:
// skipped; >= kSkyEyeZ / 2 = at infinity: moved by the rotation only) seen
// from `target`: each valid pixel's centre is projected into target and
// written to the pixel it lands in when it is nearer than what is there.
// Then one pass closes cracks: an empty pixel with at least 4 of its 8
// neighbours written takes the nearest of them (only where `wanted`, if
// given, is 0: the pixels a frame still has to fill, its `valid`).
// out.colour, .valid (non-zero = written: 1 projected, 2 crack) and .eyeZ
// (along target's W; meaningless where valid = 0) have target's size;
// out.camera = target; the other members of `out` are not touched.
// Preconditions (checked): previous's colour, valid and eyeZ have one size;
// wanted (if given) has target's size; &previous != &out. Allocation-free
// once `out` has target's size.
void reprojectFrame(const Frame& previous, const Camera& target, Frame& out,
                    const Image<std::uint8_t>* wanted = nullptr);

struct FillStats {
  int reprojected = 0;  // pixels filled from the reprojected frame
  int copied = 0;       // pixels filled from the same pixel of samePixel
};

// Fills the pixels of `out` left unfilled (valid = 0) from `reprojected`
// where it is valid, else from the same pixel of `samePixel` (null: none)
// where that is valid. Sets their colour, valid = 1, eyeZ (when out.eyeZ has
// out's size: the reprojected depth, or 0 for a copied pixel), and updates
// fromPrevious, unfilled and holeFractionAfter. holesBefore is not touched.
// Preconditions (checked): reprojected (colour, valid, eyeZ) and samePixel
// (colour, valid) have out's size.
FillStats fillHoles(const Frame& reprojected, const Frame* samePixel, Frame& out);

// out.eyeZ (resized to the layers' size) for a frame composed from these
// layers: per pixel the foreground's eye z where only it covers (or where
// both cover and !nearer), the background's where only it covers, the nearer
// of the two where both cover and `nearer` (the depth merge and the blend),
// else 0. Preconditions (checked): each given layer's coverage and eyeZ have
// the foreground colour's size.
void layerDepth(const warp::Layer& foreground, const warp::Layer* background, bool nearer,
                Frame& out);

}  // namespace hw::gapfill
