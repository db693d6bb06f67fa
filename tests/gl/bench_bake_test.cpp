// Baked keyframes (bench/bake.h) give the walk the same frames as keyframes
// rendered on the fly, and a sweep split into cells and merged equals the
// one-process sweep except for timings (bench/sweep.h, docs/slurm.md).
#include <gtest/gtest.h>

#include <filesystem>

#include "session/bake.h"
#include "bench/sweep.h"
#include "session/walk.h"
#include "core/file_io.h"
#include "gl_fixture.h"
#include "keyframe/keyframe_db.h"
#include "scenes/procedural.h"

namespace hw {
namespace {

using nlohmann::json;

class BakeTest : public test::GlTest {};

scenes::CameraPath smallPath() {
  scenes::CameraPath path = scenes::defaultIndoorPath();
  path.width = path.height = 96;
  path.frames = 13;
  path.keyframeEvery = 4;
  return path;
}

TEST_F(BakeTest, WalkFromDatabaseGivesBitIdenticalFrames) {
  const scenes::Scene scene = scenes::makeIndoorScene(20000);
  const scenes::CameraPath path = smallPath();
  const std::string dir = ::testing::TempDir() + "hw_bake_test";
  std::filesystem::remove_all(dir);
  session::BakeOptions bo;
  bo.outDir = dir + "/db";
  bo.progress = false;
  const int frames = session::bakeFrames(path, 0);
  const auto keys = session::bakeKeyframeList(path, frames);
  ASSERT_EQ(keys, (std::vector<int>{0, 4, 8, 12}));
  // Baked in two parts, as two chunks would.
  auto a = session::bakeKeyframes(scene, path, {0, 4}, bo);
  auto b = session::bakeKeyframes(scene, path, {8, 12}, bo);
  ASSERT_TRUE(a.ok() && b.ok());
  std::vector<keyframe::KeyframeDbEntry> entries = *b;
  entries.insert(entries.end(), a->begin(), a->end());
  const auto prov =
      session::bakeProvenance("indoor", scene.triangleCount(), path, frames, bo.lod, bo.depthMode);
  ASSERT_TRUE(session::writeBakeIndex(bo.outDir, prov, entries).ok());

  auto db = keyframe::KeyframeDb::open(bo.outDir);
  ASSERT_TRUE(db.ok()) << db.error().message;
  ASSERT_TRUE(db->checkMatches(prov).ok());
  EXPECT_EQ(db->keyframeFrames(), keys);

  session::WalkOptions live;
  live.progress = false;
  live.strips = 0;
  live.saveFrames = true;
  live.outDir = dir + "/live";
  session::WalkOptions baked = live;
  baked.outDir = dir + "/baked";
  baked.keyframeFrames = db->keyframeFrames();
  baked.keyframeSource =
      keyframe::makeKeyframeDbSource(std::make_shared<keyframe::KeyframeDb>(std::move(*db)));
  auto r1 = session::runWalk(scene, "indoor", path, live);
  auto r2 = session::runWalk(scene, "indoor", path, baked);
  ASSERT_TRUE(r1.ok() && r2.ok());
  for (int i = 0; i < frames; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "/frames/%04d.png", i);
    auto p1 = readFile(live.outDir + name);
    auto p2 = readFile(baked.outDir + name);
    ASSERT_TRUE(p1.ok() && p2.ok());
    EXPECT_TRUE(*p1 == *p2) << "frame " << i << " differs";
  }
  EXPECT_EQ(r1->report["summary"]["quads_per_keyframe"],
            r2->report["summary"]["quads_per_keyframe"]);
  EXPECT_EQ(r1->report["summary"]["psnr"], r2->report["summary"]["psnr"]);
}

json withoutTimings(json j) {
  if (j.is_object()) {
    json out = json::object();
    for (auto& [k, v] : j.items())
      if (k != "lod_build_ms" && k != "in_between_ms" && k != "reference_ms" && k != "machine")
        out[k] = withoutTimings(v);
    return out;
  }
  if (j.is_array())
    for (auto& v : j) v = withoutTimings(v);
  return j;
}

TEST_F(BakeTest, SweepCellsMergedEqualTheOneProcessSweep) {
  const scenes::Scene scene = scenes::makeIndoorScene(20000);
  const scenes::CameraPath path = smallPath();
  bench::SweepOptions o;
  o.taus = {256.0, 4096.0};
  o.variants = false;
  o.progress = false;
  o.outDir = ::testing::TempDir() + "hw_bake_sweep_whole";
  auto whole = bench::runSweep(scene, "indoor", path, o);
  ASSERT_TRUE(whole.ok()) << whole.error().message;
  auto n = bench::sweepCellCount(path, o);
  ASSERT_TRUE(n.ok());
  EXPECT_EQ(*n, 2 * 2 + 2 + 1);  // τ × criteria, a tiles cell per τ, per-pixel
  // One cell per "chunk": tiles cells find their tile size without the five-point rows.
  json rows = json::array();
  for (int c = 0; c < *n; ++c) {
    auto r = bench::runSweepCells(scene, "indoor", path, o, c, c + 1);
    ASSERT_TRUE(r.ok()) << r.error().message;
    ASSERT_EQ(r->size(), 1u);
    rows.push_back((*r)[0]);
  }
  bench::SweepOptions o2 = o;
  o2.outDir = ::testing::TempDir() + "hw_bake_sweep_cells";
  auto merged = bench::finishSweep(scene, "indoor", path, o2, rows);
  ASSERT_TRUE(merged.ok()) << merged.error().message;
  EXPECT_EQ(withoutTimings(*whole), withoutTimings(*merged));
  // The tile rows' sizes are matched to the five-point τ rows.
  int tiles = 0;
  for (const auto& r : (*merged)["rows"]) tiles += r["mesh"] == "uniform-tiles";
  EXPECT_GE(tiles, 1);
  // A wrong number of cell results is refused.
  rows.erase(rows.size() - 1);
  EXPECT_FALSE(bench::finishSweep(scene, "indoor", path, o2, rows).ok());
}

}  // namespace
}  // namespace hw
