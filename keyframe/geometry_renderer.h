#pragma once
// GeometryRenderer: draws a Scene at a camera with OpenGL into colour + depth
// and hands back a Keyframe (Zheng et al. 1999 §1.1). It is both the keyframe
// source and the reference/baseline renderer, so it is a fair one: one VBO/IBO
// for the scene, frustum culling by mesh and then by cluster (scenes/clusters.h),
// meshes sorted by material, no per-frame allocation. Culling never changes
// the image: clusters are runs of a mesh's triangles drawn in the mesh's own
// order, and only those with no fragment in the view are left out. Needs a
// current GL context (core/gl/context.h).
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>

#include "core/camera.h"
#include "core/result.h"
#include "keyframe/keyframe.h"
#include "keyframe/quad_mesh.h"
#include "scenes/clusters.h"
#include "scenes/scene.h"

namespace hw::keyframe {

struct RenderOptions {
  DepthMode depthMode = kDefaultDepthMode;  // fixed24 = the paper's 24-bit z-buffer
  bool frustumCulling = true;
  // Cull, and choose near geometry, by cluster; false = by whole mesh, as
  // before the scene had clusters (for comparisons).
  bool clusterCulling = true;
  scenes::ClusterOptions clusters{};  // how the scene is cut into clusters at create
  // renderKeyframe leaves out the clusters whose bounds come within this
  // distance (scene units) of the keyframe's eye: objects near the viewpoint
  // float in warped frames, so they are drawn directly instead (Zheng et al.
  // 1999 §3; renderNear). 0 = keyframes hold everything (the paper's pipeline).
  double keyframeExcludeNear = 0;
  // renderColourRect(s) draw each cluster from a simplified copy of its mesh
  // (scenes/simplify.h: the inner vertices of planar, affinely textured fans
  // removed, every outline, seam and mesh border kept; nothing moves), made
  // at create. The same surfaces, fewer and larger triangles: the pixels
  // differ only where the rasteriser's rounding does. false = the scene's
  // own triangles.
  bool simplifiedRects = false;
};

struct RenderStats {
  double drawMs = 0;      // submit + glFinish
  double readbackMs = 0;  // colour (+ depth) readback and conversion
  std::size_t meshesDrawn = 0;    // meshes with at least one triangle drawn
  std::size_t trianglesDrawn = 0;
  std::size_t clustersDrawn = 0;  // clusterCulling off: those of the meshes drawn
  std::size_t drawCalls = 0;      // runs of consecutive clusters, one draw each
};

class GeometryRenderer {
 public:
  virtual ~GeometryRenderer() = default;
  // Uploads the scene (copies what it needs; `scene` may be freed after).
  static Result<std::unique_ptr<GeometryRenderer>> create(const scenes::Scene& scene,
                                                          const RenderOptions& options = {});

  // Full keyframe: colour, z', eye z, coverage. `out` is reused when sizes match.
  virtual Status renderKeyframe(const Camera& camera, Keyframe& out, RenderStats* stats = nullptr) = 0;
  // Colour only (reference images); cheaper readback.
  virtual Status renderColour(const Camera& camera, Image<Rgba8>& out,
                              RenderStats* stats = nullptr) = 0;
  // The pixels of `rect` ([x0, x1) × [y0, y1), row 0 = top) only, the same
  // pixels renderColour gives at this camera: the scissor test is set to the
  // rectangle (only it is cleared and shaded), meshes are culled against its
  // sub-frustum (grown by a pixel), and only it is read back. `out` becomes
  // rect-sized (reused). Error for an empty rectangle or one outside the image.
  virtual Status renderColourRect(const Camera& camera, const PixelRect& rect, Image<Rgba8>& out,
                                  RenderStats* stats = nullptr) = 0;
  // With RenderOptions::simplifiedRects, from the simplified copy.
  // renderColourRect for `count` rectangles at once (outs[k] for rects[k]):
  // the same pixels, drawn in one pass (one wait for the GPU). Overlapping
  // rectangles are each drawn whole. Error as renderColourRect, before any
  // drawing. This default draws them one by one.
  virtual Status renderColourRects(const Camera& camera, const PixelRect* rects, int count,
                                   Image<Rgba8>* outs, RenderStats* stats = nullptr) {
    RenderStats total, one;
    for (int k = 0; k < count; ++k) {
      HW_TRY(renderColourRect(camera, rects[k], outs[k], &one));
      total.drawMs += one.drawMs;
      total.readbackMs += one.readbackMs;
    }
    if (stats) *stats = total;
    return {};
  }
  // renderColour and renderColourRects without the readback, for a caller
  // that keeps frames on the GPU: the image (or each rectangle of it) is
  // copied on the GPU into colour attachment 0 of GL framebuffer
  // `framebuffer` (its draw buffer is set to it), which must be a texture of
  // the camera's size (RGBA8; row 0 = bottom, so a rectangle's rows y0..y1
  // land in rows height-y1..height-y0). Errors as renderColour(Rects), and
  // for a target that is not such a framebuffer; renderers that do not draw
  // with OpenGL return one.
  virtual Status renderColourTo(const Camera& /*camera*/, unsigned /*framebuffer*/,
                                RenderStats* /*stats*/ = nullptr) {
    return makeError("this renderer does not draw with OpenGL: no image on the GPU to copy");
  }
  virtual Status renderColourRectsTo(const Camera& /*camera*/, const PixelRect* /*rects*/,
                                     int /*count*/, unsigned /*framebuffer*/,
                                     RenderStats* /*stats*/ = nullptr) {
    return makeError("this renderer does not draw with OpenGL: no image on the GPU to copy");
  }
  // Only the clusters whose bounds come within `distance` of one of `eyes`
  // (with the keyframes' eyes among them: what renderKeyframe left out of
  // those keyframes), drawn at `camera`: colour, eye z (0 where empty) and
  // coverage, to be composed into an in-between frame by depth. Its cost
  // follows the triangles of those clusters, not the size of their meshes.
  virtual Status renderNear(const Camera& camera, const glm::dvec3* eyes, int eyeCount,
                            double distance, Image<Rgba8>& colour, Image<float>& eyeZ,
                            Image<std::uint8_t>& covered, RenderStats* stats = nullptr) = 0;
  // glFlush after about `triangles` triangles of a draw (0 = one flush at the
  // end, the default), calling `afterFlush` (if set) after each. The image is
  // the same; llvmpipe then rasterises the frame in pieces, so a renderer on
  // a second context (the keyframe worker) holds the rasteriser threads both
  // contexts share for one piece at a time, and can be paced between pieces.
  // Renderers without pieces ignore it.
  virtual void setFlushEvery(std::size_t /*triangles*/, std::function<void()> /*afterFlush*/) {}
  // The triangles renderColour at `camera` would draw (RenderStats::
  // trianglesDrawn), counted on the CPU by the same culling, without drawing:
  // what a geometry frame of that view costs is predicted from it.
  virtual std::size_t visibleTriangles(const Camera& camera) const = 0;
  virtual std::size_t sceneTriangles() const = 0;
  virtual std::size_t sceneClusters() const = 0;
  virtual const RenderOptions& options() const = 0;
};

}  // namespace hw::keyframe
