#pragma once
// Which quads of one keyframe show surfaces another keyframe also sees — the
// background-layer cull . In the paper's overlay (§2.2 (i))
// the background layer only shows where the foreground layer left pixels
// empty; those are surfaces the foreground keyframe did not see (hidden
// behind something, or outside its view). A background quad whose surface
// the foreground keyframe sees is drawn under foreground pixels and can be
// left out. CPU only.
#include <cstdint>
#include <vector>

#include "keyframe/keyframe.h"
#include "keyframe/quad_mesh.h"

namespace hw::warp {

struct SeenOptions {
  // A sample counts as seen when the seer pixel it projects into holds a
  // depth within this fraction of the sample's own depth along the seer's
  // view direction, and its four neighbours within 4× this (not at a
  // silhouette of the seer's view).
  double relTolerance = 0.005;
  // Besides each leaf's four corner pixels, its pixels on a grid of this step
  // are sampled (so a small occluder in front of a big quad is noticed).
  int gridStepPx = 4;
};

// seen[i] = 1 when every sampled pixel of quad i of `mesh` (keyframe `own`'s
// mesh; samples at its corner pixels and on the grid, each lifted to the
// world with `own`'s depth) projects inside `seer`'s image, in front of its
// eye, onto a surface `seer` drew at that depth. Empty samples (uncovered in
// `own`) never make a quad unseen. Resizes `seen` to mesh.quads.size().
void quadsSeenBy(const keyframe::Keyframe& own, const keyframe::QuadMesh& mesh,
                 const keyframe::Keyframe& seer, const SeenOptions& options,
                 std::vector<std::uint8_t>& seen);

}  // namespace hw::warp
