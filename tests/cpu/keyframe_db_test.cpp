// Keyframe database (keyframe/keyframe_db.h): round trip, checksum, every
// truncation length, flipped bytes, version/magic mismatch, index checks.
#include "keyframe/keyframe_db.h"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <random>
#include <thread>

#include "core/file_io.h"

namespace hw::keyframe {
namespace {

CachedKeyframe sample(int w, int h, int quads, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  CachedKeyframe c;
  c.frame = 7;
  Keyframe& k = c.keyframe;
  k.camera = Camera::lookAt({1, 2, 3}, {0, 0, 0}, {0, 1, 0}, 0.9, w, h, 0.05, 200.0);
  k.depthMode = DepthMode::Float32Reversed;
  k.colour.resize(w, h);
  k.zPrime.resize(w, h);
  k.eyeZ.resize(w, h);
  k.covered.resize(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      k.colour(x, y) = Rgba8{std::uint8_t(rng()), std::uint8_t(rng()), std::uint8_t(rng()), 255};
      k.zPrime(x, y) = u(rng) * kZPrimeScale;
      k.eyeZ(x, y) = static_cast<float>(u(rng) * 100);
      k.covered(x, y) = rng() & 1;
    }
  c.mesh.width = w;
  c.mesh.height = h;
  for (int i = 0; i < quads; ++i) {
    Quad q;
    q.rect = {i % w, 0, i % w + 1, 1};
    for (int j = 0; j < 4; ++j) {
      q.world[j] = {u(rng), u(rng), u(rng)};
      q.pixel[j] = {u(rng) * w, u(rng) * h};
      q.eyeZ[j] = 1 + u(rng);
    }
    q.maxDelta = static_cast<float>(u(rng));
    c.mesh.quads.push_back(q);
  }
  c.mesh.stats.quads = quads;
  c.mesh.stats.onePixelLeaves = 3;
  c.mesh.stats.emptyPixels = 11;
  c.mesh.stats.clampedCorners = 2;
  c.mesh.stats.criterion = DeltaCriterion::PerAxisMax;
  c.mesh.stats.tauZPrime = 2048;
  c.mesh.stats.tauParallaxPx = 0.5;
  c.render.meshesDrawn = 5;
  c.render.trianglesDrawn = 12345;
  return c;
}

std::string encode(const CachedKeyframe& c) {
  return encodeKeyframe(c.frame, c.keyframe, c.mesh, c.render);
}

TEST(KeyframeDb, RoundTripIsExact) {
  const CachedKeyframe a = sample(13, 9, 20, 1);
  const std::string bytes = encode(a);
  CachedKeyframe b;
  ASSERT_TRUE(decodeKeyframe(bytes, "a.hwkf", b).ok());
  EXPECT_EQ(b.frame, 7);
  EXPECT_EQ(b.keyframe.colour.pixels(), a.keyframe.colour.pixels());
  EXPECT_EQ(b.keyframe.zPrime.pixels(), a.keyframe.zPrime.pixels());
  EXPECT_EQ(b.keyframe.eyeZ.pixels(), a.keyframe.eyeZ.pixels());
  EXPECT_EQ(b.keyframe.covered.pixels(), a.keyframe.covered.pixels());
  EXPECT_EQ(b.keyframe.camera.eye, a.keyframe.camera.eye);
  EXPECT_EQ(b.keyframe.camera.forward, a.keyframe.camera.forward);
  EXPECT_EQ(b.keyframe.camera.fovYRadians, a.keyframe.camera.fovYRadians);
  EXPECT_EQ(b.keyframe.depthMode, a.keyframe.depthMode);
  ASSERT_EQ(b.mesh.quads.size(), a.mesh.quads.size());
  for (std::size_t i = 0; i < a.mesh.quads.size(); ++i) {
    EXPECT_EQ(b.mesh.quads[i].world, a.mesh.quads[i].world);
    EXPECT_EQ(b.mesh.quads[i].pixel, a.mesh.quads[i].pixel);
    EXPECT_EQ(b.mesh.quads[i].eyeZ, a.mesh.quads[i].eyeZ);
    EXPECT_EQ(b.mesh.quads[i].maxDelta, a.mesh.quads[i].maxDelta);
    EXPECT_EQ(b.mesh.quads[i].rect.x1, a.mesh.quads[i].rect.x1);
  }
  EXPECT_EQ(b.mesh.stats.criterion, DeltaCriterion::PerAxisMax);
  EXPECT_EQ(b.mesh.stats.tauParallaxPx, 0.5);
  EXPECT_EQ(b.mesh.stats.emptyPixels, 11);
  EXPECT_EQ(b.render.trianglesDrawn, 12345u);
  // Encoding what was decoded gives the same bytes (no timings stored).
  EXPECT_EQ(encode(b), bytes);
}

TEST(KeyframeDb, EveryTruncationIsAnErrorNamingTheFile) {
  const std::string bytes = encode(sample(5, 4, 3, 2));
  for (std::size_t n = 0; n < bytes.size(); ++n) {
    CachedKeyframe out;
    const Status s = decodeKeyframe(std::string_view(bytes).substr(0, n), "cut.hwkf", out);
    ASSERT_FALSE(s.ok()) << "length " << n;
    EXPECT_NE(s.error().message.find("cut.hwkf"), std::string::npos) << s.error().message;
    const char* want = n < kKeyframeHeaderBytes ? "header" : "truncated";
    EXPECT_NE(s.error().message.find(want), std::string::npos) << s.error().message;
  }
  CachedKeyframe out;
  EXPECT_FALSE(decodeKeyframe(bytes + "x", "long.hwkf", out).ok());
}

TEST(KeyframeDb, EveryFlippedByteIsDetected) {
  const std::string bytes = encode(sample(6, 5, 4, 3));
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    if (i >= 56 && i < 64) continue;  // reserved header bytes, not read
    std::string bad = bytes;
    bad[i] = static_cast<char>(bad[i] ^ 0x10);
    CachedKeyframe out;
    const Status s = decodeKeyframe(bad, "flip.hwkf", out);
    ASSERT_FALSE(s.ok()) << "byte " << i;
    EXPECT_NE(s.error().message.find("flip.hwkf"), std::string::npos);
    if (i >= kKeyframeHeaderBytes) {
      EXPECT_NE(s.error().message.find("checksum mismatch"), std::string::npos)
          << s.error().message;
    }
  }
}

TEST(KeyframeDb, VersionAndMagicMismatch) {
  std::string bytes = encode(sample(4, 4, 1, 4));
  CachedKeyframe out;
  std::string badMagic = bytes;
  badMagic[0] = 'X';
  Status s = decodeKeyframe(badMagic, "m.hwkf", out);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("magic"), std::string::npos) << s.error().message;
  std::string v2 = bytes;
  const std::uint32_t two = 2;
  std::memcpy(v2.data() + 8, &two, 4);
  s = decodeKeyframe(v2, "v.hwkf", out);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("version 2"), std::string::npos) << s.error().message;
}

TEST(KeyframeDb, Hw64DiffersOnEveryBitOfShortInputs) {
  const std::string a = "hybridwalk keyframe";
  const std::uint64_t h = hw64(a.data(), a.size());
  for (std::size_t i = 0; i < a.size(); ++i)
    for (int bit = 0; bit < 8; ++bit) {
      std::string b = a;
      b[i] = static_cast<char>(b[i] ^ (1 << bit));
      EXPECT_NE(hw64(b.data(), b.size()), h);
    }
  EXPECT_NE(hw64(a.data(), a.size() - 1), h);
  EXPECT_EQ(hex64(0x1234), "0000000000001234");
}

class KeyframeDbDir : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = (std::filesystem::temp_directory_path() /
            ("hw_kfdb_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name()))
               .string();
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
    prov_.scene = "indoor";
    prov_.triangles = 100;
    prov_.pathHash = "00000000000000ff";
    prov_.frames = 11;
    prov_.width = 6;
    prov_.height = 5;
    prov_.depthMode = "fixed24";
    prov_.mesh = meshOptionsJson(LodOptions{});
    std::vector<KeyframeDbEntry> entries;
    for (int f : {0, 10}) {
      CachedKeyframe c = sample(6, 5, 4, static_cast<unsigned>(f + 10));
      const std::string bytes = encodeKeyframe(f, c.keyframe, c.mesh, c.render);
      KeyframeDbEntry e{f, keyframeFileName(f), bytes.size(), *keyframeFileChecksum(bytes, "x")};
      ASSERT_TRUE(writeFileAtomic(dir_ + "/" + e.file, bytes).ok());
      entries.push_back(e);
    }
    ASSERT_TRUE(writeFileAtomic(dir_ + "/index.json", keyframeDbIndexJson(prov_, entries)).ok());
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string dir_;
  KeyframeDbProvenance prov_;
};

TEST_F(KeyframeDbDir, OpenReadAndMatch) {
  auto db = KeyframeDb::open(dir_);
  ASSERT_TRUE(db.ok()) << db.error().message;
  EXPECT_EQ(db->keyframeFrames(), (std::vector<int>{0, 10}));
  EXPECT_TRUE(db->checkMatches(prov_).ok());
  KeyframeDbProvenance other = prov_;
  other.scene = "outdoor";
  const Status s = db->checkMatches(other);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("scene \"indoor\""), std::string::npos) << s.error().message;
  other = prov_;
  other.mesh["tau"] = 4096.0;
  EXPECT_FALSE(db->checkMatches(other).ok());
  // The gradient tolerance is recorded only when used (a database baked
  // before it existed still matches a fixed-τ run), and refused both ways.
  EXPECT_FALSE(prov_.mesh.contains("tau_gradient"));
  LodOptions grad;
  grad.tauGradient = 0.005;
  other = prov_;
  other.mesh = meshOptionsJson(grad);
  EXPECT_EQ(other.mesh["tau_gradient"], 0.005);
  const Status g = db->checkMatches(other);
  ASSERT_FALSE(g.ok());
  EXPECT_NE(g.error().message.find("mesh.tau_gradient"), std::string::npos) << g.error().message;
  CachedKeyframe out;
  ASSERT_TRUE(db->read(10, out).ok());
  EXPECT_EQ(out.frame, 10);
  EXPECT_FALSE(db->read(5, out).ok());
  // A database baked with the gradient tolerance, read by a run without it,
  // names it too.
  nlohmann::json ix = nlohmann::json::parse(*readFile(dir_ + "/index.json"));
  ix["baked_from"]["mesh"] = meshOptionsJson(grad);
  ix["index_checksum"] = indexChecksum(ix);
  ASSERT_TRUE(writeFileAtomic(dir_ + "/index.json", ix.dump(1)).ok());
  auto dbGrad = KeyframeDb::open(dir_);
  ASSERT_TRUE(dbGrad.ok()) << dbGrad.error().message;
  KeyframeDbProvenance bakedGrad = prov_;
  bakedGrad.mesh = meshOptionsJson(grad);
  EXPECT_TRUE(dbGrad->checkMatches(bakedGrad).ok());
  const Status g2 = dbGrad->checkMatches(prov_);
  ASSERT_FALSE(g2.ok());
  EXPECT_NE(g2.error().message.find("mesh.tau_gradient 0.005, this run has null"),
            std::string::npos)
      << g2.error().message;
}

TEST_F(KeyframeDbDir, CorruptTruncatedAndReplacedFilesAreNamed) {
  const std::string f = dir_ + "/" + keyframeFileName(10);
  std::string bytes = *readFile(f);
  auto db = KeyframeDb::open(dir_);
  ASSERT_TRUE(db.ok());
  CachedKeyframe out;
  // One flipped byte in the payload.
  std::string bad = bytes;
  bad[bad.size() / 2] ^= 1;
  ASSERT_TRUE(writeFileAtomic(f, bad).ok());
  Status s = db->read(10, out);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find(keyframeFileName(10)), std::string::npos);
  EXPECT_NE(s.error().message.find("checksum"), std::string::npos) << s.error().message;
  // Truncated.
  ASSERT_TRUE(writeFileAtomic(f, bytes.substr(0, bytes.size() - 100)).ok());
  s = db->read(10, out);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("truncated"), std::string::npos) << s.error().message;
  // Replaced by another valid keyframe file of the same size.
  CachedKeyframe c = sample(6, 5, 4, 99);
  const std::string other = encodeKeyframe(10, c.keyframe, c.mesh, c.render);
  ASSERT_EQ(other.size(), bytes.size());
  ASSERT_TRUE(writeFileAtomic(f, other).ok());
  s = db->read(10, out);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("index.json"), std::string::npos) << s.error().message;
}

TEST_F(KeyframeDbDir, OpenChecksEveryFileSizeBeforeAnyRead) {
  const std::string f = dir_ + "/" + keyframeFileName(10);
  const std::string bytes = *readFile(f);
  ASSERT_TRUE(writeFileAtomic(f, bytes.substr(0, bytes.size() - 1)).ok());
  auto cut = KeyframeDb::open(dir_);
  ASSERT_FALSE(cut.ok());
  EXPECT_NE(cut.error().message.find(keyframeFileName(10) + ": truncated"), std::string::npos)
      << cut.error().message;
  ASSERT_TRUE(writeFileAtomic(f, bytes + "x").ok());
  auto grown = KeyframeDb::open(dir_);
  ASSERT_FALSE(grown.ok());
  EXPECT_NE(grown.error().message.find("grown"), std::string::npos) << grown.error().message;
  std::filesystem::remove(f);
  auto gone = KeyframeDb::open(dir_);
  ASSERT_FALSE(gone.ok());
  EXPECT_NE(gone.error().message.find(keyframeFileName(10)), std::string::npos)
      << gone.error().message;
}

TEST_F(KeyframeDbDir, PrefetchingSourceGivesTheSameKeyframes) {
  auto db = KeyframeDb::open(dir_);
  ASSERT_TRUE(db.ok());
  auto shared = std::make_shared<KeyframeDb>(std::move(*db));
  auto hits = std::make_shared<std::size_t>(0);
  auto source = makeKeyframeDbSource(shared, true, hits);
  for (int f : {0, 10, 0, 10}) {
    CachedKeyframe a, b;
    ASSERT_TRUE(source(f, a).ok());
    ASSERT_TRUE(shared->read(f, b).ok());
    EXPECT_EQ(a.frame, f);
    EXPECT_EQ(a.keyframe.colour.pixels(), b.keyframe.colour.pixels());
    EXPECT_EQ(a.mesh.quads.size(), b.mesh.quads.size());
    std::this_thread::sleep_for(std::chrono::milliseconds(100));  // time for the read-ahead
  }
  EXPECT_GE(*hits, 1u);  // frame 10 after frame 0 comes from the prefetch
}

TEST_F(KeyframeDbDir, IndexErrors) {
  auto text = *readFile(dir_ + "/index.json");
  ASSERT_TRUE(writeFileAtomic(dir_ + "/index.json", text.substr(0, text.size() / 2)).ok());
  auto db = KeyframeDb::open(dir_);
  ASSERT_FALSE(db.ok());
  EXPECT_NE(db.error().message.find("index.json"), std::string::npos);
  auto j = nlohmann::json::parse(text);
  j["version"] = 99;
  ASSERT_TRUE(writeFileAtomic(dir_ + "/index.json", j.dump()).ok());
  db = KeyframeDb::open(dir_);
  ASSERT_FALSE(db.ok());
  EXPECT_NE(db.error().message.find("version 99"), std::string::npos) << db.error().message;
  std::filesystem::remove(dir_ + "/index.json");
  db = KeyframeDb::open(dir_);
  ASSERT_FALSE(db.ok());
  EXPECT_NE(db.error().message.find("missing"), std::string::npos);
  EXPECT_FALSE(KeyframeDb::open(dir_ + "/nope").ok());
}

}  // namespace
TEST_F(KeyframeDbDir, IndexChecksumCatchesConsistentEdits) {
  auto text = *readFile(dir_ + "/index.json");
  auto ix = nlohmann::json::parse(text);
  EXPECT_EQ(ix["index_checksum"], indexChecksum(ix));
  // An entry dropped: the old checksum no longer matches.
  auto dropped = ix;
  dropped["keyframes"].erase(1);
  ASSERT_TRUE(writeFileAtomic(dir_ + "/index.json", dropped.dump(1)).ok());
  auto db = KeyframeDb::open(dir_);
  ASSERT_FALSE(db.ok());
  EXPECT_NE(db.error().message.find("index_checksum"), std::string::npos) << db.error().message;
  // Re-sealed: opens, but the schedule check names the missing frame.
  dropped["index_checksum"] = indexChecksum(dropped);
  ASSERT_TRUE(writeFileAtomic(dir_ + "/index.json", dropped.dump(1)).ok());
  db = KeyframeDb::open(dir_);
  ASSERT_TRUE(db.ok()) << db.error().message;
  const Status s = db->checkSchedule({0, 10});
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find("no keyframe for frame 10"), std::string::npos)
      << s.error().message;
  EXPECT_TRUE(db->checkSchedule({0}).ok());
  // Without the checksum at all.
  ix.erase("index_checksum");
  ASSERT_TRUE(writeFileAtomic(dir_ + "/index.json", ix.dump(1)).ok());
  EXPECT_FALSE(KeyframeDb::open(dir_).ok());
}

TEST(KeyframeDbEntries, FrameRangeChecksumAndNamesAreChecked) {
  auto entry = [](nlohmann::json frame, std::string checksum, std::string file) {
    return nlohmann::json::array({{{"frame", frame},
                                   {"file", file},
                                   {"bytes", 100},
                                   {"checksum", checksum}}});
  };
  EXPECT_TRUE(parseKeyframeEntries(entry(5, "00000000000000ff", "kf.hwkf"), "i").ok());
  auto wrap = parseKeyframeEntries(entry(4294967301ull, "00000000000000ff", "kf"), "i");
  ASSERT_FALSE(wrap.ok());
  EXPECT_NE(wrap.error().message.find("4294967301"), std::string::npos) << wrap.error().message;
  EXPECT_FALSE(parseKeyframeEntries(entry(-1, "00000000000000ff", "kf"), "i").ok());
  auto hex = parseKeyframeEntries(entry(5, "zzzzzzzzzzzzzzzz", "kf"), "i");
  ASSERT_FALSE(hex.ok());
  EXPECT_NE(hex.error().message.find("16 hex digits"), std::string::npos);
  EXPECT_FALSE(parseKeyframeEntries(entry(5, "-0000000000000ff", "kf"), "i").ok());
  EXPECT_FALSE(parseKeyframeEntries(entry(5, "00000000000000ff", "../kf"), "i").ok());
  EXPECT_FALSE(parseKeyframeEntries(nlohmann::json::object(), "i").ok());
}

TEST(KeyframeDbDecode, NonFiniteOrOutsideQuadCornersAreErrors) {
  CachedKeyframe c = sample(6, 5, 3, 42u);
  CachedKeyframe out;
  ASSERT_TRUE(decodeKeyframe(encodeKeyframe(7, c.keyframe, c.mesh, c.render), "f", out).ok());
  auto bad = [&](auto edit, const char* want) {
    CachedKeyframe d = c;
    edit(d);
    const Status s = decodeKeyframe(encodeKeyframe(7, d.keyframe, d.mesh, d.render), "f", out);
    ASSERT_FALSE(s.ok()) << want;
    EXPECT_NE(s.error().message.find(want), std::string::npos) << s.error().message;
  };
  const double nan = std::nan("");
  bad([&](CachedKeyframe& d) { d.mesh.quads[1].world[2].y = nan; }, "quad 1: corner 2");
  bad([&](CachedKeyframe& d) { d.mesh.quads[0].pixel[0].x = 1e6; }, "outside the image");
  bad([&](CachedKeyframe& d) { d.mesh.quads[2].eyeZ[3] = -1; }, "eye depth");
  bad([&](CachedKeyframe& d) { d.keyframe.camera.eye.x = nan; }, "not a valid camera");
}

TEST(KeyframeDbDecode, ExpectationNamesSizePoseAndDepthMode) {
  CachedKeyframe c = sample(6, 5, 3, 43u);
  c.frame = 3;
  KeyframeExpectation want{[&](int) { return c.keyframe.camera; }, c.keyframe.depthMode};
  EXPECT_TRUE(checkKeyframeExpectation(c, want, "f").ok());
  auto fails = [&](KeyframeExpectation w, const char* what) {
    const Status s = checkKeyframeExpectation(c, w, "f");
    ASSERT_FALSE(s.ok()) << what;
    EXPECT_NE(s.error().message.find(what), std::string::npos) << s.error().message;
  };
  KeyframeExpectation w = want;
  w.cameraAt = [&](int) {
    Camera m = c.keyframe.camera;
    m.width = 7;
    return m;
  };
  fails(w, "size 6x5");
  w.cameraAt = [&](int) {
    Camera m = c.keyframe.camera;
    m.eye.x += 0.5;
    return m;
  };
  fails(w, "has eye");
  w = want;
  w.depthMode = DepthMode::Fixed24;
  fails(w, "depth mode");
}

}  // namespace hw::keyframe
