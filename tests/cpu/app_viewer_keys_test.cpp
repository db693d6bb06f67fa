// The viewer's key table, scripted keys and statistics levels
// (app/viewer_keys.h): `h` and `view --help` list the same keys, "@N" marks
// type keys before frame N, and `s` cycles fps -> stages -> stalls -> off.
#include <gtest/gtest.h>

#include <string>

#include "app/viewer_keys.h"

namespace hw::app {
namespace {

TEST(ViewerKeys, HelpAndCommandLineListEveryKey) {
  const std::string help = viewerKeyHelp();
  const std::string line = viewerKeyLine();
  ASSERT_GE(viewerKeys().size(), 13u);
  for (const ViewerKey& k : viewerKeys()) {
    EXPECT_NE(help.find(std::string("  ") + k.key + " "), std::string::npos) << k.key;
    EXPECT_NE(line.find(std::string(k.key) + " " + k.brief), std::string::npos) << k.key;
  }
  // osgviewer's keys (DESIGN.md "Viewer conventions"), full screen included.
  for (const char* k : {"s statistics", "w wireframe", "f full screen", "c screenshot", "z record",
                        "Z play", "space home", "Esc quit", "h help"})
    EXPECT_NE(line.find(k), std::string::npos) << k << " in: " << line;
}

TEST(ViewerKeys, PlainKeysAreTypedBeforeTheFirstFrame) {
  auto k = parseScriptedKeys("so");
  ASSERT_TRUE(k.ok()) << k.error().message;
  ASSERT_EQ(k->size(), 2u);
  EXPECT_EQ((*k)[0].frame, 0);
  EXPECT_EQ((*k)[0].key, unsigned('s'));
  EXPECT_EQ((*k)[1].frame, 0);
  EXPECT_EQ((*k)[1].key, unsigned('o'));
  auto empty = parseScriptedKeys("");
  ASSERT_TRUE(empty.ok());
  EXPECT_TRUE(empty->empty());
}

TEST(ViewerKeys, FrameMarksTypeTheKeysAfterThemBeforeThatFrame) {
  auto k = parseScriptedKeys("s@30pp@30g@125p");
  ASSERT_TRUE(k.ok()) << k.error().message;
  ASSERT_EQ(k->size(), 5u);
  const long frames[] = {0, 30, 30, 30, 125};
  const char keys[] = {'s', 'p', 'p', 'g', 'p'};
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_EQ((*k)[i].frame, frames[i]) << i;
    EXPECT_EQ((*k)[i].key, static_cast<unsigned>(keys[i])) << i;
  }
}

TEST(ViewerKeys, BadFrameMarksAreErrorsNamingTheText) {
  for (const char* bad : {"s@", "@p", "s@x", "@20p@10p", "@99999999999p"}) {
    auto k = parseScriptedKeys(bad);
    ASSERT_FALSE(k.ok()) << bad;
    EXPECT_NE(k.error().message.find(std::string("'") + bad + "'"), std::string::npos)
        << k.error().message;
  }
  EXPECT_NE(parseScriptedKeys("@20p@10p").error().message.find("must not decrease"),
            std::string::npos);
}

TEST(ViewerKeys, SCyclesFpsStagesStallsOff) {
  StatsLevel l = StatsLevel::Fps;  // where the viewer starts
  l = nextStatsLevel(l);
  EXPECT_EQ(l, StatsLevel::Stages);
  l = nextStatsLevel(l);  // a second s: the keyframe stalls, not off
  EXPECT_EQ(l, StatsLevel::Stalls);
  EXPECT_NE(std::string(statsLevelDescription(l)).find("stalls"), std::string::npos);
  l = nextStatsLevel(l);
  EXPECT_EQ(l, StatsLevel::Off);
  EXPECT_EQ(std::string(statsLevelDescription(l)), "statistics off");
  EXPECT_EQ(nextStatsLevel(l), StatsLevel::Fps);
}

}  // namespace
}  // namespace hw::app
