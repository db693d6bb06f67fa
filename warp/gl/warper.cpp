#include "warp/warper.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <cstdint>
#include <memory>
#include <unordered_map>
#include <vector>

#include <glm/gtc/type_ptr.hpp>

#include "core/gl/framebuffer.h"
#include "warp/seen.h"
#include "core/gl/gl_api.h"
#include "core/gl/shader.h"
#include "core/timer.h"
#include "warp/sky_rects.h"

namespace hw::warp {

const char* primitivesName(Primitives p) {
  switch (p) {
    case Primitives::Independent: return "independent";
    case Primitives::Indexed: return "indexed";
    case Primitives::Shared: return "shared";
    case Primitives::Points: return "points";
  }
  return "?";
}

bool parsePrimitives(const char* s, Primitives* out) {
  for (Primitives p :
       {Primitives::Independent, Primitives::Indexed, Primitives::Shared, Primitives::Points})
    if (std::strcmp(s, primitivesName(p)) == 0) {
      *out = p;
      return true;
    }
  return false;
}

const char* subdivisionName(Subdivision s) {
  switch (s) {
    case Subdivision::None: return "none";
    case Subdivision::Uniform: return "uniform";
    case Subdivision::Adaptive: return "adaptive";
  }
  return "?";
}

const char* texcoordModeName(TexcoordMode m) {
  return m == TexcoordMode::Projective ? "projective" : "affine";
}

namespace {

constexpr const char* kVertex = R"(#version 450 core
// Quads: w = 1. Sky rectangles: directions with w = 0 (points at infinity).
layout(location = 0) in vec4 aPos;
layout(location = 1) in vec3 aTex;  // (u·q, v·q, q) or (u, v, 1), u,v normalised
uniform mat4 uViewProj;
uniform mat4 uView;
// Points (1×1 leaves): side = new focal / keyframe focal × keyframe depth
// (aTex.z) / new depth, in pixels, rounded up so neighbours overlap.
uniform float uPointScale;
out vec3 vTex;
out float vEyeZ;
void main() {
  vec4 p = aPos;
  vTex = aTex;
  vEyeZ = -(uView * p).z;
  gl_Position = uViewProj * p;
  gl_PointSize = uPointScale > 0.0 ? clamp(ceil(uPointScale * aTex.z / max(vEyeZ, 1e-6)), 1.0, 16.0) : 1.0;
}
)";

constexpr const char* kFragment = R"(#version 450 core
in vec3 vTex;
in float vEyeZ;
uniform sampler2D uKey;
uniform float uSkyEyeZ;  // > 0 while drawing sky rectangles
uniform float uAlpha;    // 1; 254/255 marks the background layer in a fused pair
layout(location = 0) out vec4 oColour;
layout(location = 1) out float oEyeZ;  // R32F: relative 6e-8, vs the depth merge's 2 % tolerance
void main() {
  // vTex.z < 0: a large leaf's negated texcoords (WarpOptions::markLargeQuads),
  // marked 2/255 lower: 253 foreground, 252 background.
  oColour = vec4(textureProj(uKey, vTex).rgb, vTex.z < 0.0 ? uAlpha - 2.0 / 255.0 : uAlpha);
  oEyeZ = uSkyEyeZ > 0.0 ? uSkyEyeZ : vEyeZ;
}
)";

// The coverage query: a full-screen triangle (gl::kFullScreenTriangleVertex),
// no outputs (colour writes off).
constexpr const char* kQueryFragment = R"(#version 450 core
void main() {}
)";

// Alpha of background pixels in a fused pair: exactly kAlphaBackground (254)
// in RGBA8 (warp/layer.h). Pixels of large leaves (markLargeQuads) are 2 lower.
constexpr float kBackgroundAlpha = 254.0f / 255.0f;

// Float is enough here ("precision where it matters"); corners,
// matrices and unprojection are computed in double and rounded once:
//  - pos: rounding a corner to float moves it ≤ 2^-24·|p|; with the shader's
//    float product uViewProj·pos (the view translation −R·eye cancels against
//    R·p) the eye-space error is ≲ 2·2^-24·(|p| + |eye|) ≈ 3e-4 units at the
//    largest scene's 2,400 units from the origin (torcs:forza; indoor 33,
//    oa_dm5 35, morse 75, outdoor 160). On screen that is ≤ 3e-4·f/z px:
//    f = 443 px at 512 px / 60°, so 0.07 px at z = 2 and 0.27 px at a 0.5
//    near plane, inside the 0.5 px reprojection budget; the other scenes stay
//    below 0.04 px even at their near planes (indoor 0.1, outdoor 0.5).
//  - sky directions (w = 0) are unit-length: 6e-8 rad ≈ 3e-5 px.
//  - tex: s, t ∈ [0, 1] and (s·q, t·q, q) each carry a relative 6e-8, so the
//    divided texcoord is off by ≤ 2e-7 · width ≈ 1e-3 px at 4096 px.
struct WarpVertex {
  float pos[4];
  float tex[3];
  bool operator==(const WarpVertex& o) const { return std::memcmp(this, &o, sizeof o) == 0; }
};
static_assert(sizeof(WarpVertex) == 28, "no padding: vertices are compared and hashed as bytes");

struct WarpVertexHash {
  std::size_t operator()(const WarpVertex& v) const {
    std::uint64_t h = 0x9E3779B97F4A7C15ull;
    std::uint32_t w[7];
    std::memcpy(w, &v, sizeof w);
    for (std::uint32_t x : w) h = (h ^ x) * 0x100000001B3ull;
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};

// The GL objects of one uploaded keyframe, with the storage sizes they hold.
struct GlSlot {
  GLuint vao = 0, vbo = 0, ibo = 0, tex = 0;
  GLsizeiptr vboBytes = 0, iboBytes = 0;
  int texWidth = 0, texHeight = 0;
};

void destroySlot(GlSlot& s) {
  if (s.vao) glDeleteVertexArrays(1, &s.vao);
  if (s.vbo) glDeleteBuffers(1, &s.vbo);
  if (s.ibo) glDeleteBuffers(1, &s.ibo);
  if (s.tex) glDeleteTextures(1, &s.tex);
  s = GlSlot{};
}

// Slots of dropped sources, reused by the next upload. llvmpipe keeps buffer
// and texture storage in malloc'd memory, so creating and deleting a vertex
// buffer (200 KiB–1 MiB, a different size for every keyframe) and a texture
// per keyframe fragmented glibc's heap: the 10,000-frame soak's [heap] RSS
// grew 42 → 51 MiB while the live heap stayed at 43 MiB. A walk
// holds at most three sources at a time, so a few slots cover it.
struct SlotPool {
  static constexpr std::size_t kMaxFree = 4;
  std::vector<GlSlot> free;
  SlotPool() { free.reserve(kMaxFree); }
  ~SlotPool() {
    for (GlSlot& s : free) destroySlot(s);
  }
};

// What the background cull reads of a source on the CPU (cullBackground).
struct CullData {
  keyframe::Keyframe keyframe;  // camera, eyeZ, covered (no colour, no z')
  keyframe::QuadMesh mesh;      // the leaves (rects)
  std::vector<int> leafFirst;   // leaf i draws quads [leafFirst[i], leafFirst[i+1])
  std::vector<std::uint32_t> indices;  // the quads' indices (6 per drawn quad)
};

// A culled index list of this source as a background, for one foreground.
struct CullEntry {
  long foreground = -1;  // the foreground source's serial
  GLuint ibo = 0;
  GLsizeiptr bytes = 0;
  int quads = 0, culled = 0;
  long lastUse = 0;
};

class GlWarpSource final : public WarpSource {
 public:
  ~GlWarpSource() override {
    if (pool && pool->free.size() < SlotPool::kMaxFree) pool->free.push_back(slot);
    else destroySlot(slot);
    for (CullEntry& e : culls)
      if (e.ibo) glDeleteBuffers(1, &e.ibo);
  }
  const Camera& keyframeCamera() const override { return camera; }
  int quadCount() const override { return quads; }

  Camera camera;
  int quads = 0;
  int skyRects = 0;  // drawn after the quads' vertices (indices) in the same buffer
  bool indexed = false;
  int points = 0;  // Primitives::Points: vertices after the indexed ones, one per 1×1 leaf
  int pointFirst = 0;
  double focal = 0;  // the keyframe camera's, pixels
  long serial = 0;
  std::unique_ptr<CullData> cull;          // set when cullBackground and indexed
  mutable std::array<CullEntry, 2> culls;  // as a background, for the last two foregrounds
  GlSlot slot;
  // Shared so that sources outliving the warper still free their objects.
  std::shared_ptr<SlotPool> pool;
};

class GlWarper final : public Warper {
 public:
  Status init(const WarpOptions& options) {
    options_ = options;
    auto p = gl::Program::build("warp", kVertex, kFragment);
    if (!p) return p.error();
    program_ = std::move(*p);
    uViewProj_ = program_.uniform("uViewProj");
    uView_ = program_.uniform("uView");
    uKey_ = program_.uniform("uKey");
    uSkyEyeZ_ = program_.uniform("uSkyEyeZ");
    uAlpha_ = program_.uniform("uAlpha");
    uPointScale_ = program_.uniform("uPointScale");
    auto q = gl::Program::build("coverage query", gl::kFullScreenTriangleVertex, kQueryFragment);
    if (!q) return q.error();
    queryProgram_ = std::move(*q);
    glGenVertexArrays(1, &emptyVao_);
    glGenQueries(1, &query_);
    return gl::checkGlError("Warper::create");
  }
  ~GlWarper() override {
    if (emptyVao_) glDeleteVertexArrays(1, &emptyVao_);
    if (query_) glDeleteQueries(1, &query_);
  }

  Result<std::unique_ptr<WarpSource>> upload(const keyframe::Keyframe& kf,
                                             const keyframe::QuadMesh& mesh,
                                             WarpStats* stats) override {
    if (kf.colour.width() != mesh.width || kf.colour.height() != mesh.height)
      return makeError("warp upload: keyframe is " + std::to_string(kf.colour.width()) + "x" +
                       std::to_string(kf.colour.height()) + " but its quad mesh was built for " +
                       std::to_string(mesh.width) + "x" + std::to_string(mesh.height));
    Stopwatch sw;
    auto src = std::make_unique<GlWarpSource>();
    src->pool = pool_;
    if (!pool_->free.empty()) {
      src->slot = pool_->free.back();
      pool_->free.pop_back();
    }
    src->camera = kf.camera;
    if (options_.skyBackdrop) emptyRects(kf.covered, skyRects_);
    else skyRects_.clear();
    src->skyRects = static_cast<int>(skyRects_.size());
    src->indexed = options_.primitives != Primitives::Independent;
    const int subdivided = buildVertices(kf, mesh, *src);
    if (stats) {
      stats->subdividedQuads = subdivided;
      stats->drawnQuads = src->quads;
      stats->vertices = static_cast<int>(scratch_.size());
      stats->points = src->points;
    }
    uploadBuffers(src->slot, src->indexed);
    uploadTexture(src->slot, kf);
    HW_TRY(gl::checkGlError("Warper::upload"));
    if (stats) stats->uploadMs = sw.ms();
    return std::unique_ptr<WarpSource>(std::move(src));
  }

  Status warp(const WarpSource& source, const Camera& target, Layer& out,
              WarpStats* stats) override {
    const auto& src = static_cast<const GlWarpSource&>(source);
    HW_TRY(ensureTarget(target, options_.writeEyeZ, false, fbo_));
    Stopwatch sw;
    fbo_.bindAndClear(0, 0, 0, 0);
    drawSource(src, target, 1.0f);
    glFinish();
    const double drawMs = sw.lap();
    readLayer(fbo_, target, out);
    const std::size_t n = out.colour.size();
    Rgba8* c = out.colour.data();
    std::uint8_t* cov = out.coverage.data();
    int uncovered = 0;
    if (options_.markLargeQuads) {
      std::uint8_t* large = out.largeQuad.data();
      for (std::size_t i = 0; i < n; ++i) {
        const std::uint8_t a = c[i].a;
        const int on = a != 0;
        cov[i] = static_cast<std::uint8_t>(on);
        large[i] = a == kAlphaLargeForeground;
        c[i].a = on ? kAlphaForeground : 0;
        uncovered += 1 - on;
      }
    } else {
      for (std::size_t i = 0; i < n; ++i) {
        const int on = c[i].a != 0;
        cov[i] = static_cast<std::uint8_t>(on);
        uncovered += 1 - on;
      }
    }
    if (stats) {
      stats->drawMs = drawMs;
      stats->readbackMs = sw.ms();
      stats->quads = src.quads;
      stats->uncovered = uncovered;
    }
    return gl::checkGlError("Warper::warp");
  }

  Status warpPair(const WarpSource& foreground, const WarpSource* background,
                  const Camera& target, Layer& out, bool skipBackgroundWhenCovered,
                  PairStats* stats) override {
    PairStats local;
    PairStats& st = stats ? *stats : local;
    HW_TRY(drawPair(foreground, background, target, skipBackgroundWhenCovered, st));
    Stopwatch sw;
    readLayer(pairFbo_, target, out);
    const std::size_t n = out.colour.size();
    Rgba8* c = out.colour.data();
    std::uint8_t* cov = out.coverage.data();
    std::uint8_t* large = options_.markLargeQuads ? out.largeQuad.data() : nullptr;
    int fromBg = 0, uncovered = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint8_t a = c[i].a;
      const int isBg = a == kAlphaBackground || a == kAlphaLargeBackground, isNone = a == 0;
      cov[i] = static_cast<std::uint8_t>(isNone ? 0 : 1 + isBg);
      if (large) large[i] = a == kAlphaLargeForeground || a == kAlphaLargeBackground;
      c[i].a = isNone ? 0 : kAlphaForeground;
      fromBg += isBg;
      uncovered += isNone;
    }
    st.readbackMs = sw.ms();
    st.fromBackground = fromBg;
    st.uncovered = uncovered;
    return gl::checkGlError("Warper::warpPair");
  }

  Status warpPairOnGpu(const WarpSource& foreground, const WarpSource* background,
                       const Camera& target, bool skipBackgroundWhenCovered,
                       PairStats* stats) override {
    PairStats local;
    PairStats& st = stats ? *stats : local;
    HW_TRY(drawPair(foreground, background, target, skipBackgroundWhenCovered, st));
    st.readbackMs = 0;
    st.fromBackground = st.uncovered = -1;
    return gl::checkGlError("Warper::warpPairOnGpu");
  }

  unsigned pairTexture() const override { return pairFbo_.colourTexture(); }

  const WarpOptions& options() const override { return options_; }

 private:
  // The fused pair drawn into pairFbo_ (warpPair's passes, up to its glFinish);
  // `st` gets everything but the readback's fields.
  Status drawPair(const WarpSource& foreground, const WarpSource* background,
                  const Camera& target, bool skipBackgroundWhenCovered, PairStats& st) {
    const auto& fg = static_cast<const GlWarpSource&>(foreground);
    HW_TRY(ensureTarget(target, options_.writeEyeZ, true, pairFbo_));
    Stopwatch sw;
    pairFbo_.bindAndClear(0, 0, 0, 0);
    // Foreground: every pixel it writes (quads or sky) gets stencil 1.
    glEnable(GL_STENCIL_TEST);
    glStencilMask(0xFF);
    glStencilFunc(GL_ALWAYS, 1, 0xFF);
    glStencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
    drawSource(fg, target, 1.0f);
    // Coverage test: how many pixels still have stencil 0.
    glStencilMask(0x00);
    glStencilFunc(GL_EQUAL, 0, 0xFF);
    glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    glDisable(GL_DEPTH_TEST);
    glDepthMask(GL_FALSE);
    queryProgram_.use();
    glBindVertexArray(emptyVao_);
    glBeginQuery(GL_SAMPLES_PASSED, query_);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glEndQuery(GL_SAMPLES_PASSED);
    GLuint emptyAfterFg = 0;
    glGetQueryObjectuiv(query_, GL_QUERY_RESULT, &emptyAfterFg);
    const double fgMs = sw.lap();
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glEnable(GL_DEPTH_TEST);
    glDepthMask(GL_TRUE);
    const bool drawBg =
        background != nullptr && (emptyAfterFg > 0 || !skipBackgroundWhenCovered);
    const CullEntry* culled = nullptr;
    double cullMs = 0;
    if (drawBg) {
      const auto& bg = static_cast<const GlWarpSource&>(*background);
      if (bg.cull && fg.cull) {
        Stopwatch cw;
        culled = &cullFor(bg, fg);
        cullMs = cw.ms();
      }
      // Background only where the foreground left pixels empty; its own
      // depth test among its quads, not against the foreground's (overlay).
      glClear(GL_DEPTH_BUFFER_BIT);
      drawSource(bg, target, kBackgroundAlpha, culled);
    }
    glDisable(GL_STENCIL_TEST);
    glFinish();
    st = PairStats{};
    st.foregroundMs = fgMs;
    st.backgroundMs = sw.lap();
    st.quadsForeground = fg.quads;
    st.quadsBackground = !drawBg ? 0 : culled ? culled->quads : background->quadCount();
    st.backgroundCulled = culled ? culled->culled : 0;
    st.cullMs = cullMs;
    st.backgroundDrawn = drawBg;
    st.uncoveredByForeground = static_cast<int>(emptyAfterFg);
    return {};
  }

  // The source's vertices (scratch_) and indices (indices_): the mesh's
  // leaves, then the sky rects, then one point per 1×1 leaf (Points).
  // Returns the number of leaves cut into cells.
  int buildVertices(const keyframe::Keyframe& kf, const keyframe::QuadMesh& mesh,
                    GlWarpSource& src) {
    scratch_.clear();
    indices_.clear();
    shared_.clear();
    scratch_.reserve((mesh.quads.size() + skyRects_.size()) * (src.indexed ? 4 : 6));
    if (src.indexed) indices_.reserve((mesh.quads.size() + skyRects_.size()) * 6);
    const int subdivided = addLeafQuads(kf, mesh, src);
    src.quads = static_cast<int>((src.indexed ? indices_.size() : scratch_.size()) / 6);
    src.serial = ++serial_;
    if (src.cull) keepCullData(kf, mesh, src);
    addSkyQuads(kf, mesh);
    src.pointFirst = static_cast<int>(scratch_.size());
    src.points = static_cast<int>(pointScratch_.size());
    src.focal = kf.camera.fy();
    scratch_.insert(scratch_.end(), pointScratch_.begin(), pointScratch_.end());
    return subdivided;
  }

  // One quad (corners in order) as two triangles 0-1-2, 0-2-3.
  void addQuad(const WarpVertex* v) {
    static constexpr int kTri[6] = {0, 1, 2, 0, 2, 3};
    const Primitives prim = options_.primitives;
    if (prim == Primitives::Independent) {
      for (int k : kTri) scratch_.push_back(v[k]);
      return;
    }
    std::uint32_t id[4];
    for (int k = 0; k < 4; ++k) {
      if (prim == Primitives::Shared) {
        const auto [it, fresh] =
            shared_.try_emplace(v[k], static_cast<std::uint32_t>(scratch_.size()));
        if (fresh) scratch_.push_back(v[k]);
        id[k] = it->second;
      } else {
        id[k] = static_cast<std::uint32_t>(scratch_.size());
        scratch_.push_back(v[k]);
      }
    }
    for (int k : kTri) indices_.push_back(id[k]);
  }

  // The mesh's leaves as quads (cut into cells where cellsFor says so), and
  // 1×1 leaves as points into pointScratch_ (Primitives::Points). Records
  // each leaf's first quad when the source keeps cull data. Returns the
  // number of leaves cut into cells.
  int addLeafQuads(const keyframe::Keyframe& kf, const keyframe::QuadMesh& mesh,
                   GlWarpSource& src) {
    const Primitives prim = options_.primitives;
    const double invW = 1.0 / mesh.width, invH = 1.0 / mesh.height;
    // −1 while emitting a large leaf (markLargeQuads): its texcoords are
    // negated, which textureProj divides away (the sign is exact in float).
    double texSign = 1.0;
    auto emit = [&](const glm::dvec3* world, const glm::dvec2* pixel, const double* eyeZ) {
      WarpVertex v[4];
      for (int k = 0; k < 4; ++k) {
        for (int c = 0; c < 3; ++c) v[k].pos[c] = static_cast<float>(world[k][c]);
        v[k].pos[3] = 1.0f;
        const double s = pixel[k].x * invW, t = pixel[k].y * invH;
        const double w =
            texSign * (options_.texcoords == TexcoordMode::Projective ? eyeZ[k] : 1.0);
        v[k].tex[0] = static_cast<float>(s * w);
        v[k].tex[1] = static_cast<float>(t * w);
        v[k].tex[2] = static_cast<float>(w);
      }
      addQuad(v);
    };
    int subdivided = 0;
    const bool cull = options_.cullBackground && src.indexed;
    if (cull) {
      src.cull = std::make_unique<CullData>();
      src.cull->leafFirst.reserve(mesh.quads.size() + 1);
    }
    pointScratch_.clear();
    for (const keyframe::Quad& q : mesh.quads) {
      if (cull) src.cull->leafFirst.push_back(static_cast<int>(indices_.size() / 6));
      if (prim == Primitives::Points && q.rect.width() == 1 && q.rect.height() == 1) {
        const double u = q.rect.x0 + 0.5, v = q.rect.y0 + 0.5;
        const glm::dvec3 p = keyframe::quadPointAt(q, kf.camera, u, v);
        const double w = keyframe::quadEyeZAt(q, u, v);
        WarpVertex pv;
        for (int c = 0; c < 3; ++c) pv.pos[c] = static_cast<float>(p[c]);
        pv.pos[3] = 1.0f;
        pv.tex[0] = static_cast<float>(u * invW * w);
        pv.tex[1] = static_cast<float>(v * invH * w);
        pv.tex[2] = static_cast<float>(w);
        pointScratch_.push_back(pv);
        continue;
      }
      texSign = options_.markLargeQuads && cellGrid(q) > 1 ? -1.0 : 1.0;
      const int cells = cellsFor(q, kf);
      if (cells <= 1) {
        emit(q.world.data(), q.pixel.data(), q.eyeZ.data());
        continue;
      }
      ++subdivided;
      emitCells(q, kf, emit);
    }
    return subdivided;
  }

  // What the background cull reads on the CPU: the leaves and their indices.
  void keepCullData(const keyframe::Keyframe& kf, const keyframe::QuadMesh& mesh,
                    GlWarpSource& src) {
    CullData& c = *src.cull;
    c.leafFirst.push_back(src.quads);
    c.indices = indices_;
    c.keyframe.camera = kf.camera;
    c.keyframe.depthMode = kf.depthMode;
    c.keyframe.eyeZ = kf.eyeZ;
    c.keyframe.covered = kf.covered;
    c.mesh.width = mesh.width;
    c.mesh.height = mesh.height;
    c.mesh.quads = mesh.quads;
  }

  // Sky: each corner is the direction through that keyframe image point,
  // scaled to depth 1 along W, so its projective texcoord is (s, t, 1).
  void addSkyQuads(const keyframe::Keyframe& kf, const keyframe::QuadMesh& mesh) {
    const double invW = 1.0 / mesh.width, invH = 1.0 / mesh.height;
    for (const keyframe::PixelRect& r : skyRects_) {
      const double us[4] = {double(r.x0), double(r.x1), double(r.x1), double(r.x0)};
      const double vs[4] = {double(r.y0), double(r.y0), double(r.y1), double(r.y1)};
      WarpVertex v[4];
      for (int k = 0; k < 4; ++k) {
        const glm::dvec3 d = kf.camera.unproject(us[k], vs[k], 1.0) - kf.camera.eye;
        for (int c = 0; c < 3; ++c) v[k].pos[c] = static_cast<float>(d[c]);
        v[k].pos[3] = 0.0f;
        v[k].tex[0] = static_cast<float>(us[k] * invW);
        v[k].tex[1] = static_cast<float>(vs[k] * invH);
        v[k].tex[2] = 1.0f;
      }
      addQuad(v);
    }
  }

  // scratch_ (and indices_ when indexed) into the slot's buffers, created
  // with their vertex array on first use.
  void uploadBuffers(GlSlot& slot, bool indexed) {
    if (!slot.vao) {
      glGenVertexArrays(1, &slot.vao);
      glBindVertexArray(slot.vao);
      glGenBuffers(1, &slot.vbo);
      glGenBuffers(1, &slot.ibo);
      glBindBuffer(GL_ARRAY_BUFFER, slot.vbo);
      glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, slot.ibo);  // recorded in the VAO
      glEnableVertexAttribArray(0);
      glVertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, sizeof(WarpVertex),
                            reinterpret_cast<void*>(offsetof(WarpVertex, pos)));
      glEnableVertexAttribArray(1);
      glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(WarpVertex),
                            reinterpret_cast<void*>(offsetof(WarpVertex, tex)));
      glBindVertexArray(0);
    }
    // Storage is reallocated only to grow, with 25 % headroom, so after the
    // first keyframes of a walk uploads are copies into existing storage.
    const auto bytes = static_cast<GLsizeiptr>(scratch_.size() * sizeof(WarpVertex));
    glBindBuffer(GL_ARRAY_BUFFER, slot.vbo);
    if (bytes > slot.vboBytes) {
      slot.vboBytes = bytes + bytes / 4;
      glBufferData(GL_ARRAY_BUFFER, slot.vboBytes, nullptr, GL_DYNAMIC_DRAW);
    }
    if (bytes > 0) glBufferSubData(GL_ARRAY_BUFFER, 0, bytes, scratch_.data());
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    if (indexed) {
      const auto ibytes = static_cast<GLsizeiptr>(indices_.size() * sizeof(std::uint32_t));
      glBindVertexArray(slot.vao);  // the element buffer binding is VAO state
      if (ibytes > slot.iboBytes) {
        slot.iboBytes = ibytes + ibytes / 4;
        glBufferData(GL_ELEMENT_ARRAY_BUFFER, slot.iboBytes, nullptr, GL_DYNAMIC_DRAW);
      }
      if (ibytes > 0) glBufferSubData(GL_ELEMENT_ARRAY_BUFFER, 0, ibytes, indices_.data());
      glBindVertexArray(0);
    }
  }

  // The keyframe's colour into the slot's texture, created on first use and
  // reallocated only when the size changes.
  void uploadTexture(GlSlot& slot, const keyframe::Keyframe& kf) {
    if (!slot.tex) {
      glGenTextures(1, &slot.tex);
      glBindTexture(GL_TEXTURE_2D, slot.tex);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    }
    glBindTexture(GL_TEXTURE_2D, slot.tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    // Image row 0 (top) at t = 0, matching t = v / height above.
    if (slot.texWidth != kf.colour.width() || slot.texHeight != kf.colour.height()) {
      slot.texWidth = kf.colour.width();
      slot.texHeight = kf.colour.height();
      glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, slot.texWidth, slot.texHeight, 0, GL_RGBA,
                   GL_UNSIGNED_BYTE, kf.colour.data());
    } else {
      glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, slot.texWidth, slot.texHeight, GL_RGBA,
                      GL_UNSIGNED_BYTE, kf.colour.data());
    }
  }
  // Cells of subdivideCellPx a leaf spans (nx·ny); > 1 = a subdivision
  // candidate, the leaves Uniform cuts.
  int cellGrid(const keyframe::Quad& q) const {
    const int cell = std::max(1, options_.subdivideCellPx);
    const int nx = (q.rect.width() + cell - 1) / cell, ny = (q.rect.height() + cell - 1) / cell;
    return nx * ny;
  }

  // 1 = draw the leaf as it is; otherwise it is cut into cells.
  int cellsFor(const keyframe::Quad& q, const keyframe::Keyframe& kf) const {
    const int cell = std::max(1, options_.subdivideCellPx);
    const int grid = cellGrid(q);
    if (options_.subdivision == Subdivision::None || grid <= 1) return 1;
    if (options_.subdivision == Subdivision::Uniform) return grid;
    const double zMin = std::min({q.eyeZ[0], q.eyeZ[1], q.eyeZ[2], q.eyeZ[3]});
    const double zMax = std::max({q.eyeZ[0], q.eyeZ[1], q.eyeZ[2], q.eyeZ[3]});
    if (zMax >= options_.subdivideDepthRatio * zMin) return grid;
    // Depth off the plane, sampled on the cell grid's pixel centres.
    for (int y = q.rect.y0; y < q.rect.y1; y += std::max(1, cell / 2))
      for (int x = q.rect.x0; x < q.rect.x1; x += std::max(1, cell / 2)) {
        if (!kf.covered(x, y)) continue;
        const double zPlane = keyframe::quadEyeZAt(q, x + 0.5, y + 0.5);
        const double z = kf.eyeZ(x, y);
        if (std::abs(z - zPlane) > options_.subdivideResidual * z) return grid;
      }
    return 1;
  }

  // Cuts the leaf into a grid of cells at integer pixel edges. Corners on the
  // leaf's border stay on its plane; interior corners take the keyframe depth
  // (subdivideFromDepth) when the 4 pixels around them are covered.
  template <class Emit>
  void emitCells(const keyframe::Quad& q, const keyframe::Keyframe& kf, Emit& emit) {
    const int cell = std::max(1, options_.subdivideCellPx);
    const int x0 = q.rect.x0, y0 = q.rect.y0, x1 = q.rect.x1, y1 = q.rect.y1;
    const int nx = (x1 - x0 + cell - 1) / cell, ny = (y1 - y0 + cell - 1) / cell;
    gridX_.resize(static_cast<std::size_t>(nx) + 1);
    gridY_.resize(static_cast<std::size_t>(ny) + 1);
    for (int i = 0; i <= nx; ++i) gridX_[static_cast<std::size_t>(i)] = x0 + (x1 - x0) * i / nx;
    for (int j = 0; j <= ny; ++j) gridY_[static_cast<std::size_t>(j)] = y0 + (y1 - y0) * j / ny;
    const std::size_t stride = static_cast<std::size_t>(nx) + 1;
    gridZ_.resize(stride * (static_cast<std::size_t>(ny) + 1));
    gridP_.resize(gridZ_.size());
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) {
        const int u = gridX_[static_cast<std::size_t>(i)], v = gridY_[static_cast<std::size_t>(j)];
        // Leaf corners keep their recovered values exactly.
        double z = keyframe::quadEyeZAt(q, u, v);
        const bool border = i == 0 || j == 0 || i == nx || j == ny;
        if (!border && options_.subdivideFromDepth && kf.covered(u - 1, v - 1) &&
            kf.covered(u, v - 1) && kf.covered(u - 1, v) && kf.covered(u, v)) {
          const double inv = (1.0 / kf.eyeZ(u - 1, v - 1) + 1.0 / kf.eyeZ(u, v - 1) +
                              1.0 / kf.eyeZ(u - 1, v) + 1.0 / kf.eyeZ(u, v)) / 4.0;
          if (std::isfinite(inv) && inv > 0) z = 1.0 / inv;
        }
        const std::size_t k = static_cast<std::size_t>(j) * stride + static_cast<std::size_t>(i);
        gridZ_[k] = z;
        gridP_[k] = kf.camera.unproject(u, v, z);
      }
    const auto at = [&](int i, int j) { return static_cast<std::size_t>(j) * stride + static_cast<std::size_t>(i); };
    // Exact corners for the leaf's own four corners.
    gridP_[at(0, 0)] = q.world[0], gridZ_[at(0, 0)] = q.eyeZ[0];
    gridP_[at(nx, 0)] = q.world[1], gridZ_[at(nx, 0)] = q.eyeZ[1];
    gridP_[at(nx, ny)] = q.world[2], gridZ_[at(nx, ny)] = q.eyeZ[2];
    gridP_[at(0, ny)] = q.world[3], gridZ_[at(0, ny)] = q.eyeZ[3];
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const std::size_t c[4] = {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)};
        const glm::dvec3 w[4] = {gridP_[c[0]], gridP_[c[1]], gridP_[c[2]], gridP_[c[3]]};
        const glm::dvec2 px[4] = {
            {gridX_[static_cast<std::size_t>(i)], gridY_[static_cast<std::size_t>(j)]},
            {gridX_[static_cast<std::size_t>(i) + 1], gridY_[static_cast<std::size_t>(j)]},
            {gridX_[static_cast<std::size_t>(i) + 1], gridY_[static_cast<std::size_t>(j) + 1]},
            {gridX_[static_cast<std::size_t>(i)], gridY_[static_cast<std::size_t>(j) + 1]}};
        const double z[4] = {gridZ_[c[0]], gridZ_[c[1]], gridZ_[c[2]], gridZ_[c[3]]};
        emit(w, px, z);
      }
  }

  // Colour (+ eye z when written) into `out`, coverage sized for the caller to fill.
  void readLayer(gl::Framebuffer& fbo, const Camera& target, Layer& out) {
    fbo.readColour(out.colour);
    if (options_.writeEyeZ) fbo.readFloatChannel(out.eyeZ);
    else out.eyeZ.resize(0, 0);
    if (out.coverage.width() != target.width || out.coverage.height() != target.height)
      out.coverage.resize(target.width, target.height);
    if (!options_.markLargeQuads) out.largeQuad.resize(0, 0);
    else if (out.largeQuad.width() != target.width || out.largeQuad.height() != target.height)
      out.largeQuad.resize(target.width, target.height);
  }

  std::vector<int> gridX_, gridY_;
  std::vector<double> gridZ_;
  std::vector<glm::dvec3> gridP_;

  Status ensureTarget(const Camera& target, bool eyeZ, bool stencil, gl::Framebuffer& fbo) {
    if (target.width < 1 || target.height < 1)
      return makeError("warp: target image size " + std::to_string(target.width) + "x" +
                       std::to_string(target.height) + ": expected at least 1x1");
    if (fbo.width() != target.width || fbo.height() != target.height) {
      auto fb = gl::Framebuffer::create(target.width, target.height, DepthMode::Fixed24, eyeZ,
                                        stencil);
      if (!fb) return fb.error();
      fbo = std::move(*fb);
    }
    return {};
  }

  // The culled index list of `bg` under foreground `fg`: built on the first
  // frame of the pair (quadsSeenBy + an index buffer upload), then reused.
  const CullEntry& cullFor(const GlWarpSource& bg, const GlWarpSource& fg) {
    ++cullClock_;
    CullEntry* e = nullptr;
    for (CullEntry& c : bg.culls)
      if (c.foreground == fg.serial) e = &c;
    if (e) {
      e->lastUse = cullClock_;
      return *e;
    }
    e = bg.culls[0].lastUse <= bg.culls[1].lastUse ? &bg.culls[0] : &bg.culls[1];
    const CullData& b = *bg.cull;
    quadsSeenBy(b.keyframe, b.mesh, fg.cull->keyframe, SeenOptions{}, seen_);
    cullIndices_.clear();
    int drawn = 0;
    for (std::size_t leaf = 0; leaf < seen_.size(); ++leaf) {
      if (seen_[leaf]) continue;
      const auto first = static_cast<std::size_t>(b.leafFirst[leaf]) * 6;
      const auto last = static_cast<std::size_t>(b.leafFirst[leaf + 1]) * 6;
      cullIndices_.insert(cullIndices_.end(), b.indices.begin() + static_cast<std::ptrdiff_t>(first),
                          b.indices.begin() + static_cast<std::ptrdiff_t>(last));
      drawn += b.leafFirst[leaf + 1] - b.leafFirst[leaf];
    }
    if (!e->ibo) glGenBuffers(1, &e->ibo);
    const auto bytes = static_cast<GLsizeiptr>(cullIndices_.size() * sizeof(std::uint32_t));
    glBindVertexArray(0);  // do not disturb a VAO's element binding
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, e->ibo);
    if (bytes > e->bytes) {
      e->bytes = bytes + bytes / 4;
      glBufferData(GL_ELEMENT_ARRAY_BUFFER, e->bytes, nullptr, GL_DYNAMIC_DRAW);
    }
    if (bytes > 0) glBufferSubData(GL_ELEMENT_ARRAY_BUFFER, 0, bytes, cullIndices_.data());
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, 0);
    e->foreground = fg.serial;
    e->quads = drawn;
    e->culled = bg.quads - drawn;
    e->lastUse = cullClock_;
    return *e;
  }

  // Sky rectangles (behind everything) then the quads, into the bound target;
  // with `culled`, only the quads of its index list.
  void drawSource(const GlWarpSource& src, const Camera& target, float alpha,
                  const CullEntry* culled = nullptr) {
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, src.slot.tex);
    // Product in double, rounded to float once (see WarpVertex for the error).
    const glm::mat4 vp(target.projectionMatrix(DepthMode::Fixed24, options_.infiniteFar) *
                       target.viewMatrix());
    const glm::mat4 view(target.viewMatrix());
    program_.use();
    glUniformMatrix4fv(uViewProj_, 1, GL_FALSE, glm::value_ptr(vp));
    glUniformMatrix4fv(uView_, 1, GL_FALSE, glm::value_ptr(view));
    glUniform1i(uKey_, 0);
    glUniform1f(uAlpha_, alpha);
    glUniform1f(uPointScale_, 0.0f);
    glDisable(GL_CULL_FACE);  // quads may face away from the new view
    glDisable(GL_BLEND);
    glBindVertexArray(src.slot.vao);
    if (src.skyRects > 0) {
      // Sky first, behind everything: no depth test or write.
      glDisable(GL_DEPTH_TEST);
      glDepthMask(GL_FALSE);
      glUniform1f(uSkyEyeZ_, kSkyEyeZ);
      if (src.indexed)
        glDrawElements(GL_TRIANGLES, src.skyRects * 6, GL_UNSIGNED_INT,
                       reinterpret_cast<void*>(static_cast<std::size_t>(src.quads) * 6 *
                                               sizeof(std::uint32_t)));
      else
        glDrawArrays(GL_TRIANGLES, src.quads * 6, src.skyRects * 6);
      glEnable(GL_DEPTH_TEST);
      glDepthMask(GL_TRUE);
    }
    glUniform1f(uSkyEyeZ_, 0.0f);
    if (culled) {
      glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, culled->ibo);  // into the VAO, restored below
      glDrawElements(GL_TRIANGLES, culled->quads * 6, GL_UNSIGNED_INT, nullptr);
      glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, src.slot.ibo);
    } else if (src.indexed) {
      glDrawElements(GL_TRIANGLES, src.quads * 6, GL_UNSIGNED_INT, nullptr);
    } else {
      glDrawArrays(GL_TRIANGLES, 0, src.quads * 6);
    }
    if (src.points > 0) {
      glEnable(GL_PROGRAM_POINT_SIZE);
      glUniform1f(uPointScale_, static_cast<float>(target.fy() / src.focal));
      glDrawArrays(GL_POINTS, src.pointFirst, src.points);
      glDisable(GL_PROGRAM_POINT_SIZE);
    }
    glBindVertexArray(0);
  }

  std::vector<keyframe::PixelRect> skyRects_;
  WarpOptions options_;
  gl::Program program_;
  int uViewProj_ = -1, uView_ = -1, uKey_ = -1, uSkyEyeZ_ = -1, uAlpha_ = -1, uPointScale_ = -1;
  gl::Program queryProgram_;
  GLuint emptyVao_ = 0, query_ = 0;
  gl::Framebuffer pairFbo_;
  std::vector<WarpVertex> scratch_;
  std::vector<std::uint32_t> indices_;
  std::vector<std::uint32_t> cullIndices_;
  std::vector<WarpVertex> pointScratch_;
  std::vector<std::uint8_t> seen_;
  long serial_ = 0, cullClock_ = 0;
  std::unordered_map<WarpVertex, std::uint32_t, WarpVertexHash> shared_;  // Primitives::Shared
  std::shared_ptr<SlotPool> pool_ = std::make_shared<SlotPool>();
  gl::Framebuffer fbo_;
};

}  // namespace

Result<std::unique_ptr<Warper>> Warper::create(const WarpOptions& options) {
  auto w = std::make_unique<GlWarper>();
  HW_TRY(w->init(options));
  return std::unique_ptr<Warper>(std::move(w));
}

}  // namespace hw::warp
