// runViewer's options checked before any window opens (checkViewerOptions,
// app/viewer.h): working defaults pass, and each bad value is an error that
// names it.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "app/viewer.h"

namespace hw::app {
namespace {

TEST(ViewerOptionsCheck, DefaultsPass) {
  EXPECT_TRUE(checkViewerOptions(ViewerOptions{}).ok());
  ViewerOptions o;
  o.keys = "s@10p@20p";
  EXPECT_TRUE(checkViewerOptions(o).ok());
}

TEST(ViewerOptionsCheck, BadValuesAreNamed) {
  struct Case {
    std::function<void(ViewerOptions&)> set;
    const char* says;
  };
  const std::vector<Case> cases = {
      {[](ViewerOptions& o) { o.width = 8; }, "window size"},
      {[](ViewerOptions& o) { o.height = 20000; }, "window size"},
      {[](ViewerOptions& o) { o.lod.tau = -1; }, "tau must be"},
      {[](ViewerOptions& o) { o.lod.tauParallaxPx = NAN; }, "tau-px"},
      {[](ViewerOptions& o) { o.lod.tauGradient = INFINITY; }, "tau gradient"},
      {[](ViewerOptions& o) { o.keyframeAngleDeg = 180; }, "keyframe thresholds"},
      {[](ViewerOptions& o) { o.keyframeDistance = -2; }, "keyframe thresholds"},
      {[](ViewerOptions& o) { o.exitAfterFrames = -1; }, "exit-after"},
      {[](ViewerOptions& o) { o.keys = "p@"; }, "frame number"},
  };
  for (const Case& c : cases) {
    ViewerOptions o;
    c.set(o);
    const Status s = checkViewerOptions(o);
    ASSERT_FALSE(s.ok()) << c.says;
    EXPECT_NE(s.error().message.find(c.says), std::string::npos) << s.error().message;
  }
}

}  // namespace
}  // namespace hw::app
