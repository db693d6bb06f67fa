// Auto's pinned choices (session/mode_pin.h): a pin written is read back as
// it was; every way a pin file can be wrong is an error that names the file
// and what was expected; the hash that names a pin changes with what it is fed.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "session/mode_pin.h"

namespace hw::session {
namespace {

namespace fs = std::filesystem;

std::string tempDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() /
                     ("hw_mode_pin_" + name + "_" +
                      std::to_string(::testing::UnitTest::GetInstance()->random_seed()));
  fs::remove_all(d);
  return d.string();
}

void writeText(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

TEST(ModePin, WrittenPinsReadBackAndMissingOnesAreNotErrors) {
  const std::string dir = tempDir("roundtrip");
  const std::string file = dir + "/sub/walk-1.json";  // the folder is made
  const std::vector<FrameKind> kinds = {FrameKind::Keyframe, FrameKind::Warp, FrameKind::Warp,
                                        FrameKind::Geometry, FrameKind::Keyframe};
  bool found = true;
  auto none = readModePin(file, 5, &found);
  ASSERT_TRUE(none.ok()) << none.error().message;
  EXPECT_FALSE(found);
  ASSERT_TRUE(writeModePin(file, ModePin{kinds, {-1, 3, 0, -1, -1}}, "indoor").ok());
  auto back = readModePin(file, 5, &found);
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_TRUE(found);
  EXPECT_EQ(back->kinds, kinds);
  EXPECT_EQ(back->holeRects, (std::vector<int>{-1, 3, 0, -1, -1}));
  // Without hole rectangles (modes only): read back without them.
  ASSERT_TRUE(writeModePin(file, ModePin{kinds, {}}, "indoor").ok());
  back = readModePin(file, 5, &found);
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_EQ(back->kinds, kinds);
  EXPECT_TRUE(back->holeRects.empty());
  // Another walk length is another walk.
  auto other = readModePin(file, 6, &found);
  ASSERT_FALSE(other.ok());
  EXPECT_NE(other.error().message.find("expected \"frames\": 6, got 5"), std::string::npos)
      << other.error().message;
  fs::remove_all(dir);
}

TEST(ModePin, MalformedPinsAreErrorsNamingTheFileAndWhatWasExpected) {
  const std::string dir = tempDir("bad");
  fs::create_directories(dir);
  struct Case {
    const char* text;
    const char* says;
  } cases[] = {
      {"not json", "invalid JSON"},
      {"[1,2]", "expected \"format\""},
      {R"({"format":"hybridwalk mode pin","version":2,"frames":3,"modes":"kwk"})",
       "expected \"version\": 1, got 2"},
      {R"({"format":"hybridwalk mode pin","version":1,"frames":3})", "expected \"modes\""},
      {R"({"format":"hybridwalk mode pin","version":1,"frames":3,"modes":"kw"})",
       "expected 3 letters, got 2"},
      {R"({"format":"hybridwalk mode pin","version":1,"frames":3,"modes":"kxk"})",
       "frame 1: expected g, w or k, got 'x'"},
      {R"({"format":"hybridwalk mode pin","version":1,"frames":"3","modes":"kwk"})",
       "expected \"frames\": 3, got \"3\""},
      {R"({"format":"hybridwalk mode pin","version":1,"frames":3,"modes":"kwk","hole_rects":[-1,2]})",
       "\"hole_rects\": expected an array of 3 integers, got 2 entries"},
      {R"({"format":"hybridwalk mode pin","version":1,"frames":3,"modes":"kwk","hole_rects":[-1,-2,-1]})",
       "\"hole_rects\": frame 1: expected an integer from -1 to 1000000, got -2"},
      {R"({"format":"hybridwalk mode pin","version":1,"frames":3,"modes":"kwk","hole_rects":[-1,1.5,-1]})",
       "frame 1: expected an integer from -1 to 1000000, got 1.5"},
  };
  for (const Case& c : cases) {
    const std::string file = dir + "/pin.json";
    writeText(file, c.text);
    bool found = true;
    auto r = readModePin(file, 3, &found);
    ASSERT_FALSE(r.ok()) << c.text;
    EXPECT_NE(r.error().message.find(file), std::string::npos) << r.error().message;
    EXPECT_NE(r.error().message.find(c.says), std::string::npos) << r.error().message;
  }
  // A FIFO where a pin would be: refused, not read (which would block).
  const std::string fifo = dir + "/fifo.json";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  bool found = true;
  auto r = readModePin(fifo, 3, &found);
  EXPECT_FALSE(r.ok());
  // A folder that cannot be made: an error, nothing written.
  writeText(dir + "/file", "x");
  EXPECT_FALSE(writeModePin(dir + "/file/pin.json", ModePin{{FrameKind::Geometry}, {}}, "x").ok());
  fs::remove_all(dir);
}

TEST(ModePin, TheNameChangesWithWhatIsHashed) {
  PinHasher a, b, c;
  a.text("indoor");
  a.number(1.0);
  b.text("indoor");
  b.number(1.0);
  c.text("indoor");
  c.number(1.0000001);
  EXPECT_EQ(a.hex(), b.hex());
  EXPECT_NE(a.hex(), c.hex());
  EXPECT_EQ(a.hex().size(), 16u);
  // Lengths are hashed: "ab"+"c" is not "a"+"bc".
  PinHasher d, e;
  d.text("ab");
  d.text("c");
  e.text("a");
  e.text("bc");
  EXPECT_NE(d.hex(), e.hex());
}

TEST(ModePin, TheFolderFollowsTheEnvironment) {
  struct Saved {
    const char* name;
    bool set;
    std::string value;
  };
  std::vector<Saved> saved;
  for (const char* n : {"HYBRIDWALK_PINS", "XDG_CACHE_HOME", "HOME"}) {
    const char* v = std::getenv(n);
    saved.push_back({n, v != nullptr, v ? v : ""});
  }
  ::setenv("HYBRIDWALK_PINS", "/somewhere/pins", 1);
  EXPECT_EQ(defaultModePinDir(), "/somewhere/pins");
  ::unsetenv("HYBRIDWALK_PINS");
  ::setenv("XDG_CACHE_HOME", "/xdg", 1);
  EXPECT_EQ(defaultModePinDir(), "/xdg/hybridwalk/mode-pins");
  ::unsetenv("XDG_CACHE_HOME");
  ::setenv("HOME", "/home/u", 1);
  EXPECT_EQ(defaultModePinDir(), "/home/u/.cache/hybridwalk/mode-pins");
  ::unsetenv("HOME");
  EXPECT_EQ(defaultModePinDir(), "");  // nowhere to keep pins: none are kept
  for (const Saved& s : saved)
    if (s.set)
      ::setenv(s.name, s.value.c_str(), 1);
    else
      ::unsetenv(s.name);
}

}  // namespace
}  // namespace hw::session
