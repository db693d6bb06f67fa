#pragma once
// Holes drawn by the geometry renderer (WalkOptions::renderHoles), shared by
// the walk (session/walk.cpp) and the library's frames (session/
// path_frames.cpp) so that the two stay the same frames: the hole tiles
// (gapfill/hole_rects.h) as rectangles, the ones with the most holes first,
// drawn in one scissored pass and put into the frame. Buffers are kept
// between frames (no allocation once they have grown).
#include <cstdint>
#include <functional>
#include <vector>

#include "core/camera.h"
#include "core/image.h"
#include "core/result.h"
#include "gapfill/compose.h"
#include "gapfill/gl/gpu_frames.h"
#include "gapfill/hole_rects.h"
#include "keyframe/geometry_renderer.h"
#include "session/in_between.h"
#include "session/walk.h"

namespace hw::session {

// A rectangle drawn by the geometry renderer put into the frame: its pixels
// are exact (age 0, valid) and no longer a large leaf's.
void applyRendered(const keyframe::PixelRect& r, const Image<Rgba8>& colour, gapfill::Frame& frame,
                   InBetweenStep& step);

struct HolePassResult {
  int wanted = 0;        // rectangles found
  int drawn = 0;         // rectangles drawn
  long long area = 0;    // their pixels
  long long holes = 0;   // hole pixels (frame.holesBefore) among them
  long long triangles = 0;  // triangles the pass submitted
  double drawMs = 0;     // the geometry renderer's pass
};

// Which hole tiles become rectangles (WalkOptions::holeTilePx, holeRectsMax).
struct HoleTiling {
  int tilePx = 0;    // tiles of tilePx² pixels holding WalkOptions::holeTileMinPixels holes
  int maxFound = 0;  // at most this many rectangles, those with the most holes; 0 = all
};
HoleTiling holeTiling(const WalkOptions& options);

class HolePass {
 public:
  // Finds the hole rectangles of frame.holesBefore (`tiling`);
  // `maxRects(wanted)` says how many of them to draw (null: all). With `gpu`
  // (frames kept on the
  // GPU) the rectangles are copied into its current frame there, and only
  // frame.valid is updated on the CPU.
  Status run(keyframe::GeometryRenderer& renderer, const Camera& cam, gapfill::Frame& frame,
             InBetweenStep& step, const HoleTiling& tiling,
             const std::function<int(int)>& maxRects,
             HolePassResult* out, gapfill::GpuFrames* gpu = nullptr);

 private:
  std::vector<std::uint32_t> scores_;
  std::vector<gapfill::HoleRect> rects_;
  std::vector<keyframe::PixelRect> px_;
  std::vector<Image<Rgba8>> colours_;
};

}  // namespace hw::session
