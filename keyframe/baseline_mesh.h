#pragma once
// Baseline quad meshes to compare the LOD builder with at a matched quad count:
// the Rail-Track viewer's uniform quad mesh with empty-tile removal (Yang &
// Crawfis, §"quad-mesh"/"empty tiles") and one quad per pixel (post-rendering
// warping). Corners come from LodBuilder::buildFromRects, i.e. the same plane
// fit and clamping as the Zheng et al. 1999 leaves.
#include "core/result.h"
#include "keyframe/keyframe.h"
#include "keyframe/lod_builder.h"
#include "keyframe/quad_mesh.h"

namespace hw::keyframe {

// Uniform tiles of tileSize × tileSize pixels from the top-left corner (the
// last column/row of tiles is narrower/shorter when the size does not divide
// the image). Empty pixels (covered == 0 or non-finite z') belong to no quad:
//  - a fully covered tile is one quad;
//  - a fully empty tile is removed (the Rail-Track viewer's empty-tile removal);
//  - a mixed tile becomes the maximal horizontal runs of covered pixels in each
//    of its rows, with runs of consecutive rows that have the same x range
//    merged into one rectangle.
// So the covered pixels are tiled exactly once. A tile that is not planar still
// gets one plane fit: that is what a uniform mesh does.
// `builder` (optional) is reused to avoid allocations; `options` only chooses
// the Δ criterion of the reported maxDelta (and is validated).
// Errors: tileSize < 1, or anything LodBuilder::build(keyframe) rejects.
Result<QuadMesh> buildUniformTiles(const Keyframe& keyframe, int tileSize,
                                   LodBuilder* builder = nullptr, const LodOptions& options = {});

// One 1×1 quad per covered pixel, in row-major order (the mesh of
// post-rendering warping). The fit over one pixel is constant z', as for 1×1
// leaves of the LOD builder. Errors: as LodBuilder::build(keyframe).
Result<QuadMesh> buildPerPixel(const Keyframe& keyframe, LodBuilder* builder = nullptr,
                               const LodOptions& options = {});

// Quad count of buildUniformTiles(keyframe, tileSize) without recovering
// corners. Preconditions (checked): zPrime and covered of the same, non-zero
// size; tileSize >= 1.
long long uniformTileQuadCount(const Keyframe& keyframe, int tileSize);

// The tile size in [1, max(width, height)] whose uniform-tile quad count is
// closest to targetQuads; ties go to the smallest size. Evaluates every size
// (the count is not monotone in the size), in O(w·h + Σ over sizes of tiles
// and of runs in mixed tiles). Preconditions as uniformTileQuadCount.
int tileSizeForQuadCount(const Keyframe& keyframe, long long targetQuads);

}  // namespace hw::keyframe
