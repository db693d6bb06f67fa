#pragma once
// Offscreen render target: RGBA8 colour (+ optional R32F channel) and a depth
// attachment in one of the three depth modes (24-bit fixed, 32F, 32F
// reversed-Z). bind() sets the whole state the mode needs (sokol habit: no
// inherited state). Readbacks flip rows so Image row 0 is the top.
#include <cstdint>
#include <vector>

#include "core/camera.h"
#include "core/image.h"
#include "core/result.h"

namespace hw::gl {

class Framebuffer {
 public:
  Framebuffer() = default;
  ~Framebuffer();
  Framebuffer(Framebuffer&& o) noexcept { *this = std::move(o); }
  Framebuffer& operator=(Framebuffer&& o) noexcept;
  Framebuffer(const Framebuffer&) = delete;
  Framebuffer& operator=(const Framebuffer&) = delete;

  // Needs a current context. withFloatChannel adds colour attachment 1 (R32F);
  // withStencil makes the depth attachment DEPTH24_STENCIL8 (Fixed24 only).
  static Result<Framebuffer> create(int width, int height, DepthMode mode,
                                    bool withFloatChannel = false, bool withStencil = false);

  // Binds, sets viewport, clip control and depth function for the mode, and
  // clears colour to `clear` (and the float channel to 0), depth to far and
  // the stencil (if any) to 0; the stencil test is left disabled.
  void bindAndClear(float r, float g, float b, float a);

  void readColour(Image<Rgba8>& out);
  // The w × h pixels from (x0, y0) (row 0 = top) into a w × h image.
  void readColourRect(int x0, int y0, int w, int h, Image<Rgba8>& out);
  void readFloatChannel(Image<float>& out);
  // Depth as z' and eye z for a camera with these near/far planes.
  void readDepth(double nearPlane, double farPlane, Image<double>& zPrime, Image<float>& eyeZ,
                 Image<std::uint8_t>& covered);

  int width() const { return width_; }
  int height() const { return height_; }
  // The GL framebuffer and its colour attachment (RGBA8, row 0 = bottom),
  // for copies on the GPU (glBlitFramebuffer, texelFetch).
  unsigned id() const { return fbo_; }
  unsigned colourTexture() const { return colour_; }
  DepthMode depthMode() const { return mode_; }

 private:
  void release();
  unsigned fbo_ = 0, colour_ = 0, floatTex_ = 0, depth_ = 0;
  int width_ = 0, height_ = 0;
  DepthMode mode_ = DepthMode::Fixed24;
  bool hasFloat_ = false;
  bool hasStencil_ = false;
  std::vector<std::uint32_t> rawDepth_;  // readback scratch, reused
  std::vector<float> rawFloat_;
  std::vector<Rgba8> rowScratch_;
};

}  // namespace hw::gl
