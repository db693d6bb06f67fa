#include "warp/warper.h"

#include <cstring>
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
uniform float uAlpha;    // 1; 254/255 marks the background layer in a fused pair
layout(location = 0) out vec4 oColour;
layout(location = 1) out float oEyeZ;
void main() {
  oColour = vec4(textureProj(uKey, vTex).rgb, uAlpha);
  oEyeZ = uSkyEyeZ > 0.0 ? uSkyEyeZ : vEyeZ;
}
)";

// The coverage query: a full-screen triangle, no outputs (colour writes off).
constexpr const char* kQueryVertex = R"(#version 450 core
void main() {
  vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
)";
constexpr const char* kQueryFragment = R"(#version 450 core
void main() {}
)";

// Alpha of background pixels in a fused pair: exactly 254 in RGBA8.
constexpr float kBackgroundAlpha = 254.0f / 255.0f;

struct WarpVertex {
  float pos[4];
  float tex[3];
};

class GlWarpSource final : public WarpSource {
 public:
  ~GlWarpSource() override {
    if (vao) glDeleteVertexArrays(1, &vao);
    if (vbo) glDeleteBuffers(1, &vbo);
    if (tex) glDeleteTextures(1, &tex);
  }
  const Camera& keyframeCamera() const override { return camera; }
  int quadCount() const override { return quads; }

  Camera camera;
  int quads = 0;
  int skyRects = 0;  // drawn after the quads' vertices in the same buffer
  GLuint vao = 0, vbo = 0, tex = 0;
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
    auto q = gl::Program::build("coverage query", kQueryVertex, kQueryFragment);
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
    glGenVertexArrays(1, &src->vao);
    glBindVertexArray(src->vao);
    glGenBuffers(1, &src->vbo);
    glBindBuffer(GL_ARRAY_BUFFER, src->vbo);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(scratch_.size() * sizeof(WarpVertex)),
                 scratch_.data(), GL_STATIC_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, sizeof(WarpVertex),
                          reinterpret_cast<void*>(offsetof(WarpVertex, pos)));
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(WarpVertex),
                          reinterpret_cast<void*>(offsetof(WarpVertex, tex)));
    glBindVertexArray(0);

    glGenTextures(1, &src->tex);
    glBindTexture(GL_TEXTURE_2D, src->tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    // Image row 0 (top) at t = 0, matching t = v / height above.
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, kf.colour.width(), kf.colour.height(), 0, GL_RGBA,
                 GL_UNSIGNED_BYTE, kf.colour.data());
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
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
    fbo_.readColour(out.colour);
    if (options_.writeEyeZ) fbo_.readFloatChannel(out.eyeZ);
    else out.eyeZ.resize(0, 0);
    if (out.coverage.width() != target.width || out.coverage.height() != target.height)
      out.coverage.resize(target.width, target.height);
    const std::size_t n = out.colour.size();
    const Rgba8* c = out.colour.data();
    std::uint8_t* cov = out.coverage.data();
    int uncovered = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const int on = c[i].a != 0;
      cov[i] = static_cast<std::uint8_t>(on);
      uncovered += 1 - on;
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
    if (drawBg) {
      // Background only where the foreground left pixels empty; its own
      // depth test among its quads, not against the foreground's (overlay).
      glClear(GL_DEPTH_BUFFER_BIT);
      drawSource(static_cast<const GlWarpSource&>(*background), target, kBackgroundAlpha);
    }
    glDisable(GL_STENCIL_TEST);
    glFinish();
    const double bgMs = sw.lap();
    pairFbo_.readColour(out.colour);
    if (options_.writeEyeZ) pairFbo_.readFloatChannel(out.eyeZ);
    else out.eyeZ.resize(0, 0);
    if (out.coverage.width() != target.width || out.coverage.height() != target.height)
      out.coverage.resize(target.width, target.height);
    const std::size_t n = out.colour.size();
    Rgba8* c = out.colour.data();
    std::uint8_t* cov = out.coverage.data();
    int fromBg = 0, uncovered = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint8_t a = c[i].a;
      const int isBg = a == 254, isNone = a == 0;
      cov[i] = static_cast<std::uint8_t>(isNone ? 0 : 1 + isBg);
      c[i].a = isNone ? 0 : 255;
      fromBg += isBg;
      uncovered += isNone;
    }
    if (stats) {
      stats->foregroundMs = fgMs;
      stats->backgroundMs = bgMs;
      stats->readbackMs = sw.ms();
      stats->quadsForeground = fg.quads;
      stats->quadsBackground = drawBg ? background->quadCount() : 0;
      stats->backgroundDrawn = drawBg;
      stats->uncoveredByForeground = static_cast<int>(emptyAfterFg);
      stats->fromBackground = fromBg;
      stats->uncovered = uncovered;
    }
    return gl::checkGlError("Warper::warpPair");
  }

  const WarpOptions& options() const override { return options_; }

 private:
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

  // Sky rectangles (behind everything) then the quads, into the bound target.
  void drawSource(const GlWarpSource& src, const Camera& target, float alpha) {
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, src.tex);
    const glm::mat4 vp(target.projectionMatrix(DepthMode::Fixed24, options_.infiniteFar) *
                       target.viewMatrix());
    const glm::mat4 view(target.viewMatrix());
    program_.use();
    glUniformMatrix4fv(uViewProj_, 1, GL_FALSE, glm::value_ptr(vp));
    glUniformMatrix4fv(uView_, 1, GL_FALSE, glm::value_ptr(view));
    glUniform1i(uKey_, 0);
    glUniform1f(uAlpha_, alpha);
    glDisable(GL_CULL_FACE);  // quads may face away from the new view
    glDisable(GL_BLEND);
    glBindVertexArray(src.vao);
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
  }

  std::vector<keyframe::PixelRect> skyRects_;
  WarpOptions options_;
  gl::Program program_;
  int uViewProj_ = -1, uView_ = -1, uKey_ = -1, uSkyEyeZ_ = -1, uAlpha_ = -1;
  gl::Program queryProgram_;
  GLuint emptyVao_ = 0, query_ = 0;
  gl::Framebuffer pairFbo_;
  std::vector<WarpVertex> scratch_;
  gl::Framebuffer fbo_;
};

}  // namespace

Result<std::unique_ptr<Warper>> Warper::create(const WarpOptions& options) {
  auto w = std::make_unique<GlWarper>();
  HW_TRY(w->init(options));
  return std::unique_ptr<Warper>(std::move(w));
}

}  // namespace hw::warp
