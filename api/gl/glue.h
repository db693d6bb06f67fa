#pragma once
// The API's GL pieces: adopting the caller's current context, and drawing a
// frame into its default framebuffer (Renderer::present).
#include <cstdint>
#include <memory>
#include <string>

#include "core/result.h"

namespace hybridwalk::detail {

// Loads the entry points from the current context through `getProc` and
// returns its GL_RENDERER. Error when `getProc` is null or an entry point
// of OpenGL 4.5 core is missing (no current context, or an older one).
hw::Result<std::string> adoptCurrentContext(void* (*getProc)(const char*));

class Presenter {
 public:
  virtual ~Presenter() = default;
  // Needs a current context.
  static hw::Result<std::unique_ptr<Presenter>> create();
  // RGBA8 pixels, row 0 = top, drawn over the viewport of framebuffer 0.
  virtual hw::Status draw(const std::uint8_t* rgba, int width, int height, int viewportWidth,
                          int viewportHeight) = 0;
};

}  // namespace hybridwalk::detail
