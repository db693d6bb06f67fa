// session/publish.h: the web folder's checksum and the embedded page.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "session/publish.h"

namespace hw::session {
namespace {

TEST(Publish, Hw32OfNothingIsItsSeed) { EXPECT_EQ(hw32("", 0), 2166136261u); }

TEST(Publish, Hw32DetectsEveryFlippedByte) {
  std::vector<unsigned char> bytes(103);  // not a whole number of words
  for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<unsigned char>(i * 37 + 5);
  const std::uint32_t h = hw32(bytes.data(), bytes.size());
  for (std::size_t i = 0; i < bytes.size(); ++i)
    for (int bit = 0; bit < 8; ++bit) {
      bytes[i] ^= static_cast<unsigned char>(1 << bit);
      EXPECT_NE(hw32(bytes.data(), bytes.size()), h) << "byte " << i << " bit " << bit;
      bytes[i] ^= static_cast<unsigned char>(1 << bit);
    }
  // A zero byte appended changes the length, not the padded words.
  bytes.push_back(0);
  EXPECT_NE(hw32(bytes.data(), bytes.size()), h);
}

TEST(Publish, ThePageIsEmbeddedWhole) {
  const std::string html = webIndexHtml(), js = webPlayerJs();
  EXPECT_NE(html.find("<script type=\"module\" src=\"player.js\"></script>"), std::string::npos);
  EXPECT_NE(html.find("</html>"), std::string::npos);
  EXPECT_NE(html.find("content=\"@MANIFEST@\""), std::string::npos);  // publish fills it in
  EXPECT_NE(js.find("window.hwRender"), std::string::npos);
  EXPECT_NE(js.rfind("main();"), std::string::npos);
  EXPECT_GT(js.size(), 8000u);  // more than one embedded piece
}

}  // namespace
}  // namespace hw::session
