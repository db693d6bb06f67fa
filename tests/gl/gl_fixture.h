#pragma once
// One OSMesa context per test program. A context that cannot be created is a
// test FAILURE, never a skip (CI must not pass without GL).
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
    ASSERT_NE(glContext(), nullptr) << "OSMesa context could not be created";
    glContext()->makeCurrent();
  }
};

}  // namespace hw::test
