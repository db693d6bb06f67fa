// GLFW window context (run under Xvfb by scripts/test.sh). Without a display
// this FAILS rather than skips: CI must exercise the windowed path.
#include <gtest/gtest.h>

#include <cstdlib>

#include "core/gl/context.h"
#include "core/gl/framebuffer.h"
#include "core/gl/gl_api.h"

namespace hw {
namespace {

TEST(WindowContext, OpensA45CoreContextAndDraws) {
  ASSERT_NE(std::getenv("DISPLAY"), nullptr) << "no DISPLAY: run under xvfb-run (scripts/test.sh does)";
  auto w = gl::createWindowContext(96, 64, "hybridwalk test", true);
  ASSERT_TRUE(w.ok()) << w.error().message;
  EXPECT_NE((*w)->version().find("4."), std::string::npos) << (*w)->version();
  // Same FBO path as headless rendering, inside the window's context.
  auto fb = gl::Framebuffer::create(32, 16, DepthMode::Fixed24);
  ASSERT_TRUE(fb.ok()) << fb.error().message;
  fb->bindAndClear(0.2f, 0.4f, 0.6f, 1.0f);
  Image<Rgba8> img;
  fb->readColour(img);
  ASSERT_EQ(img.width(), 32);
  EXPECT_NEAR(img(5, 5).r, 51, 1);
  EXPECT_NEAR(img(5, 5).g, 102, 1);
  EXPECT_NEAR(img(5, 5).b, 153, 1);
  // And the window's own framebuffer.
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glViewport(0, 0, 96, 64);
  glClearColor(1.0f, 0.5f, 0.0f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  unsigned char px[4] = {0, 0, 0, 0};
  glReadPixels(10, 10, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, px);
  EXPECT_EQ(px[0], 255);
  EXPECT_NEAR(px[1], 128, 1);
  EXPECT_EQ(px[2], 0);
  (*w)->swapBuffers();
  EXPECT_TRUE(gl::checkGlError("window test").ok());
}

TEST(WindowContext, NoDisplayIsAClearError) {
  const char* saved = std::getenv("DISPLAY");
  std::string keep = saved ? saved : "";
  unsetenv("DISPLAY");
  auto w = gl::createWindowContext(32, 32, "x", false);
  if (!keep.empty()) setenv("DISPLAY", keep.c_str(), 1);
  ASSERT_FALSE(w.ok());
  EXPECT_NE(w.error().message.find("DISPLAY"), std::string::npos) << w.error().message;
}

}  // namespace
}  // namespace hw
