#pragma once
// The vertices the warper (warp/gl/warper.cpp) draws for one keyframe with
// its default options — one quad per leaf (no subdivision), projective
// texcoords (u·q, v·q, q) (Zheng et al. 1999 §2.1; DESIGN.md "Backward
// warp"), the sky backdrop as rectangles at infinity — as plain floats, for
// another renderer to draw the same triangles (the web player, session/publish.h).
#include <cstdint>
#include <vector>

#include "keyframe/keyframe.h"
#include "keyframe/quad_mesh.h"

namespace hw::warp {

// Floats per vertex: position x, y, z (world; w = 1 for quads, 0 for the sky
// rectangles' directions) and texcoord s·q, t·q, q (s = u / width, t = v /
// height, row 0 = top at t = 0; q = the corner's keyframe eye depth, 1 for the sky).
constexpr int kFloatsPerWarpVertex = 6;

struct WarpVertices {
  int quads = 0;     // leaves of the mesh, 4 vertices each, first
  int skyRects = 0;  // then the sky rectangles, 4 vertices each
  // (quads + skyRects) · 4 · kFloatsPerWarpVertex floats. Corners in the
  // mesh's order (top-left, top-right, bottom-right, bottom-left of the
  // keyframe image); each quad is drawn as triangles 0-1-2, 0-2-3.
  std::vector<float> data;
};

// Rounded from double once, as the GL warper does, so both draw bit-identical
// vertex data. Precondition (checked): the keyframe and mesh share a size.
WarpVertices warpVertices(const keyframe::Keyframe& keyframe, const keyframe::QuadMesh& mesh,
                          bool skyBackdrop = true);

}  // namespace hw::warp
