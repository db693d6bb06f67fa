#pragma once
// Frames kept on the GPU, for a driver that shows them there (the viewer with
// OpenGL's warper): the fused pair of layers composed with the previous
// frame in one pass over textures (the paper's overlay with the copy
// fallback), rectangles the geometry renderer drew copied in, keyframes and
// geometry frames put in, the frame shown from its texture. Only the masks
// (which pixels are holes, which are valid) are read back: the hole pass
// chooses its rectangles from them and the statistics count them. The pixels
// are gapfill::compose's and the hole pass's on the CPU, bit for bit
// (tests/gl/session_gpu_frames_test.cpp).
#include <cstdint>
#include <vector>

#include "core/gl/shader.h"
#include "core/image.h"
#include "core/rect.h"
#include "core/result.h"
#include "gapfill/compose.h"

namespace hw::gapfill {

class GpuFrames {
 public:
  GpuFrames() = default;
  ~GpuFrames();
  GpuFrames(const GpuFrames&) = delete;
  GpuFrames& operator=(const GpuFrames&) = delete;

  // Both frames (the current one and the previous) at w x h; a new size
  // leaves their content undefined (the caller forgets the previous frame).
  // Needs a current GL context. Errors: a size the GL cannot hold, GL errors.
  Status resize(int w, int h);
  int width() const { return width_; }
  int height() const { return height_; }

  // The current frame from a fused pair's texture (warp::Warper::pairTexture,
  // this size): its colour where it covers (alpha 255), else the previous
  // frame's pixel where that is valid (`hasPrevious`), else kUnfilledColour.
  // Masks: holes where the pair covers nothing; valid unless unfilled.
  Status compose(unsigned pairTexture, bool hasPrevious);
  // The current frame = `colour` (row 0 = top; this size, checked): no holes,
  // every pixel valid.
  Status upload(const Image<Rgba8>& colour);
  // GL framebuffer whose colour attachment 0 is the current frame's colour
  // texture (row 0 = bottom): where the geometry renderer copies its pixels.
  unsigned copyTarget() const;
  // After rectangles (row 0 = top) were copied in: their pixels are valid.
  void markValid(const PixelRect* rects, int count);
  // After a whole image was copied in: no holes, every pixel valid.
  void markAllDrawn();

  // The current frame's masks and counts into `frame` (row 0 = top):
  // holesBefore, valid, fromForeground/Background/Previous, unfilled and the
  // two fractions, as compose() sets them. frame.colour is resized to this
  // size but not read back (readColour).
  void readMasks(Frame& frame);
  void readColour(Image<Rgba8>& out);  // row 0 = top
  // The current frame's colour texture (RGBA8, row 0 = bottom), to show.
  unsigned colourTexture() const;

  // The current frame becomes the previous one (the next compose reads it).
  void swap() { current_ ^= 1; }

 private:
  struct Target {
    unsigned colour = 0, mask = 0;  // RGBA8; RG8: R = 0 hole, 1 foreground, 2 background; G = valid
    unsigned both = 0;              // framebuffer: colour + mask (compose)
    unsigned colourOnly = 0;        // framebuffer: colour (copies into it)
    unsigned maskOnly = 0;          // framebuffer: mask (clears, readback)
  };
  Status ensureProgram();
  void release();
  void clearMask(unsigned fbo, std::uint8_t code, std::uint8_t valid);

  Target t_[2];
  int current_ = 0;
  int width_ = 0, height_ = 0;
  gl::Program program_;
  int uHasPrevious_ = -1;
  unsigned vao_ = 0;
  std::vector<std::uint8_t> maskScratch_;
  std::vector<Rgba8> rowScratch_;
};

}  // namespace hw::gapfill
