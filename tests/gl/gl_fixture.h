#pragma once
// One headless context per test program, from the default backend (--gl
// auto: EGL where it gives 4.5 core, else OSMesa; HYBRIDWALK_GL picks one). A
// context that cannot be created is a test FAILURE, never a skip (CI must not
// pass without GL).
#include <gtest/gtest.h>

#include <memory>

#include "core/gl/context.h"

namespace hw::test {

inline gl::Context* glContext() {
  static std::unique_ptr<gl::Context> ctx = [] {
    auto c = gl::createHeadlessContext();
    if (!c) {
      ADD_FAILURE() << c.error().message;
      return std::unique_ptr<gl::Context>();
    }
    return std::move(*c);
  }();
  return ctx.get();
}

class GlTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_NE(glContext(), nullptr) << "headless OpenGL context could not be created";
    glContext()->makeCurrent();
  }
};

}  // namespace hw::test
