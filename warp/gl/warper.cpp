#include "warp/warper.h"

#include <algorithm>
#include <cstring>
#include <memory>
#include <vector>

#include <glm/gtc/type_ptr.hpp>

#include "core/gl/framebuffer.h"
#include "core/gl/gl_api.h"
#include "core/gl/shader.h"
#include "core/timer.h"
#include "warp/sky_rects.h"

namespace hw::warp {

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
out vec3 vTex;
out float vEyeZ;
void main() {
  vec4 p = aPos;
  vTex = aTex;
  vEyeZ = -(uView * p).z;
  gl_Position = uViewProj * p;
}
)";

constexpr const char* kFragment = R"(#version 450 core
in vec3 vTex;
in float vEyeZ;
uniform sampler2D uKey;
uniform float uSkyEyeZ;  // > 0 while drawing sky rectangles
layout(location = 0) out vec4 oColour;
layout(location = 1) out float oEyeZ;  // R32F: relative 6e-8, vs the depth merge's 2 % tolerance
void main() {
  oColour = vec4(textureProj(uKey, vTex).rgb, 1.0);
  oEyeZ = uSkyEyeZ > 0.0 ? uSkyEyeZ : vEyeZ;
}
)";

// Float is enough here (issue #7, "precision where it matters"); corners,
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
};

// The GL objects of one uploaded keyframe, with the storage sizes they hold.
struct GlSlot {
  GLuint vao = 0, vbo = 0, tex = 0;
  GLsizeiptr vboBytes = 0;
  int texWidth = 0, texHeight = 0;
};

void destroySlot(GlSlot& s) {
  if (s.vao) glDeleteVertexArrays(1, &s.vao);
  if (s.vbo) glDeleteBuffers(1, &s.vbo);
  if (s.tex) glDeleteTextures(1, &s.tex);
  s = GlSlot{};
}

// Slots of dropped sources, reused by the next upload. llvmpipe keeps buffer
// and texture storage in malloc'd memory, so creating and deleting a vertex
// buffer (200 KiB–1 MiB, a different size for every keyframe) and a texture
// per keyframe fragmented glibc's heap: the 10,000-frame soak's [heap] RSS
// grew 42 → 51 MiB while the live heap stayed at 43 MiB (issue #7). A walk
// holds at most three sources at a time, so a few slots cover it.
struct SlotPool {
  static constexpr std::size_t kMaxFree = 4;
  std::vector<GlSlot> free;
  SlotPool() { free.reserve(kMaxFree); }
  ~SlotPool() {
    for (GlSlot& s : free) destroySlot(s);
  }
};

class GlWarpSource final : public WarpSource {
 public:
  ~GlWarpSource() override {
    if (pool && pool->free.size() < SlotPool::kMaxFree) pool->free.push_back(slot);
    else destroySlot(slot);
  }
  const Camera& keyframeCamera() const override { return camera; }
  int quadCount() const override { return quads; }

  Camera camera;
  int quads = 0;
  int skyRects = 0;  // drawn after the quads' vertices in the same buffer
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
    return gl::checkGlError("Warper::create");
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
    GlSlot& slot = src->slot;
    src->camera = kf.camera;
    src->quads = static_cast<int>(mesh.quads.size());
    const double invW = 1.0 / mesh.width, invH = 1.0 / mesh.height;
    if (options_.skyBackdrop) emptyRects(kf.covered, skyRects_);
    else skyRects_.clear();
    src->skyRects = static_cast<int>(skyRects_.size());
    scratch_.resize((mesh.quads.size() + skyRects_.size()) * 6);
    WarpVertex* out = scratch_.data();
    static constexpr int kTri[6] = {0, 1, 2, 0, 2, 3};
    for (const keyframe::Quad& q : mesh.quads) {
      for (int k : kTri) {
        WarpVertex& v = *out++;
        for (int c = 0; c < 3; ++c) v.pos[c] = static_cast<float>(q.world[k][c]);
        v.pos[3] = 1.0f;
        const double s = q.pixel[k].x * invW, t = q.pixel[k].y * invH;
        const double w = options_.texcoords == TexcoordMode::Projective ? q.eyeZ[k] : 1.0;
        v.tex[0] = static_cast<float>(s * w);
        v.tex[1] = static_cast<float>(t * w);
        v.tex[2] = static_cast<float>(w);
      }
    }
    // Sky: each corner is the direction through that keyframe image point,
    // scaled to depth 1 along W, so its projective texcoord is (s, t, 1).
    for (const keyframe::PixelRect& r : skyRects_) {
      const double us[4] = {double(r.x0), double(r.x1), double(r.x1), double(r.x0)};
      const double vs[4] = {double(r.y0), double(r.y0), double(r.y1), double(r.y1)};
      for (int k : kTri) {
        WarpVertex& v = *out++;
        const glm::dvec3 d = kf.camera.unproject(us[k], vs[k], 1.0) - kf.camera.eye;
        for (int c = 0; c < 3; ++c) v.pos[c] = static_cast<float>(d[c]);
        v.pos[3] = 0.0f;
        v.tex[0] = static_cast<float>(us[k] * invW);
        v.tex[1] = static_cast<float>(vs[k] * invH);
        v.tex[2] = 1.0f;
      }
    }
    if (!slot.vao) {
      glGenVertexArrays(1, &slot.vao);
      glBindVertexArray(slot.vao);
      glGenBuffers(1, &slot.vbo);
      glBindBuffer(GL_ARRAY_BUFFER, slot.vbo);
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
    HW_TRY(gl::checkGlError("Warper::upload"));
    if (stats) stats->uploadMs = sw.ms();
    return std::unique_ptr<WarpSource>(std::move(src));
  }

  Status warp(const WarpSource& source, const Camera& target, Layer& out,
              WarpStats* stats) override {
    const auto& src = static_cast<const GlWarpSource&>(source);
    if (target.width < 1 || target.height < 1)
      return makeError("warp: target image size " + std::to_string(target.width) + "x" +
                       std::to_string(target.height) + ": expected at least 1x1");
    if (fbo_.width() != target.width || fbo_.height() != target.height) {
      auto fb = gl::Framebuffer::create(target.width, target.height, DepthMode::Fixed24,
                                        options_.writeEyeZ);
      if (!fb) return fb.error();
      fbo_ = std::move(*fb);
    }
    Stopwatch sw;
    fbo_.bindAndClear(0, 0, 0, 0);
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
    glDisable(GL_CULL_FACE);  // quads may face away from the new view
    glDisable(GL_BLEND);
    glBindVertexArray(src.slot.vao);
    if (src.skyRects > 0) {
      // Sky first, behind everything: no depth test or write.
      glDisable(GL_DEPTH_TEST);
      glDepthMask(GL_FALSE);
      glUniform1f(uSkyEyeZ_, kSkyEyeZ);
      glDrawArrays(GL_TRIANGLES, src.quads * 6, src.skyRects * 6);
      glEnable(GL_DEPTH_TEST);
      glDepthMask(GL_TRUE);
    }
    glUniform1f(uSkyEyeZ_, 0.0f);
    glDrawArrays(GL_TRIANGLES, 0, src.quads * 6);
    glBindVertexArray(0);
    glFinish();
    const double drawMs = sw.lap();
    fbo_.readColour(out.colour);
    if (options_.writeEyeZ) fbo_.readFloatChannel(out.eyeZ);
    else out.eyeZ.resize(0, 0);
    if (out.coverage.width() != target.width || out.coverage.height() != target.height)
      out.coverage.resize(target.width, target.height);
    const std::size_t n = out.colour.size();
    const Rgba8* c = out.colour.data();
    std::uint8_t* cov = out.coverage.data();
    for (std::size_t i = 0; i < n; ++i) cov[i] = c[i].a != 0 ? 1 : 0;
    if (stats) {
      stats->drawMs = drawMs;
      stats->readbackMs = sw.ms();
      stats->quads = src.quads;
    }
    return gl::checkGlError("Warper::warp");
  }

  const WarpOptions& options() const override { return options_; }

 private:
  std::vector<keyframe::PixelRect> skyRects_;
  WarpOptions options_;
  gl::Program program_;
  int uViewProj_ = -1, uView_ = -1, uKey_ = -1, uSkyEyeZ_ = -1;
  std::vector<WarpVertex> scratch_;
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
