#pragma once
// A copy of a run of a mesh's triangles with fewer, larger triangles, for
// passes that may draw the same surfaces triangulated otherwise (the hole
// pass: keyframe/geometry_renderer.h, RenderOptions::simplifiedRects).
//
// Vertices are removed by half-edge collapses (a vertex merged into one of
// its neighbours), so the result indexes the mesh's own vertices and needs
// no vertex buffer of its own. Only vertices inside a closed, consistently
// oriented fan of the given triangles are removed: vertices on the run's
// border, on the mesh's open edges, on texture or normal seams
// (split vertices) and on non-manifold edges stay, so neighbouring runs
// still meet edge to edge (no crack or T-junction) and every outline stays
// where it was. A collapse is taken only when
// - the removed vertex's normal and its neighbours' agree within
//   `normalCos` (shading keeps what it interpolated),
// - the texture coordinates are affine in the position over the removed
//   vertex's fan, within `uvTolerance` (any triangulation of the fan then
//   maps the texture as before),
// - no triangle of the fan flips or becomes degenerate,
// - the vertex it merges into keeps at most 64 neighbours (bounded work on
//   large flat meshes), and
// - the surface moves by at most `maxError` (scene units), counted
//   conservatively: the moved vertex's distance to the planes it leaves,
//   the removed vertex's distance to the new triangles, added up over the
//   collapses that touched a vertex.
// On a planar region with texture coordinates affine in the position (the
// built-in scenes, most brush geometry) every inner vertex can go at error 0.
#include <cstdint>
#include <vector>

#include "scenes/scene.h"

namespace hw::scenes {

struct SimplifyOptions {
  double maxError = 0;         // scene units; 0 = only collapses that move nothing
  double normalCos = 0.9998;   // about 1.1°
  double uvTolerance = 1e-4;   // in texture coordinates (a texel of 4096 is 2.4e-4)
};

struct SimplifiedTriangles {
  std::vector<std::uint32_t> indices;  // into the mesh's vertices, 3 per triangle
  std::vector<std::uint32_t> source;   // per triangle: the mesh triangle whose place it took
  std::vector<float> error;            // per triangle: the bound at its corners, scene units
  double maxError = 0;                 // the largest of them (≤ SimplifyOptions::maxError)
};

// The triangles [firstTriangle, firstTriangle + triangleCount) of `mesh`
// simplified, cheapest collapse first. Each survivor is one of the mesh's
// triangles with corners moved, listed in the mesh's order (`source`
// increases); triangles with a repeated index (no area) are left out.
// Indices out of the mesh's range must not occur (GeometryRenderer::create
// checks first).
SimplifiedTriangles simplifyTriangles(const Mesh& mesh, std::uint32_t firstTriangle,
                                      std::uint32_t triangleCount, const SimplifyOptions& options);

}  // namespace hw::scenes
