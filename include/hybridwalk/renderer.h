#pragma once
// The hybridwalk renderer: a scene and a camera in, a frame out (Zheng et al.
// 1999, docs/how-it-works.md). Keyframes are drawn by the geometry renderer
// and cut into level-of-detail quad meshes; the frames between them are
// backward-warped from the two keyframes around them and composed with the
// previous frame. Backward warping needs the keyframe *after* a frame, so a
// renderer works in one of two ways:
//  - along a path given up front (RendererDesc::path, then renderNext()):
//    keyframes every Path::keyframeEvery frames, and frame i is bit for bit
//    `hybridwalk walk`'s frame i for the same scene, path and options;
//  - at a camera given per frame (render()): keyframes placed as the
//    interactive viewer places them, one ahead along the camera's motion
//    (extrapolated from the last two cameras) and one where the camera
//    stands when no keyframe is near (that frame is then the keyframe).
// Option structs work as given; a zero / Default field means the value of
// the preset (RendererDesc::preset), i.e. what `hybridwalk walk --mode
// hybrid` uses. Times are wall-clock milliseconds.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "hybridwalk/camera.h"
#include "hybridwalk/result.h"
#include "hybridwalk/scene.h"

namespace hybridwalk {

// Where the renderer draws.
// A renderer is used from one thread at a time.
enum class ContextKind {
  Own,      // its own headless context (EGL or OSMesa: RendererDesc::headlessGl;
            // no display needed), made current on the calling thread by each
            // call (and left so)
  Current,  // the caller's OpenGL 4.5 core context, current on the calling
            // thread for every call (e.g. a GLFW window's); needs
            // RendererDesc::getProcAddress
};
using GetProcAddress = void* (*)(const char* name);

// ContextKind::Own: the library its headless context comes from
// (docs/gpu.md). Env: the HYBRIDWALK_GL environment variable (auto|egl|osmesa;
// auto when unset). Auto: EGL when it gives an OpenGL 4.5 core context, else
// OSMesa. The GL entry points are process-wide: one process uses one kind.
enum class HeadlessGl { Env, Auto, Egl, OsMesa };

enum class Mode {
  Hybrid,    // keyframes + warped frames
  Geometry,  // every frame drawn by the geometry renderer (the reference)
};

enum class Criterion { Default, FivePoint, PerAxisMax };                // the Δ²z' test
enum class Planarity { Default, Stencil, RegionLocal };                 // where Δ² is taken
enum class Compose { Default, Overlay, DepthMerge };                    // layer composition
enum class DepthBuffer { Default, Fixed24, Float32, Float32Reversed };  // keyframe depth
enum class Toggle { Default, Off, On };
// What draws the warped layers (`hybridwalk walk --warper`): Auto, a
// rasteriser on the CPU where OpenGL itself runs on the CPU (Mesa's
// llvmpipe), else OpenGL's textured quads; Gl and Cpu force one. The frames
// agree to within rounding.
enum class Warper { Auto, Gl, Cpu };
// Where the defaults come from (`hybridwalk walk --preset`): Default, the
// settings measured best over many scenes (τ as a parallax bound of 0.125 px
// per scene unit, region-local planarity, strip merging); Paper, Zheng et
// al. 1999 exactly (τ = 2^11 z' units, five-point stencil, no merging).
enum class Preset { Default, Paper };

// The level-of-detail quad mesh of each keyframe (docs/how-it-works.md).
struct LodDesc {
  // |Δ²z'| threshold, z' units (2^24 scale); > 0 (with tauParallaxPx 0)
  // replaces the preset's threshold; 0 = the preset's.
  double tau = 0;
  double tauParallaxPx = 0;  // > 0: parallax error bound, pixels per scene unit (replaces tau)
  Criterion criterion = Criterion::Default;  // both presets: five-point
  Planarity planarity = Planarity::Default;  // Default: region-local; Paper: stencil
  Toggle mergeStrips = Toggle::Default;      // merge coplanar 1-pixel strips; Default: on
};

// Where keyframes go with a free camera (render()). A keyframe is one pose
// unit from the camera when it is `distance` away or `angleDeg` turned (the
// two add up); one is rendered ahead once the camera has passed the newest
// by a quarter unit, and at the camera when none is within 1.5 units.
struct KeyframeDesc {
  double distance = 0;  // scene units; 0 = 1/16 of the scene's bounding-box diagonal
  double angleDeg = 0;  // degrees; 0 = 15
};

struct RendererDesc {
  ContextKind context = ContextKind::Own;
  GetProcAddress getProcAddress = nullptr;  // ContextKind::Current: e.g. glfwGetProcAddress
  HeadlessGl headlessGl = HeadlessGl::Env;  // ContextKind::Own
  int eglDevice = -1;  // ContextKind::Own on EGL: an EGL device index (`hybridwalk info`); -1: default
  Mode mode = Mode::Hybrid;
  Preset preset = Preset::Default;
  LodDesc lod;
  KeyframeDesc keyframes;
  Compose compose = Compose::Default;  // overlay (the paper's)
  Warper warper = Warper::Auto;
  // Objects within this distance (scene units) of a keyframe's eye are drawn
  // as geometry into every frame instead of warped (the paper's §3); 0 = off.
  double nearDistance = 0;
  DepthBuffer depthBuffer = DepthBuffer::Default;  // float32-reversed
  bool depth = false;                              // fill Frame::depth
  // Non-empty: the renderer follows this path (renderNext()); empty: free
  // camera (render()).
  Path path;
};

enum class FrameKind {
  Keyframe,  // a keyframe image shown as it is (rendered now or earlier)
  Warped,    // warped from keyframes, holes filled from the previous frame
  Geometry,  // drawn by the geometry renderer
};

struct FrameStats {
  FrameKind kind = FrameKind::Geometry;
  int index = -1;               // path: the frame's index in the path; free camera: -1
  int keyframes[2] = {-1, -1};  // path: the keyframes around it (equal on a keyframe)
  int keyframesBuilt = 0;       // keyframes rendered / uploaded during this call
  int quads = 0;                // quads warped (both layers), or the shown keyframe's
  double holeFraction = 0;      // pixels no keyframe covered (then the previous frame's)
  double keyframeRenderMs = 0;  // geometry draw + readback of keyframes built in this call
  double lodMs = 0;             // their Δ buffer, subdivision and corners
  double uploadMs = 0;          // their mesh and texture upload
  double warpMs = 0;            // warping the layers, with their readback
  double composeMs = 0;         // composition with the previous frame
  double nearMs = 0;            // near objects drawn as geometry
  double geometryMs = 0;        // FrameKind::Geometry: draw + readback
  double totalMs = 0;           // the whole call, copying out included
};

struct Frame {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgba;  // width·height·4, row 0 = top, alpha 255
  // RendererDesc::depth: eye-space depth along the view direction (scene
  // units) per pixel, 0 where nothing is (sky, unfilled); a pixel filled from
  // the previous frame keeps that frame's depth. Near objects
  // (nearDistance) are not in it. Empty without RendererDesc::depth.
  std::vector<float> depth;
  FrameStats stats;
};

class Renderer {
 public:
  // Uploads the scene (the Scene may be destroyed afterwards). With
  // ContextKind::Own it creates its own headless context; with Current it
  // loads the GL entry points through getProcAddress from the current
  // context. One kind of context per process: the entry points are
  // process-wide. Errors: no OSMesa / no current 4.5 core context (names
  // what is missing), getProcAddress missing, bad option values, a bad path
  // (cameras of different sizes), GL failures.
  static Result<Renderer> create(const Scene& scene, const RendererDesc& desc = {});

  Renderer(Renderer&&) noexcept;
  Renderer& operator=(Renderer&&) noexcept;
  ~Renderer();  // ContextKind::Current: that context must be current

  // Free camera: the frame at `camera` (any size; keyframes of another size
  // are dropped). Error on a renderer with a path, a bad camera (non-finite,
  // axes not orthonormal, size, planes), or from GL.
  Status render(const Camera& camera, Frame& out);
  // Path: the next frame of RendererDesc::path (frame frameIndex()). Error
  // on a renderer without a path, after the last frame, or from GL.
  Status renderNext(Frame& out);
  int frameIndex() const;  // the frame renderNext() draws next
  int frameCount() const;  // frames in the path (0 without one)

  // The geometry renderer's frame at `camera` (the reference each hybrid
  // frame is measured against); does not disturb the hybrid frames.
  Status renderGeometry(const Camera& camera, Frame& out);

  // Draws `frame` over the whole viewport (0, 0, viewportWidth,
  // viewportHeight) of the current context's default framebuffer (a
  // window's back buffer; swap it yourself). ContextKind::Current only. GL
  // state the library changes (program, textures, vertex array, framebuffer,
  // viewport, depth test) is not restored.
  Status present(const Frame& frame, int viewportWidth, int viewportHeight);

  const std::string& glRenderer() const;  // GL_RENDERER of the context

  struct Impl;

 private:
  explicit Renderer(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// PSNR of a's colour against b's, dB over R, G and B (the walk's metric);
// +inf when identical, NaN when the sizes differ or a frame is empty.
double psnr(const Frame& a, const Frame& b);

}  // namespace hybridwalk
