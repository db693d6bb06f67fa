#pragma once
// Shared by the walk tests (tests/gl/bench_walk_*_test.cpp): a built-in scene
// with its default path cut short, and a file's bytes.
#include <gtest/gtest.h>

#include <string>

#include "core/file_io.h"
#include "scenes/camera_path.h"
#include "scenes/loader.h"
#include "scenes/scene.h"

namespace hw::test {

struct Indoor {
  scenes::Scene scene;
  scenes::CameraPath path;
};

// `scene` ("indoor", "indoor:20k") with the indoor default path at size²,
// `frames` frames, a keyframe every `keyframeEvery`.
inline Indoor smallIndoor(const std::string& scene, int size, int frames, int keyframeEvery) {
  auto s = scenes::loadScene(scene);
  EXPECT_TRUE(s.ok()) << s.error().message;
  auto p = scenes::defaultPathFor("indoor");
  EXPECT_TRUE(p.ok()) << p.error().message;
  Indoor in{std::move(*s), std::move(*p)};
  in.path.width = in.path.height = size;
  in.path.frames = frames;
  in.path.keyframeEvery = keyframeEvery;
  return in;
}

// The file's bytes, or "" when it cannot be read.
inline std::string readBytes(const std::string& file) {
  auto r = readFile(file);
  return r ? *r : std::string();
}

}  // namespace hw::test
