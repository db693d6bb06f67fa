#include "core/gl/framebuffer.h"

#include <cstring>
#include <utility>

#include "core/check.h"
#include "core/depth.h"
#include "core/gl/gl_api.h"

namespace hw::gl {

Framebuffer::~Framebuffer() { release(); }

Framebuffer& Framebuffer::operator=(Framebuffer&& o) noexcept {
  if (this != &o) {
    release();
    fbo_ = std::exchange(o.fbo_, 0u);
    colour_ = std::exchange(o.colour_, 0u);
    floatTex_ = std::exchange(o.floatTex_, 0u);
    depth_ = std::exchange(o.depth_, 0u);
    width_ = o.width_;
    height_ = o.height_;
    mode_ = o.mode_;
    hasFloat_ = o.hasFloat_;
    hasStencil_ = o.hasStencil_;
    rawDepth_ = std::move(o.rawDepth_);
    rawFloat_ = std::move(o.rawFloat_);
    rowScratch_ = std::move(o.rowScratch_);
  }
  return *this;
}

void Framebuffer::release() {
  if (fbo_) glDeleteFramebuffers(1, &fbo_);
  if (colour_) glDeleteTextures(1, &colour_);
  if (floatTex_) glDeleteTextures(1, &floatTex_);
  if (depth_) glDeleteTextures(1, &depth_);
  fbo_ = colour_ = floatTex_ = depth_ = 0;
}

Result<Framebuffer> Framebuffer::create(int width, int height, DepthMode mode,
                                        bool withFloatChannel, bool withStencil) {
  GLint maxSize = 0;
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &maxSize);
  if (width < 1 || height < 1 || width > maxSize || height > maxSize)
    return makeError("framebuffer size " + std::to_string(width) + "x" + std::to_string(height) +
                     " is outside 1.." + std::to_string(maxSize));
  if (withStencil && mode != DepthMode::Fixed24)
    return makeError(std::string("framebuffer: a stencil needs the fixed24 depth mode, not ") +
                     depthModeName(mode));
  Framebuffer fb;
  fb.hasStencil_ = withStencil;
  fb.width_ = width;
  fb.height_ = height;
  fb.mode_ = mode;
  fb.hasFloat_ = withFloatChannel;
  glGenFramebuffers(1, &fb.fbo_);
  glBindFramebuffer(GL_FRAMEBUFFER, fb.fbo_);
  auto makeTex = [&](GLint internal, GLenum format, GLenum type) {
    GLuint t = 0;
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_2D, t);
    glTexImage2D(GL_TEXTURE_2D, 0, internal, width, height, 0, format, type, nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    return t;
  };
  fb.colour_ = makeTex(GL_RGBA8, GL_RGBA, GL_UNSIGNED_BYTE);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, fb.colour_, 0);
  if (withFloatChannel) {
    fb.floatTex_ = makeTex(GL_R32F, GL_RED, GL_FLOAT);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, fb.floatTex_, 0);
  }
  if (withStencil)
    fb.depth_ = makeTex(GL_DEPTH24_STENCIL8, GL_DEPTH_STENCIL, GL_UNSIGNED_INT_24_8);
  else if (mode == DepthMode::Fixed24)
    fb.depth_ = makeTex(GL_DEPTH_COMPONENT24, GL_DEPTH_COMPONENT, GL_UNSIGNED_INT);
  else
    fb.depth_ = makeTex(GL_DEPTH_COMPONENT32F, GL_DEPTH_COMPONENT, GL_FLOAT);
  glFramebufferTexture2D(GL_FRAMEBUFFER,
                         withStencil ? GL_DEPTH_STENCIL_ATTACHMENT : GL_DEPTH_ATTACHMENT,
                         GL_TEXTURE_2D, fb.depth_, 0);
  const GLenum bufs[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  glDrawBuffers(withFloatChannel ? 2 : 1, bufs);
  const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "0x%04x", status);
    return makeError(std::string("framebuffer incomplete (status ") + buf + ") for depth mode " +
                     depthModeName(mode));
  }
  HW_TRY(checkGlError("Framebuffer::create"));
  return fb;
}

void Framebuffer::bindAndClear(float r, float g, float b, float a) {
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glViewport(0, 0, width_, height_);
  glEnable(GL_DEPTH_TEST);
  glDepthMask(GL_TRUE);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  if (mode_ == DepthMode::Float32Reversed) {
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glDepthFunc(GL_GREATER);
    glClearDepth(0.0);
  } else {
    glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
    glDepthFunc(GL_LESS);
    glClearDepth(1.0);
  }
  glClearColor(r, g, b, a);
  glDisable(GL_STENCIL_TEST);
  if (hasStencil_) {
    glStencilMask(0xFF);
    glClearStencil(0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
  } else {
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  }
  if (hasFloat_) {
    // Attachment 1 cleared separately to 0 (no coverage / no depth).
    const GLenum only1[2] = {GL_NONE, GL_COLOR_ATTACHMENT1};
    glDrawBuffers(2, only1);
    glClearColor(0, 0, 0, 0);
    glClear(GL_COLOR_BUFFER_BIT);
    const GLenum both[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glDrawBuffers(2, both);
  }
}

void Framebuffer::readColour(Image<Rgba8>& out) { readColourRect(0, 0, width_, height_, out); }

void Framebuffer::readColourRect(int x0, int y0, int w, int h, Image<Rgba8>& out) {
  HW_CHECK(x0 >= 0 && y0 >= 0 && w >= 1 && h >= 1 && x0 + w <= width_ && y0 + h <= height_);
  if (out.width() != w || out.height() != h) out.resize(w, h);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  // GL rows count from the bottom: the rect's top row y0 is GL row height - 1 - y0.
  glReadPixels(x0, height_ - y0 - h, w, h, GL_RGBA, GL_UNSIGNED_BYTE, out.data());
  const std::size_t rowBytes = static_cast<std::size_t>(w) * sizeof(Rgba8);
  rowScratch_.resize(static_cast<std::size_t>(w));
  for (int y = 0; y < h / 2; ++y) {
    Rgba8* a = &out(0, y);
    Rgba8* b = &out(0, h - 1 - y);
    std::memcpy(rowScratch_.data(), a, rowBytes);
    std::memcpy(a, b, rowBytes);
    std::memcpy(b, rowScratch_.data(), rowBytes);
  }
}

void Framebuffer::readFloatChannel(Image<float>& out) {
  if (out.width() != width_ || out.height() != height_) out.resize(width_, height_);
  rawFloat_.resize(static_cast<std::size_t>(width_) * height_);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
  glReadBuffer(GL_COLOR_ATTACHMENT1);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glReadPixels(0, 0, width_, height_, GL_RED, GL_FLOAT, rawFloat_.data());
  for (int y = 0; y < height_; ++y)
    std::memcpy(&out(0, y), rawFloat_.data() + static_cast<std::size_t>(height_ - 1 - y) * width_,
                static_cast<std::size_t>(width_) * sizeof(float));
}

void Framebuffer::readDepth(double nearPlane, double farPlane, Image<double>& zPrime,
                            Image<float>& eyeZ, Image<std::uint8_t>& covered) {
  rawDepth_.resize(static_cast<std::size_t>(width_) * height_);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo_);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  if (mode_ == DepthMode::Fixed24)
    glReadPixels(0, 0, width_, height_, GL_DEPTH_COMPONENT, GL_UNSIGNED_INT, rawDepth_.data());
  else
    glReadPixels(0, 0, width_, height_, GL_DEPTH_COMPONENT, GL_FLOAT, rawDepth_.data());
  convertDepth(rawDepth_.data(), width_, height_, mode_, nearPlane, farPlane, zPrime, eyeZ,
               covered);
}

}  // namespace hw::gl
