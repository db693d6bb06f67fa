// Headless backends (core/gl/context.h) on this machine's real EGL: a 4.5
// core context from Mesa's surfaceless platform and from each EGL device, a
// second context on a worker thread drawing through the same entry-point
// table, the errors for a device out of range and for HW_GL_FAIL=1, and what
// `auto` takes. Only EGL contexts draw here (OSMesa is only probed; its
// frames are compared with EGL's by tests/cli/gl_backends.sh, one process
// per backend).
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <thread>

#include "core/gl/context.h"
#include "core/gl/framebuffer.h"
#include "core/gl/gl_api.h"

namespace hw {
namespace {

using gl::Backend;

gl::HeadlessOptions eglOptions(int device = -1) {
  gl::HeadlessOptions o;
  o.backend = Backend::Egl;
  o.eglDevice = device;
  return o;
}

// Clears a 4x4 FBO to (r, g, b) and reads the first pixel back.
Rgba8 clearAndRead(float r, float g, float b) {
  auto fb = gl::Framebuffer::create(4, 4, DepthMode::Fixed24);
  if (!fb) {
    ADD_FAILURE() << fb.error().message;
    return {};
  }
  fb->bindAndClear(r, g, b, 1.0f);
  Image<Rgba8> img(4, 4);
  fb->readColour(img);
  return img(0, 0);
}

TEST(Headless, EglGivesCoreProfile45OnItsDefaultDisplay) {
  ASSERT_TRUE(gl::backendBuilt(Backend::Egl));
  auto ctx = gl::createHeadlessContext(eglOptions());
  ASSERT_TRUE(ctx) << ctx.error().message;
  EXPECT_EQ((*ctx)->backend(), "egl");
  EXPECT_FALSE((*ctx)->vendor().empty());
  EXPECT_NE((*ctx)->version().find("4.5"), std::string::npos) << (*ctx)->version();
  EXPECT_NE((*ctx)->version().find("Core Profile"), std::string::npos) << (*ctx)->version();
  GLint major = 0, minor = 0, mask = 0;
  glGetIntegerv(GL_MAJOR_VERSION, &major);
  glGetIntegerv(GL_MINOR_VERSION, &minor);
  glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &mask);
  EXPECT_EQ(major * 10 + minor, 45);
  EXPECT_TRUE(mask & GL_CONTEXT_CORE_PROFILE_BIT);
  const gl::ContextStrings s = gl::lastHeadlessContextStrings();
  EXPECT_EQ(s.backend, "egl");
  EXPECT_EQ(s.renderer, (*ctx)->renderer());
  const Rgba8 p = clearAndRead(1.0f, 0.0f, 0.5f);
  EXPECT_EQ(p.r, 255);
  EXPECT_EQ(p.g, 0);
  EXPECT_EQ(p.b, 128);
}

TEST(Headless, EveryEglDeviceIsListedAndDevice0Renders) {
  const auto probes = gl::probeHeadlessBackends();
  int devices = 0;
  for (const gl::BackendProbe& p : probes) {
    if (p.backend == Backend::Egl && p.eglDevice >= 0) ++devices;
    if (p.backend == Backend::Egl && p.eglDevice < 0) {
      EXPECT_TRUE(p.core45) << p.name << ": " << p.error;
    }
    if (p.backend == Backend::OsMesa) {
      EXPECT_TRUE(gl::backendBuilt(Backend::OsMesa));
      EXPECT_TRUE(p.core45) << p.error;
    }
  }
  ASSERT_GE(devices, 1) << "eglQueryDevicesEXT listed no device";
  auto ctx = gl::createHeadlessContext(eglOptions(0));
  ASSERT_TRUE(ctx) << ctx.error().message;
  EXPECT_EQ((*ctx)->backend(), "egl");
  const Rgba8 p = clearAndRead(0.0f, 1.0f, 0.0f);
  EXPECT_EQ(p.g, 255);
  EXPECT_EQ(p.r, 0);
}

TEST(Headless, DeviceOutOfRangeNamesHowManyThereAre) {
  auto ctx = gl::createHeadlessContext(eglOptions(99));
  ASSERT_FALSE(ctx);
  EXPECT_NE(ctx.error().message.find("EGL device 99 does not exist"), std::string::npos)
      << ctx.error().message;
  EXPECT_NE(ctx.error().message.find("hybridwalk info"), std::string::npos);
}

TEST(Headless, SecondContextDrawsOnAWorkerThreadThroughTheSameTable) {
  auto first = gl::createHeadlessContext(eglOptions());
  ASSERT_TRUE(first) << first.error().message;
  std::string error;
  Rgba8 workerPixel{};
  std::thread worker([&] {
    auto second = gl::createSecondHeadlessContext();
    if (!second) {
      error = second.error().message;
      return;
    }
    EXPECT_EQ((*second)->backend(), "egl");
    workerPixel = clearAndRead(0.0f, 0.0f, 1.0f);
  });
  // The first context keeps drawing on this thread meanwhile.
  const Rgba8 mainPixel = clearAndRead(1.0f, 1.0f, 0.0f);
  worker.join();
  ASSERT_TRUE(error.empty()) << error;
  EXPECT_EQ(workerPixel.b, 255);
  EXPECT_EQ(workerPixel.r, 0);
  EXPECT_EQ(mainPixel.r, 255);
  EXPECT_EQ(mainPixel.b, 0);
}

TEST(Headless, AutoTakesEglHere) {
  gl::HeadlessOptions o;  // auto
  auto ctx = gl::createHeadlessContext(o);
  ASSERT_TRUE(ctx) << ctx.error().message;
  EXPECT_EQ((*ctx)->backend(), "egl");
}

TEST(Headless, ForcedFailureFailsEveryBackend) {
  ASSERT_EQ(::setenv("HW_GL_FAIL", "1", 1), 0);
  auto egl = gl::createHeadlessContext(eglOptions());
  gl::HeadlessOptions automatic;
  auto any = gl::createHeadlessContext(automatic);
  ::unsetenv("HW_GL_FAIL");
  ASSERT_FALSE(egl);
  EXPECT_NE(egl.error().message.find("EGL"), std::string::npos) << egl.error().message;
  EXPECT_NE(egl.error().message.find("HW_GL_FAIL=1"), std::string::npos);
  ASSERT_FALSE(any);
  if (gl::backendBuilt(Backend::OsMesa)) {
    EXPECT_NE(any.error().message.find("OSMesa"), std::string::npos) << any.error().message;
  }
}

TEST(Headless, BackendNamesRoundTrip) {
  for (Backend b : {Backend::Auto, Backend::Egl, Backend::OsMesa}) {
    Backend back = Backend::Auto;
    ASSERT_TRUE(gl::parseBackend(gl::backendName(b), &back));
    EXPECT_EQ(back, b);
  }
  Backend unused = Backend::Auto;
  EXPECT_FALSE(gl::parseBackend("vulkan", &unused));
  EXPECT_FALSE(gl::parseBackend("EGL", &unused));
}

}  // namespace
}  // namespace hw
