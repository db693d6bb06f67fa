#pragma once
// Backward warping (Zheng et al. 1999 §2.1): a keyframe's quad mesh, textured
// with the keyframe image, drawn from a new camera into a Layer. Texture
// coordinates are projective — each corner carries (u·q, v·q, q), q its depth in
// the keyframe camera, divided per fragment (textureProj) — which reproduces
// Q = H_{E'}⁻¹ H_E P exactly on planar quads (DESIGN.md "Backward warp").
#include <memory>

#include "core/camera.h"
#include "core/result.h"
#include "keyframe/keyframe.h"
#include "keyframe/quad_mesh.h"
#include "warp/layer.h"

namespace hw::warp {

enum class TexcoordMode {
  Projective,  // (u·q, v·q, q): exact for planar quads (default)
  Affine,      // plain (u, v) with perspective-correct interpolation (for comparison)
};
const char* texcoordModeName(TexcoordMode m);

// Subdivision of large near quads at upload (Zheng et al. 1999 §2.1: "such
// quadrangles should be subdivided adaptively. At present, however, a uniform
// subdivision is performed").
enum class Subdivision {
  None,      // one quad per leaf (default)
  Uniform,   // the paper's: every quad cut into cells of subdivideCellPx
  Adaptive,  // only quads at least 2 cells wide or high whose depth varies:
             // corner eye-z ratio ≥ subdivideDepthRatio, or pixels off the
             // quad's plane by more than subdivideResidual (relative)
};
const char* subdivisionName(Subdivision s);  // "none", "uniform", "adaptive"

// How a layer's quads reach the rasteriser ("cheaper primitives").
// All three draw the same triangles with the same vertex values, so the
// layers are identical pixel for pixel; only the vertex work differs.
enum class Primitives {
  Independent,  // 6 vertices per quad, glDrawArrays (every vertex shaded 6×/quad)
  Indexed,      // 4 vertices + 6 indices per quad, glDrawElements
  Shared,       // indexed, and corners bit-identical in position and texcoord
                // (neighbouring leaves on one plane) stored once
  Points,       // indexed, but 1×1 leaves (the edge strips' pixels) drawn as one
                // GL point each, sized to the keyframe pixel's footprint in the
                // new view (not pixel-identical: a square, one texel)
};
const char* primitivesName(Primitives p);  // "independent", "indexed", "shared", "points"
bool parsePrimitives(const char* s, Primitives* out);

struct WarpOptions {
  Primitives primitives = Primitives::Indexed;
  // warpPair: leave out the background quads whose surfaces the foreground
  // keyframe sees (warp/seen.h); they would mostly be drawn under foreground
  // pixels. Decided once per keyframe pair on the CPU. Needs an indexed
  // Primitives mode (Independent ignores it). Off by default: it is not
  // lossless — the foreground layer leaves 1-pixel cracks along creases and
  // object edges even where its keyframe saw the surface, and the culled
  // background no longer fills them (indoor 512²: median −0.02 dB, four of
  // 107 frames −0.2 … −1.0 dB; background draw −17 %).
  bool cullBackground = false;
  Subdivision subdivision = Subdivision::None;
  int subdivideCellPx = 16;           // cell size in keyframe pixels
  double subdivideDepthRatio = 1.5;   // Adaptive: max/min corner eye z
  double subdivideResidual = 0.002;   // Adaptive: |z − plane z| / z over the leaf's pixels
  // Interior cell corners take the keyframe's own depth (mean 1/z of the 4
  // pixels around the corner), so cells follow a surface that is not quite
  // planar; edge corners stay on the leaf's plane so neighbours still meet.
  // Off: every cell corner lies on the plane (only the affine mapping gains).
  bool subdivideFromDepth = true;
  // Fill Layer::largeQuad (pixels drawn from leaves larger than one cell, in
  // every Subdivision mode) so their distortion can be measured apart. Free:
  // those leaves' texcoords are negated, which textureProj divides away, and
  // the fragment shader marks them in the alpha it writes anyway. Pixels are
  // identical with it off; Primitives::Shared then stores a few more vertices
  // (a candidate's corners no longer match its neighbours').
  bool markLargeQuads = true;
  TexcoordMode texcoords = TexcoordMode::Projective;
  // Far plane at infinity for layers, so half-pixel-expanded horizon corners
  // beyond the keyframe's far plane are not clipped (DESIGN.md).
  bool infiniteFar = true;
  // Empty keyframe pixels (nothing drawn: sky) are drawn first, as
  // rectangles at infinity (warp/sky_rects.h) behind every quad: points at
  // infinity move only with camera rotation, so this is exact for them. Off:
  // the paper's rule, where empty pixels belong to no quad and become holes.
  bool skyBackdrop = true;
  // Write Layer::eyeZ (an R32F attachment). Only the depth-merge composition
  // reads it; without it Layer::eyeZ is left empty (0×0).
  bool writeEyeZ = true;
};

struct WarpStats {
  double uploadMs = 0;    // mesh build + buffer/texture upload
  double drawMs = 0;      // draw + glFinish
  double readbackMs = 0;  // colour + depth readback
  int quads = 0;
  int uncovered = 0;      // pixels of the layer no quad or sky rectangle covers
  int subdividedQuads = 0;  // upload: leaves cut into cells
  int drawnQuads = 0;       // upload: quads drawn after subdivision
  int vertices = 0;         // upload: vertices stored (quads and sky rectangles)
  int points = 0;           // upload: 1×1 leaves drawn as points (Primitives::Points)
};

// One fused pass for both layers (Warper::warpPair).
struct PairStats {
  double foregroundMs = 0;  // foreground draw + coverage query (waits for both)
  double backgroundMs = 0;  // background draw + glFinish (0 when skipped)
  double readbackMs = 0;    // one colour readback + coverage
  int quadsForeground = 0;
  int quadsBackground = 0;      // drawn; 0 when the background layer was skipped
  int backgroundCulled = 0;     // background quads left out (cullBackground)
  double cullMs = 0;            // deciding them (first frame of a pair only); in backgroundMs
  bool backgroundDrawn = false;
  int uncoveredByForeground = 0;  // from the query: pixels the foreground left empty
  int fromBackground = 0;         // pixels the background filled
  int uncovered = 0;              // pixels neither layer covers (the paper's holes)
};

// GPU copy of one keyframe (texture + quad vertex buffer).
class WarpSource {
 public:
  virtual ~WarpSource() = default;
  virtual const Camera& keyframeCamera() const = 0;
  virtual int quadCount() const = 0;
};

class Warper {
 public:
  virtual ~Warper() = default;
  // Needs a current GL context.
  static Result<std::unique_ptr<Warper>> create(const WarpOptions& options = {});

  virtual Result<std::unique_ptr<WarpSource>> upload(const keyframe::Keyframe& keyframe,
                                                     const keyframe::QuadMesh& mesh,
                                                     WarpStats* stats = nullptr) = 0;
  // Draws `source` from `target` into `out` (resized to the target's size).
  virtual Status warp(const WarpSource& source, const Camera& target, Layer& out,
                      WarpStats* stats = nullptr) = 0;
  // The paper's overlay of two layers (§2.2 (i): foreground where it covers,
  // else background) in one render target: the foreground is drawn and marks
  // the stencil; an occlusion query counts the pixels it left empty (the
  // coverage test); only if there are any — and `background` is given — is
  // the background drawn, where the stencil is still 0. One readback. The
  // result equals warp(fg) + warp(bg) + compose(Overlay) pixel for pixel.
  // out.coverage: 1 = foreground, 2 = background, 0 = neither; out.eyeZ as
  // in warp() when WarpOptions::writeEyeZ. skipBackgroundWhenCovered = false draws the background even
  // when the query finds nothing to fill (for measuring the skip).
  virtual Status warpPair(const WarpSource& foreground, const WarpSource* background,
                          const Camera& target, Layer& out, bool skipBackgroundWhenCovered,
                          PairStats* stats = nullptr) = 0;
  // warpPair without the readback, for a caller that keeps frames on the
  // GPU: the pair stays in pairTexture() (an RGBA8 texture of the target's
  // size, row 0 = bottom; alpha 0 where neither layer covers, else the pair's
  // codes, warp/layer.h) until the next pair is drawn. `stats` as warpPair's,
  // except readbackMs = 0 and fromBackground = uncovered = -1 (not counted).
  // Warpers that do not draw with OpenGL have no such texture: an error.
  virtual Status warpPairOnGpu(const WarpSource& /*foreground*/, const WarpSource* /*background*/,
                               const Camera& /*target*/, bool /*skipBackgroundWhenCovered*/,
                               PairStats* /*stats*/ = nullptr) {
    return makeError("this warper draws its layers on the CPU: no layer texture on the GPU");
  }
  virtual unsigned pairTexture() const { return 0; }
  virtual const WarpOptions& options() const = 0;
};

}  // namespace hw::warp
