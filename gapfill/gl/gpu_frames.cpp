#include "gapfill/gl/gpu_frames.h"

#include <cstring>
#include <string>

#include "core/check.h"
#include "core/gl/gl_api.h"
#include "warp/layer.h"

namespace hw::gapfill {
namespace {

// compose() with the fused pair as the foreground layer, per pixel (texel
// for texel, row 0 = bottom throughout). Byte values pass through UNORM8
// unchanged (x/255 is written back as x).
const char* kFragment = R"(#version 450 core
uniform sampler2D pair;
uniform sampler2D previousColour;
uniform sampler2D previousMask;
uniform int hasPrevious;
layout(location = 0) out vec4 colour;
layout(location = 1) out vec4 mask;  // R: 0 hole, 1 foreground, 2 background (/255); G: valid
const float kByte = 1.0 / 255.0;
void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  vec4 c = texelFetch(pair, p, 0);
  int a = int(round(c.a * 255.0));
  if (a != 0) {
    bool background = a == 254 || a == 252;  // warp::kAlphaBackground, kAlphaLargeBackground
    colour = vec4(c.rgb, 1.0);
    mask = vec4(background ? 2.0 * kByte : kByte, kByte, 0.0, 0.0);
  } else if (hasPrevious != 0 && texelFetch(previousMask, p, 0).g > 0.0) {
    colour = texelFetch(previousColour, p, 0);
    mask = vec4(0.0, kByte, 0.0, 0.0);
  } else {
    colour = vec4(0.0, 0.0, 0.0, 1.0);  // kUnfilledColour
    mask = vec4(0.0);
  }
})";

unsigned makeTexture(GLint internal, GLenum format, int w, int h) {
  GLuint t = 0;
  glGenTextures(1, &t);
  glBindTexture(GL_TEXTURE_2D, t);
  glTexImage2D(GL_TEXTURE_2D, 0, internal, w, h, 0, format, GL_UNSIGNED_BYTE, nullptr);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glBindTexture(GL_TEXTURE_2D, 0);
  return t;
}

unsigned makeFramebuffer(unsigned colour0, unsigned colour1) {
  GLuint f = 0;
  glGenFramebuffers(1, &f);
  glBindFramebuffer(GL_FRAMEBUFFER, f);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, colour0, 0);
  if (colour1) {
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, colour1, 0);
    const GLenum both[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glDrawBuffers(2, both);
  }
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return f;
}

}  // namespace

static_assert(warp::kAlphaBackground == 254 && warp::kAlphaLargeBackground == 252,
              "the compose shader's background codes");

GpuFrames::~GpuFrames() {
  release();
  if (vao_) glDeleteVertexArrays(1, &vao_);
}

void GpuFrames::release() {
  for (Target& t : t_) {
    for (unsigned* f : {&t.both, &t.colourOnly, &t.maskOnly})
      if (*f) glDeleteFramebuffers(1, f);
    for (unsigned* x : {&t.colour, &t.mask})
      if (*x) glDeleteTextures(1, x);
    t = Target{};
  }
  width_ = height_ = 0;
}

Status GpuFrames::ensureProgram() {
  if (program_.id()) return {};
  auto p = gl::Program::build("frame composition on the GPU", gl::kFullScreenTriangleVertex,
                              kFragment);
  if (!p) return p.error();
  program_ = std::move(*p);
  program_.use();
  glUniform1i(program_.uniform("pair"), 0);
  glUniform1i(program_.uniform("previousColour"), 1);
  glUniform1i(program_.uniform("previousMask"), 2);
  uHasPrevious_ = program_.uniform("hasPrevious");
  glGenVertexArrays(1, &vao_);
  return gl::checkGlError("frame composition set-up");
}

Status GpuFrames::resize(int w, int h) {
  if (w == width_ && h == height_ && t_[0].colour) return {};
  GLint maxSize = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxSize);
  if (w < 1 || h < 1 || w > maxSize || h > maxSize)
    return makeError("frames on the GPU: size " + std::to_string(w) + "x" + std::to_string(h) +
                     " is outside 1.." + std::to_string(maxSize));
  release();
  for (Target& t : t_) {
    t.colour = makeTexture(GL_RGBA8, GL_RGBA, w, h);
    t.mask = makeTexture(GL_RG8, GL_RG, w, h);
    t.both = makeFramebuffer(t.colour, t.mask);
    t.colourOnly = makeFramebuffer(t.colour, 0);
    t.maskOnly = makeFramebuffer(t.mask, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, t.both);
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
      release();
      return makeError("frames on the GPU: framebuffer incomplete (status " +
                       std::to_string(status) + ")");
    }
  }
  width_ = w;
  height_ = h;
  clearMask(t_[0].maskOnly, 0, 0);
  clearMask(t_[1].maskOnly, 0, 0);
  return gl::checkGlError("frames on the GPU: allocation");
}

void GpuFrames::clearMask(unsigned fbo, std::uint8_t code, std::uint8_t valid) {
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glDisable(GL_SCISSOR_TEST);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  const float v[4] = {static_cast<float>(code) / 255.0f, static_cast<float>(valid) / 255.0f, 0, 0};
  glClearBufferfv(GL_COLOR, 0, v);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

Status GpuFrames::compose(unsigned pairTexture, bool hasPrevious) {
  HW_TRY(ensureProgram());
  HW_CHECK(width_ > 0);
  const Target& cur = t_[current_];
  const Target& prev = t_[current_ ^ 1];
  glBindFramebuffer(GL_FRAMEBUFFER, cur.both);
  glViewport(0, 0, width_, height_);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_STENCIL_TEST);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  program_.use();
  glUniform1i(uHasPrevious_, hasPrevious ? 1 : 0);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, pairTexture);
  glActiveTexture(GL_TEXTURE1);
  glBindTexture(GL_TEXTURE_2D, prev.colour);
  glActiveTexture(GL_TEXTURE2);
  glBindTexture(GL_TEXTURE_2D, prev.mask);
  glBindVertexArray(vao_);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glActiveTexture(GL_TEXTURE2);
  glBindTexture(GL_TEXTURE_2D, 0);
  glActiveTexture(GL_TEXTURE1);
  glBindTexture(GL_TEXTURE_2D, 0);
  glActiveTexture(GL_TEXTURE0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return gl::checkGlError("frames on the GPU: composition");
}

Status GpuFrames::upload(const Image<Rgba8>& colour) {
  HW_CHECK_EQ(colour.width(), width_);
  HW_CHECK_EQ(colour.height(), height_);
  const auto w = static_cast<std::size_t>(width_);
  rowScratch_.resize(w * static_cast<std::size_t>(height_));
  for (int y = 0; y < height_; ++y)  // GL row 0 is the bottom
    std::memcpy(static_cast<void*>(rowScratch_.data() + static_cast<std::size_t>(height_ - 1 - y) * w),
                colour.data() + static_cast<std::size_t>(y) * w, w * sizeof(Rgba8));
  glBindTexture(GL_TEXTURE_2D, t_[current_].colour);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE,
                  rowScratch_.data());
  glBindTexture(GL_TEXTURE_2D, 0);
  markAllDrawn();
  return gl::checkGlError("frames on the GPU: upload");
}

unsigned GpuFrames::copyTarget() const { return t_[current_].colourOnly; }

void GpuFrames::markValid(const PixelRect* rects, int count) {
  glBindFramebuffer(GL_FRAMEBUFFER, t_[current_].maskOnly);
  glEnable(GL_SCISSOR_TEST);
  glColorMask(GL_FALSE, GL_TRUE, GL_FALSE, GL_FALSE);  // valid only; the hole code stays
  const float v[4] = {0, 1.0f / 255.0f, 0, 0};
  for (int k = 0; k < count; ++k) {
    const PixelRect& r = rects[k];
    glScissor(r.x0, height_ - r.y1, r.width(), r.height());
    glClearBufferfv(GL_COLOR, 0, v);
  }
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glDisable(GL_SCISSOR_TEST);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void GpuFrames::markAllDrawn() { clearMask(t_[current_].maskOnly, 1, 1); }

void GpuFrames::readMasks(Frame& frame) {
  const auto w = static_cast<std::size_t>(width_);
  const std::size_t n = w * static_cast<std::size_t>(height_);
  maskScratch_.resize(2 * n);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, t_[current_].maskOnly);
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width_, height_, GL_RG, GL_UNSIGNED_BYTE, maskScratch_.data());
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  if (frame.colour.width() != width_ || frame.colour.height() != height_)
    frame.colour.resize(width_, height_);
  if (frame.holesBefore.width() != width_ || frame.holesBefore.height() != height_)
    frame.holesBefore.resize(width_, height_);
  if (frame.valid.width() != width_ || frame.valid.height() != height_)
    frame.valid.resize(width_, height_);
  int nf = 0, nb = 0, np = 0, nu = 0, nh = 0;
  for (int y = 0; y < height_; ++y) {
    const std::uint8_t* m = maskScratch_.data() + 2 * static_cast<std::size_t>(height_ - 1 - y) * w;
    std::uint8_t* holes = frame.holesBefore.data() + static_cast<std::size_t>(y) * w;
    std::uint8_t* valid = frame.valid.data() + static_cast<std::size_t>(y) * w;
    for (std::size_t x = 0; x < w; ++x) {
      const std::uint8_t code = m[2 * x], ok = m[2 * x + 1] != 0;
      holes[x] = code == 0;
      valid[x] = ok;
      nf += code == 1;
      nb += code == 2;
      nh += code == 0;
      np += code == 0 && ok;
      nu += !ok;
    }
  }
  frame.fromForeground = nf;
  frame.fromBackground = nb;
  frame.fromPrevious = np;
  frame.unfilled = nu;
  frame.blended = 0;
  frame.holeFractionBefore = n ? static_cast<double>(nh) / static_cast<double>(n) : 0.0;
  frame.holeFractionAfter = n ? static_cast<double>(nu) / static_cast<double>(n) : 0.0;
}

void GpuFrames::readColour(Image<Rgba8>& out) {
  const auto w = static_cast<std::size_t>(width_);
  rowScratch_.resize(w * static_cast<std::size_t>(height_));
  glBindFramebuffer(GL_READ_FRAMEBUFFER, t_[current_].colourOnly);
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, rowScratch_.data());
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  if (out.width() != width_ || out.height() != height_) out.resize(width_, height_);
  for (int y = 0; y < height_; ++y)
    std::memcpy(static_cast<void*>(out.data() + static_cast<std::size_t>(y) * w),
                rowScratch_.data() + static_cast<std::size_t>(height_ - 1 - y) * w,
                w * sizeof(Rgba8));
}

unsigned GpuFrames::colourTexture() const { return t_[current_].colour; }

}  // namespace hw::gapfill
