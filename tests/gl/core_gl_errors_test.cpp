// OpenGL error accounting: drainGlErrors counts what glGetError
// reports, and the KHR_debug callback (debug builds, or HW_GL_DEBUG=1, as
// set here before the context exists) counts each error as it happens.
#include <gtest/gtest.h>

#include <cstdlib>

#include "core/gl/context.h"
#include "core/gl/gl_api.h"
#include "gl_fixture.h"

namespace hw {
namespace {

// Runs before main's first test creates the shared context.
const bool kDebugRequested = [] { return ::setenv("HW_GL_DEBUG", "1", 1) == 0; }();

class GlErrors : public test::GlTest {};

TEST_F(GlErrors, NoErrorsAfterContextCreation) {
  ASSERT_TRUE(kDebugRequested);
  EXPECT_EQ(gl::drainGlErrors(), 0);
  EXPECT_EQ(gl::debugCallbackErrors(), 0);
}

TEST_F(GlErrors, DeliberateErrorsAreCountedByBothMechanisms) {
  ASSERT_EQ(gl::drainGlErrors(), 0);
  const long long before = gl::debugCallbackErrors();
  ASSERT_GE(before, 0) << "no KHR_debug callback although HW_GL_DEBUG=1";
  glEnable(0x7fff);                      // GL_INVALID_ENUM
  glBindTexture(GL_TEXTURE_2D, 987654);  // core profile: name never generated → GL_INVALID_OPERATION
  EXPECT_EQ(gl::debugCallbackErrors() - before, 2);
  // The spec lets an implementation keep one flag per error kind; Mesa
  // keeps only the first error until it is read. Either way: not zero.
  const int drained = gl::drainGlErrors();
  EXPECT_GE(drained, 1);
  EXPECT_LE(drained, 2);
  EXPECT_EQ(gl::drainGlErrors(), 0);
}

}  // namespace
}  // namespace hw
