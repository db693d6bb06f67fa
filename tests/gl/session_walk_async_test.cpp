// Keyframes rendered ahead on a worker thread (keyframe/gl/async_keyframes.h):
// a walk with them gives the same frames as the synchronous walk, the cache
// keeps to its memory bound, and the worker is joined on shutdown and on
// errors without hanging.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>

#include "session/walk.h"
#include "gl_fixture.h"
#include "walk_fixture.h"
#include "keyframe/geometry_renderer.h"
#include "keyframe/gl/async_keyframes.h"
#include "keyframe/keyframe_cache.h"
#include "scenes/loader.h"

namespace hw {
namespace {

using test::Indoor;
using test::readBytes;

class AsyncKeyframesTest : public test::GlTest {};

TEST_F(AsyncKeyframesTest, AsyncWalkGivesTheSameFramesAsTheSynchronousWalk) {
  const Indoor in = test::smallIndoor("indoor", 128, 23, 5);
  const std::string dir = ::testing::TempDir() + "walk_async_test";
  std::filesystem::remove_all(dir);
  nlohmann::json reports[3];
  const char* names[3] = {"/sync", "/async", "/slices"};
  for (int async = 0; async < 3; ++async) {
    session::WalkOptions o;
    o.progress = false;
    o.strips = 0;
    o.saveFrames = true;
    o.outDir = dir + names[async];
    o.asyncKeyframes = async >= 1;
    o.keyframePrefetch = 2;
    if (async == 2) o.keyframePacing = session::WalkOptions::KeyframePacing::Slices;
    auto r = session::runWalk(in.scene, "indoor", in.path, o);
    ASSERT_TRUE(r.ok()) << r.error().message;
    reports[async] = r->report;
  }
  const auto& s0 = reports[0]["summary"];
  const auto& s1 = reports[1]["summary"];
  EXPECT_EQ(s0["keyframe_acquisition"], "sync");
  EXPECT_EQ(s1["keyframe_acquisition"], "async");
  EXPECT_EQ(s0["keyframes"], s1["keyframes"]);
  EXPECT_EQ(s0["keyframe_stalls"], 0);
  ASSERT_EQ(reports[0]["frames"].size(), 23u);
  ASSERT_EQ(reports[1]["frames"].size(), 23u);
  for (int i = 0; i < 23; ++i) {
    const auto& f0 = reports[0]["frames"][i];
    const auto& f1 = reports[1]["frames"][i];
    EXPECT_EQ(f0["quads"], f1["quads"]) << "frame " << i;
    EXPECT_EQ(f0["psnr"], f1["psnr"]) << "frame " << i;
    EXPECT_TRUE(f1["ms"]["frame"].is_number());
    char name[32];
    std::snprintf(name, sizeof name, "/frames/%04d.png", i);
    const std::string a = readBytes(dir + "/sync" + name), b = readBytes(dir + "/async" + name);
    ASSERT_FALSE(a.empty()) << name;
    EXPECT_TRUE(a == b) << "frame " << i << " differs between sync and async keyframes";
    EXPECT_TRUE(a == readBytes(dir + "/slices" + name)) << "frame " << i << " differs with slices";
    EXPECT_TRUE(reports[2]["frames"][i]["ms"]["keyframe_slice"].is_number()) << "frame " << i;
  }
  EXPECT_EQ(s1["frame_ms"]["count"], 23);
  const auto& s2 = reports[2]["summary"];
  EXPECT_EQ(s2["keyframe_pacing"], "slices");
  EXPECT_EQ(s2["keyframe_slice_ms"]["count"], 23);
  EXPECT_GT(s2["keyframe_slice_ms"]["max"].get<double>(), 0.0);  // keyframes were built in slices
  EXPECT_TRUE(s1["keyframe_slice_ms"].is_null());
}

// Builds every keyframe along the path through prefetch() and get() and
// checks the bound after each call.
void walkCache(keyframe::KeyframeCache& cache, const keyframe::KeyframeSchedule& schedule,
               std::size_t bound) {
  for (int i = 0; i < schedule.frames; ++i) {
    ASSERT_TRUE(cache.prefetch(i).ok());
    EXPECT_LE(cache.bytes(), bound) << "after prefetch(" << i << ")";
    const auto [k0, k1] = schedule.bracket(i);
    auto a = cache.get(k0);
    ASSERT_TRUE(a.ok()) << a.error().message;
    auto b = cache.get(k1);
    ASSERT_TRUE(b.ok()) << b.error().message;
    // The first pointer is still valid: the second get() kept it.
    EXPECT_EQ((*a)->frame, k0);
    EXPECT_EQ((*b)->frame, k1);
    EXPECT_TRUE(cache.contains(k0) && cache.contains(k1));
    EXPECT_LE(cache.bytes(), bound) << "after get at frame " << i;
  }
  EXPECT_LE(cache.peakBytes(), bound);
}

TEST_F(AsyncKeyframesTest, CacheKeepsToItsMemoryBoundWithAndWithoutTheWorker) {
  const Indoor in = test::smallIndoor("indoor", 96, 31, 3);
  auto r = keyframe::GeometryRenderer::create(in.scene);
  ASSERT_TRUE(r.ok()) << r.error().message;
  const keyframe::MeshSpec spec;
  auto cameraOf = [&](int i) { return in.path.cameraAt(i); };
  // One entry's size, to set a bound of about three entries.
  keyframe::KeyframeCache probe(**r, spec, cameraOf);
  ASSERT_TRUE(probe.get(0).ok());
  const std::size_t one = probe.bytes();
  ASSERT_GT(one, std::size_t{96 * 96 * 17});  // colour + z' + eye z + coverage at least
  const std::size_t bound = one * 7 / 2;
  const keyframe::KeyframeSchedule schedule{31, 3, {}};

  keyframe::KeyframeCache sync(**r, spec, cameraOf, keyframe::CacheOptions{bound, 2});
  sync.setSchedule(schedule);
  walkCache(sync, schedule, bound);
  EXPECT_GT(sync.evictions(), 0u);
  EXPECT_EQ(sync.builds(), schedule.keyframes().size());  // forward walk: each built once

  keyframe::AsyncKeyframeOptions ao;
  ao.mesh = spec;
  ao.maxQueued = 4;
  auto w = keyframe::AsyncKeyframes::create(in.scene, cameraOf, ao);
  ASSERT_TRUE(w.ok()) << w.error().message;
  keyframe::KeyframeCache async(**r, spec, cameraOf, keyframe::CacheOptions{bound, 2});
  async.setSchedule(schedule);
  async.setProducer(w->get());
  walkCache(async, schedule, bound);
  EXPECT_GT(async.evictions(), 0u);
  EXPECT_EQ((*w)->built(), static_cast<int>(schedule.keyframes().size()));
}

TEST_F(AsyncKeyframesTest, ABoundBelowTwoKeyframesStillHoldsTheBracket) {
  const Indoor in = test::smallIndoor("indoor", 64, 12, 4);
  auto r = keyframe::GeometryRenderer::create(in.scene);
  ASSERT_TRUE(r.ok()) << r.error().message;
  keyframe::KeyframeCache cache(
      **r, {}, [&](int i) { return in.path.cameraAt(i); }, keyframe::CacheOptions{1, 2});
  const keyframe::KeyframeSchedule schedule{12, 4, {}};
  cache.setSchedule(schedule);
  for (int i = 0; i < 12; ++i) {
    ASSERT_TRUE(cache.prefetch(i).ok());
    const auto [k0, k1] = schedule.bracket(i);
    auto a = cache.get(k0);
    auto b = cache.get(k1);
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_EQ((*a)->frame, k0);
    EXPECT_LE(cache.entries(), 2u);
  }
}

TEST_F(AsyncKeyframesTest, ReleasedKeyframesLeaveTheCacheAndAWalkKeepsOnlyWhatCanStillBeUsed) {
  const Indoor in = test::smallIndoor("indoor", 64, 30, 3);
  auto r = keyframe::GeometryRenderer::create(in.scene);
  ASSERT_TRUE(r.ok()) << r.error().message;
  // A bound far above the walk's keyframes: only releaseBefore drops them.
  keyframe::KeyframeCache cache(
      **r, {}, [&](int i) { return in.path.cameraAt(i); }, keyframe::CacheOptions{1u << 30, 1});
  const keyframe::KeyframeSchedule schedule{30, 3, {}};
  cache.setSchedule(schedule);
  for (int i = 0; i < 30; ++i) {
    ASSERT_TRUE(cache.prefetch(i).ok());
    const auto [k0, k1] = schedule.bracket(i);
    ASSERT_TRUE(cache.get(k0).ok() && cache.get(k1).ok());
    cache.releaseBefore(k0);
    EXPECT_FALSE(k0 >= 3 && cache.contains(k0 - 3)) << "frame " << i;
    EXPECT_TRUE(cache.contains(k0) && cache.contains(k1));
    // The bracket and the one prefetched keyframe at most.
    EXPECT_LE(cache.entries(), 3u) << "frame " << i;
  }
  EXPECT_EQ(cache.evictions(), 0u);
  EXPECT_GE(cache.released(), 8u);  // keyframes 0, 3, ..., 24 passed
  // A walk (default 256 MiB bound) releases them as it passes.
  session::WalkOptions o;
  o.progress = false;
  o.strips = 0;
  o.reference = false;
  auto w = session::runWalk(in.scene, "indoor", in.path, o);
  ASSERT_TRUE(w.ok()) << w.error().message;
  const auto& s = w->report["summary"];
  EXPECT_GE(s["keyframe_cache_released"].get<int>(), 8);  // the walk releases passed keyframes
  EXPECT_EQ(s["keyframe_cache_evictions"].get<int>(), 0);
}

TEST_F(AsyncKeyframesTest, KeyframesFromTheWorkerEqualTheSynchronousOnes) {
  const Indoor in = test::smallIndoor("indoor", 96, 20, 5);
  auto r = keyframe::GeometryRenderer::create(in.scene);
  ASSERT_TRUE(r.ok()) << r.error().message;
  auto cameraOf = [&](int i) { return in.path.cameraAt(i); };
  keyframe::AsyncKeyframeOptions ao;
  auto w = keyframe::AsyncKeyframes::create(in.scene, cameraOf, ao);
  ASSERT_TRUE(w.ok()) << w.error().message;
  keyframe::LodBuilder builder;
  for (int f : {0, 5, 10}) {
    ASSERT_TRUE((*w)->request(f));
    keyframe::CachedKeyframe mine;
    ASSERT_TRUE(keyframe::buildCachedKeyframe(**r, builder, {}, cameraOf(f), f, mine).ok());
    std::unique_ptr<keyframe::CachedKeyframe> theirs;
    double waited = -1;
    ASSERT_TRUE((*w)->take(f, &theirs, &waited).ok());
    EXPECT_GE(waited, 0.0);
    ASSERT_EQ(theirs->frame, f);
    const auto& a = mine.keyframe;
    const auto& b = theirs->keyframe;
    ASSERT_EQ(a.colour.width(), b.colour.width());
    int colourDiff = 0, depthDiff = 0;
    for (int y = 0; y < a.colour.height(); ++y)
      for (int x = 0; x < a.colour.width(); ++x) {
        const Rgba8 p = a.colour(x, y), q = b.colour(x, y);
        colourDiff += p.r != q.r || p.g != q.g || p.b != q.b || p.a != q.a;
        depthDiff += a.zPrime(x, y) != b.zPrime(x, y);
      }
    EXPECT_EQ(colourDiff, 0) << "keyframe " << f;
    EXPECT_EQ(depthDiff, 0) << "keyframe " << f;
    ASSERT_EQ(mine.mesh.quads.size(), theirs->mesh.quads.size());
    for (std::size_t q = 0; q < mine.mesh.quads.size(); ++q)
      ASSERT_TRUE(mine.mesh.quads[q].world == theirs->mesh.quads[q].world) << "quad " << q;
  }
  EXPECT_EQ((*w)->built(), 3);
}

TEST_F(AsyncKeyframesTest, QueueIsBoundedAndAnUnrequestedTakeWaits) {
  const Indoor in = test::smallIndoor("indoor", 64, 40, 5);
  keyframe::AsyncKeyframeOptions ao;
  ao.maxQueued = 2;
  auto w = keyframe::AsyncKeyframes::create(
      in.scene, [&](int i) { return in.path.cameraAt(i); }, ao);
  ASSERT_TRUE(w.ok()) << w.error().message;
  EXPECT_TRUE((*w)->request(0));
  EXPECT_TRUE((*w)->request(5));
  EXPECT_TRUE((*w)->request(5));    // already queued
  EXPECT_FALSE((*w)->request(10));  // full
  std::unique_ptr<keyframe::CachedKeyframe> e;
  double waited = 0;
  ASSERT_TRUE((*w)->take(35, &e, &waited).ok());  // never requested: queued first
  EXPECT_EQ(e->frame, 35);
  EXPECT_GT(waited, 0.0);
}

TEST_F(AsyncKeyframesTest, APacedWorkerStillDeliversWhenAFrameWaitsForIt) {
  const Indoor in = test::smallIndoor("indoor", 64, 20, 5);
  for (int mode = 0; mode < 3; ++mode) {
    SCOPED_TRACE(mode == 0 ? "steps pacing" : mode == 1 ? "time pacing" : "slices");
    keyframe::AsyncKeyframeOptions ao;
    if (mode == 0) {
      ao.stepsPerFrame = 1;
    } else {
      ao.framesPerKeyframe = 1000;  // a tiny budget per frame
      ao.budgetScale = 1;
      ao.slices = mode == 2;
    }
    ao.flushEveryTriangles = 1000;  // many steps per keyframe
    auto w = keyframe::AsyncKeyframes::create(
        in.scene, [&](int i) { return in.path.cameraAt(i); }, ao);
    ASSERT_TRUE(w.ok()) << w.error().message;
    // Waiting lifts the pacing (no deadlock), for the keyframe waited for.
    std::unique_ptr<keyframe::CachedKeyframe> e;
    double waited = 0;
    ASSERT_TRUE((*w)->take(0, &e, &waited).ok());
    EXPECT_GT(waited, 0.0);
    ASSERT_TRUE((*w)->request(5));
    // One frame's budget is not a whole keyframe.
    (*w)->frameTick();
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    EXPECT_FALSE((*w)->ready(5));
    if (mode == 2) {
      // Slices: the worker runs only inside runSlice(), which returns once
      // the slice is used; with nothing queued it returns at once.
      int slices = 0;
      for (; slices < 20000 && !(*w)->ready(5); ++slices) (*w)->runSlice();
      EXPECT_TRUE((*w)->ready(5));
      EXPECT_GT(slices, 1);  // one slice is not a whole keyframe
      ASSERT_TRUE((*w)->take(5, &e, &waited).ok());
      EXPECT_EQ((*w)->runSlice(), 0.0);  // idle: nothing to run
      continue;
    }
    for (int t = 0; t < 20000 && !(*w)->ready(5); ++t) {
      (*w)->frameTick();
      std::this_thread::sleep_for(std::chrono::microseconds(500));
    }
    EXPECT_TRUE((*w)->ready(5));  // ticks alone get it done
  }
}

// The viewer re-paces its worker from the keyframe interval it measures
// (app/keyframe_pacing.h): a new frames-per-keyframe applies at once, also
// to a worker already waiting for its next frame's budget.
TEST_F(AsyncKeyframesTest, SetFramesPerKeyframeAppliesToAWaitingWorker) {
  const Indoor in = test::smallIndoor("indoor", 64, 20, 5);
  keyframe::AsyncKeyframeOptions ao;
  ao.framesPerKeyframe = 1000;  // a tiny budget per frame
  ao.budgetScale = 1;
  ao.flushEveryTriangles = 1000;  // many steps per keyframe
  auto w = keyframe::AsyncKeyframes::create(
      in.scene, [&](int i) { return in.path.cameraAt(i); }, ao);
  ASSERT_TRUE(w.ok()) << w.error().message;
  EXPECT_EQ((*w)->framesPerKeyframe(), 1000.0);
  std::unique_ptr<keyframe::CachedKeyframe> e;
  double waited = 0;
  ASSERT_TRUE((*w)->take(0, &e, &waited).ok());  // a build time for the budget
  ASSERT_TRUE((*w)->request(5));
  (*w)->frameTick();
  // No more ticks: at 1000 frames per keyframe the worker used this frame's
  // budget and waits for the next; at 0.001 one frame's budget is a
  // thousand keyframes, so it finishes.
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  ASSERT_FALSE((*w)->ready(5));
  (*w)->setFramesPerKeyframe(0.001);
  EXPECT_EQ((*w)->framesPerKeyframe(), 0.001);
  for (int t = 0; t < 2000 && !(*w)->ready(5); ++t)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  EXPECT_TRUE((*w)->ready(5));
  // Nonsense values are ignored.
  (*w)->setFramesPerKeyframe(0);
  (*w)->setFramesPerKeyframe(-3);
  (*w)->setFramesPerKeyframe(std::nan(""));
  EXPECT_EQ((*w)->framesPerKeyframe(), 0.001);
  // Without time pacing there is nothing to set.
  keyframe::AsyncKeyframeOptions steps;
  steps.stepsPerFrame = 2;
  auto s = keyframe::AsyncKeyframes::create(
      in.scene, [&](int i) { return in.path.cameraAt(i); }, steps);
  ASSERT_TRUE(s.ok()) << s.error().message;
  (*s)->setFramesPerKeyframe(3);
  EXPECT_EQ((*s)->framesPerKeyframe(), 0.0);
}

// hold() stops the worker at a step boundary until release(), in every
// pacing mode, so a render timed meanwhile has the CPUs to itself; a take()
// that has to wait lifts the hold instead of deadlocking.
TEST_F(AsyncKeyframesTest, AHeldWorkerBuildsNothingUntilReleased) {
  const Indoor in = test::smallIndoor("indoor", 64, 20, 5);
  for (int mode = 0; mode < 3; ++mode) {
    SCOPED_TRACE(mode == 0 ? "unpaced" : mode == 1 ? "time pacing" : "steps pacing");
    keyframe::AsyncKeyframeOptions ao;
    if (mode == 1) ao.framesPerKeyframe = 0.001;  // a budget of a thousand keyframes per frame
    if (mode == 2) ao.stepsPerFrame = 1000000;
    ao.flushEveryTriangles = 1000;
    auto w = keyframe::AsyncKeyframes::create(
        in.scene, [&](int i) { return in.path.cameraAt(i); }, ao);
    ASSERT_TRUE(w.ok()) << w.error().message;
    std::unique_ptr<keyframe::CachedKeyframe> e;
    double waited = 0;
    ASSERT_TRUE((*w)->take(0, &e, &waited).ok());  // a build time for the time budget
    (*w)->frameTick();
    EXPECT_GE((*w)->hold(), 0.0);  // idle: at once
    ASSERT_TRUE((*w)->request(5));
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    EXPECT_FALSE((*w)->ready(5)) << "the worker built while held";
    (*w)->release();
    for (int t = 0; t < 2000 && !(*w)->ready(5); ++t)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    EXPECT_TRUE((*w)->ready(5));
    // Held with a keyframe in progress: hold() returns at its next step.
    ASSERT_TRUE((*w)->request(10));
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    (*w)->hold();
    const bool doneAtHold = (*w)->ready(10);
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    if (!doneAtHold) {
      EXPECT_FALSE((*w)->ready(10)) << "the worker went on while held";
    }
    // Waiting for it lifts the hold.
    ASSERT_TRUE((*w)->take(10, &e, &waited).ok());
    (*w)->release();
  }
}

TEST_F(AsyncKeyframesTest, DestroyingMidQueueJoinsTheWorker) {
  const Indoor in = test::smallIndoor("indoor", 128, 100, 5);
  keyframe::AsyncKeyframeOptions ao;
  ao.maxQueued = 8;
  for (int round = 0; round < 3; ++round) {
    auto w = keyframe::AsyncKeyframes::create(
        in.scene, [&](int i) { return in.path.cameraAt(i); }, ao);
    ASSERT_TRUE(w.ok()) << w.error().message;
    for (int f = 0; f < 40; f += 5) EXPECT_TRUE((*w)->request(f));
    // Falls out of scope with keyframes queued and one being built: the
    // destructor must return (a hang fails by CTest timeout).
  }
}

TEST_F(AsyncKeyframesTest, ABuildErrorComesBackForItsFrameAndTheWorkerStillJoins) {
  const Indoor in = test::smallIndoor("indoor", 64, 20, 5);
  auto cameraOf = [&](int i) {
    Camera c = in.path.cameraAt(i);
    if (i == 10) c.width = 0;  // the renderer refuses a 0-pixel image
    return c;
  };
  auto w = keyframe::AsyncKeyframes::create(in.scene, cameraOf, {});
  ASSERT_TRUE(w.ok()) << w.error().message;
  ASSERT_TRUE((*w)->request(5));
  ASSERT_TRUE((*w)->request(10));
  std::unique_ptr<keyframe::CachedKeyframe> e;
  double waited = 0;
  const Status s = (*w)->take(10, &e, &waited);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("0x"), std::string::npos) << s.error().message;
  EXPECT_TRUE((*w)->take(5, &e, &waited).ok());  // the others are unaffected
}

TEST_F(AsyncKeyframesTest, AFailedBuildIsFinishedButNotReadySoAPollingCallerSeesTheError) {
  // The viewer polls finished() and takes only then; ready() alone would
  // leave a failed build pending forever.
  const Indoor in = test::smallIndoor("indoor", 64, 20, 5);
  auto cameraOf = [&](int i) {
    Camera c = in.path.cameraAt(i);
    if (i == 10) c.width = 0;
    return c;
  };
  auto w = keyframe::AsyncKeyframes::create(in.scene, cameraOf, {});
  ASSERT_TRUE(w.ok()) << w.error().message;
  ASSERT_TRUE((*w)->request(5));
  ASSERT_TRUE((*w)->request(10));
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (!((*w)->finished(5) && (*w)->finished(10)) && std::chrono::steady_clock::now() < until)
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  ASSERT_TRUE((*w)->finished(10));
  EXPECT_FALSE((*w)->ready(10));
  EXPECT_TRUE((*w)->ready(5));
  EXPECT_FALSE((*w)->finished(15));  // never requested
  std::unique_ptr<keyframe::CachedKeyframe> e;
  double waited = -1;
  EXPECT_FALSE((*w)->take(10, &e, &waited).ok());
  EXPECT_EQ(waited, 0.0);  // finished: take() did not wait
}

TEST_F(AsyncKeyframesTest, AWorkerContextFailureIsAnErrorFromCreate) {
  const Indoor in = test::smallIndoor("indoor", 64, 20, 5);
  ::setenv("HW_GL_FAIL", "1", 1);
  auto w =
      keyframe::AsyncKeyframes::create(in.scene, [&](int i) { return in.path.cameraAt(i); }, {});
  ::unsetenv("HW_GL_FAIL");
  ASSERT_FALSE(w.ok());
  EXPECT_NE(w.error().message.find("keyframe worker"), std::string::npos) << w.error().message;
  // The main context still works afterwards.
  auto r = keyframe::GeometryRenderer::create(in.scene);
  ASSERT_TRUE(r.ok()) << r.error().message;
  keyframe::Keyframe k;
  EXPECT_TRUE((*r)->renderKeyframe(in.path.cameraAt(0), k).ok());
}

}  // namespace
}  // namespace hw
