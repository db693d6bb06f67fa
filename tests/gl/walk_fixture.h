#pragma once
// Shared by the walk tests (tests/gl/bench_walk_*_test.cpp): a built-in scene
// with its default path cut short, and a file's bytes.
#include <gtest/gtest.h>

#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "core/file_io.h"
#include "keyframe/geometry_renderer.h"
#include "keyframe/lod_builder.h"
#include "scenes/camera_path.h"
#include "scenes/loader.h"
#include "scenes/scene.h"
#include "warp/cpu_warper.h"
#include "warp/warper.h"

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

// A keyframe rendered at `cam` and its quad mesh.
struct Built {
  keyframe::Keyframe kf;
  keyframe::QuadMesh mesh;
};
inline Built buildKeyframe(keyframe::GeometryRenderer& renderer, const Camera& cam,
                           const keyframe::LodOptions& lod) {
  Built b;
  EXPECT_TRUE(renderer.renderKeyframe(cam, b.kf).ok());
  keyframe::LodBuilder builder;
  EXPECT_TRUE(builder.build(b.kf, lod, &b.mesh).ok());
  return b;
}

// The file's bytes, or "" when it cannot be read.
inline std::string readBytes(const std::string& file) {
  auto r = readFile(file);
  return r ? *r : std::string();
}

// The warper a walk drew its layers with (its report's summary.warper:
// "cpu" or "gl"), for tests that redo a walk's frame by hand.
inline Result<std::unique_ptr<warp::Warper>> warperOfWalk(const nlohmann::json& report,
                                                          const warp::WarpOptions& options) {
  EXPECT_TRUE(report["summary"].contains("warper"));
  if (report["summary"].value("warper", "") == "cpu") return warp::createCpuWarper(options, 1);
  return warp::Warper::create(options);
}

}  // namespace hw::test
