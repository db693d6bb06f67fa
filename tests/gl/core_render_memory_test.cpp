// gl::releaseFinishedRenderMemory (core/gl/render_memory.h), called by the
// walk before each 500-frame memory sample: it must leave the GL state it
// touches as it found it, draw nothing into the caller's target, and raise
// no GL error.
#include <gtest/gtest.h>

#include "core/gl/context.h"
#include "core/gl/framebuffer.h"
#include "core/gl/gl_api.h"
#include "core/gl/render_memory.h"
#include "core/image.h"
#include "gl_fixture.h"

namespace hw {
namespace {

class RenderMemory : public test::GlTest {};

TEST_F(RenderMemory, LeavesTargetBindingsScissorAndMaskAsFound) {
  ASSERT_EQ(gl::drainGlErrors(), 0);
  auto fb = gl::Framebuffer::create(16, 16, DepthMode::Fixed24);
  ASSERT_TRUE(fb) << fb.error().message;
  fb->bindAndClear(1.0f, 0.0f, 0.0f, 1.0f);
  GLint draw = 0, read = 0;
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &draw);
  glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read);
  ASSERT_NE(draw, 0);
  GLuint rbo = 0;  // a renderbuffer bound by the caller stays bound
  glGenRenderbuffers(1, &rbo);
  glBindRenderbuffer(GL_RENDERBUFFER, rbo);
  glEnable(GL_SCISSOR_TEST);
  glScissor(2, 3, 4, 5);
  glColorMask(GL_TRUE, GL_FALSE, GL_TRUE, GL_FALSE);
  glClearColor(0.0f, 0.0f, 1.0f, 1.0f);

  gl::releaseFinishedRenderMemory();

  EXPECT_EQ(gl::drainGlErrors(), 0);
  GLint v = 0;
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &v);
  EXPECT_EQ(v, draw);
  glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &v);
  EXPECT_EQ(v, read);
  glGetIntegerv(GL_RENDERBUFFER_BINDING, &v);
  EXPECT_EQ(v, static_cast<GLint>(rbo));
  glGetIntegerv(GL_SCISSOR_TEST, &v);
  EXPECT_EQ(v, GL_TRUE);
  GLint box[4] = {0, 0, 0, 0};
  glGetIntegerv(GL_SCISSOR_BOX, box);
  EXPECT_EQ(box[0], 2);
  EXPECT_EQ(box[1], 3);
  EXPECT_EQ(box[2], 4);
  EXPECT_EQ(box[3], 5);
  GLint mask[4] = {-1, -1, -1, -1};
  glGetIntegerv(GL_COLOR_WRITEMASK, mask);
  EXPECT_EQ(mask[0], GL_TRUE);
  EXPECT_EQ(mask[1], GL_FALSE);
  EXPECT_EQ(mask[2], GL_TRUE);
  EXPECT_EQ(mask[3], GL_FALSE);

  // The caller's target still holds its own clear (red), not the blue clear
  // colour left set above: the private 1×1 target took the clear.
  glDisable(GL_SCISSOR_TEST);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glBindRenderbuffer(GL_RENDERBUFFER, 0);
  glDeleteRenderbuffers(1, &rbo);
  Image<Rgba8> px;
  fb->readColour(px);
  ASSERT_EQ(px.width(), 16);
  for (int y = 0; y < px.height(); ++y)
    for (int x = 0; x < px.width(); ++x) {
      const Rgba8 c = px(x, y);
      ASSERT_EQ(c.r, 255) << x << "," << y;
      ASSERT_EQ(c.b, 0) << x << "," << y;
    }
  EXPECT_EQ(gl::drainGlErrors(), 0);
}

TEST_F(RenderMemory, WorksWithNothingRenderedBefore) {
  ASSERT_EQ(gl::drainGlErrors(), 0);
  gl::releaseFinishedRenderMemory();
  gl::releaseFinishedRenderMemory();
  EXPECT_EQ(gl::drainGlErrors(), 0);
}

}  // namespace
}  // namespace hw
