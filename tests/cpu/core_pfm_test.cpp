// PFM read/write (core/pfm.h): bit-exact round trip, the PFM row order
// (bottom row first on disk), both endiannesses, and errors that name the
// file for every truncation and for garbage or 3-channel input.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>
#include <string>

#include "core/file_io.h"
#include "core/pfm.h"

namespace hw {
namespace {

std::string tempDir() {
  const auto d =
      std::filesystem::temp_directory_path() /
      ("hw_pfm_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
       ::testing::UnitTest::GetInstance()->current_test_info()->name());
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d.string();
}

Image<float> randomImage(int w, int h, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> dist(-1000.0f, 1000.0f);
  Image<float> img(w, h);
  for (float& v : img.pixels()) v = dist(rng);
  return img;
}

bool bitEqual(const Image<float>& a, const Image<float>& b) {
  return a.width() == b.width() && a.height() == b.height() &&
         std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

TEST(Pfm, RoundTripIsBitExactIncludingSpecialValues) {
  const std::string dir = tempDir();
  Image<float> img = randomImage(7, 5, 1);
  img(0, 0) = 0.0f;
  img(1, 0) = -0.0f;
  img(2, 0) = std::numeric_limits<float>::infinity();
  img(3, 0) = std::numeric_limits<float>::denorm_min();
  img(4, 0) = std::numeric_limits<float>::quiet_NaN();
  img(6, 4) = std::numeric_limits<float>::max();
  ASSERT_TRUE(writePfm(dir + "/a.pfm", img).ok());
  auto back = readPfm(dir + "/a.pfm");
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_TRUE(bitEqual(img, *back));
  // No temporary left beside the file.
  int files = 0;
  for ([[maybe_unused]] auto& e : std::filesystem::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 1);
}

TEST(Pfm, HeaderIsLittleEndianSingleChannelAndTopRowIsStoredLast) {
  const int w = 4, h = 3;
  Image<float> img(w, h, 1.0f);
  for (int x = 0; x < w; ++x) img(x, 0) = 42.5f + x;  // our row 0 = top
  const std::string bytes = encodePfm(img);
  const std::string header = "Pf\n4 3\n-1.0\n";
  ASSERT_EQ(bytes.size(), header.size() + w * h * 4);
  EXPECT_EQ(bytes.substr(0, header.size()), header);
  // Last row in the file holds row 0, little-endian.
  const std::size_t lastRow = header.size() + (h - 1) * w * 4;
  for (int x = 0; x < w; ++x) {
    const auto* p = reinterpret_cast<const unsigned char*>(bytes.data() + lastRow + 4 * x);
    const std::uint32_t bits = std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 |
                               std::uint32_t(p[2]) << 16 | std::uint32_t(p[3]) << 24;
    EXPECT_EQ(std::bit_cast<float>(bits), 42.5f + x);
  }
  // The first row in the file is our bottom row.
  const auto* p = reinterpret_cast<const unsigned char*>(bytes.data() + header.size());
  const std::uint32_t first = std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 |
                              std::uint32_t(p[2]) << 16 | std::uint32_t(p[3]) << 24;
  EXPECT_EQ(std::bit_cast<float>(first), 1.0f);
}

TEST(Pfm, ReadsBigEndianFilesAndOtherWhitespace) {
  Image<float> img = randomImage(3, 2, 2);
  std::string le = encodePfm(img);
  const std::size_t header = std::string("Pf\n3 2\n-1.0\n").size();
  std::string be = "Pf 3\t2\r\n1.0\n";
  for (std::size_t i = header; i < le.size(); i += 4)
    for (int k = 3; k >= 0; --k) be.push_back(le[i + static_cast<std::size_t>(k)]);
  auto back = decodePfm(be, "be.pfm");
  ASSERT_TRUE(back.ok()) << back.error().message;
  EXPECT_TRUE(bitEqual(img, *back));
}

TEST(Pfm, EveryTruncationIsAnErrorNamingTheFile) {
  const std::string bytes = encodePfm(randomImage(5, 4, 3));
  for (std::size_t n = 0; n < bytes.size(); ++n) {
    auto r = decodePfm(std::string_view(bytes).substr(0, n), "cut.pfm");
    ASSERT_FALSE(r.ok()) << "prefix of " << n << " bytes accepted";
    EXPECT_NE(r.error().message.find("cut.pfm"), std::string::npos) << r.error().message;
  }
}

TEST(Pfm, TruncatedFileReportsExpectedAndGotBytes) {
  const std::string dir = tempDir();
  const std::string file = dir + "/short.pfm";
  std::string bytes = encodePfm(randomImage(8, 6, 4));
  bytes.resize(bytes.size() - 10);
  ASSERT_TRUE(writeFileAtomic(file, bytes).ok());
  auto r = readPfm(file);
  ASSERT_FALSE(r.ok());
  const std::string& m = r.error().message;
  EXPECT_NE(m.find(file), std::string::npos) << m;
  EXPECT_NE(m.find("truncated"), std::string::npos) << m;
  EXPECT_NE(m.find("expected 192 bytes"), std::string::npos) << m;
  EXPECT_NE(m.find("got 182"), std::string::npos) << m;
}

TEST(Pfm, TrailingBytesAreAnError) {
  std::string bytes = encodePfm(randomImage(2, 2, 5)) + "xx";
  auto r = decodePfm(bytes, "long.pfm");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("expected 16 bytes"), std::string::npos) << r.error().message;
}

TEST(Pfm, ThreeChannelFileIsRejected) {
  const std::string dir = tempDir();
  const std::string file = dir + "/rgb.pfm";
  ASSERT_TRUE(writeFileAtomic(file, "PF\n1 1\n-1.0\n" + std::string(12, '\0')).ok());
  auto r = readPfm(file);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find(file), std::string::npos) << r.error().message;
  EXPECT_NE(r.error().message.find("expected 1 channel"), std::string::npos) << r.error().message;
}

TEST(Pfm, GarbageHeadersAreErrorsNamingTheFile) {
  const std::string pix(4, '\0');
  const char* bad[] = {
      "P6\n1 1\n255\n",          // another format
      "Pf\nx 1\n-1.0\n",         // non-numeric width
      "Pf\n1 1.5\n-1.0\n",       // non-integer height
      "Pf\n0 1\n-1.0\n",         // zero width
      "Pf\n-1 1\n-1.0\n",        // negative width
      "Pf\n1 99999999\n-1.0\n",  // absurd height
      "Pf\n1 1\n0.0\n",          // zero scale: no endianness
      "Pf\n1 1\nnan\n",          // non-finite scale
      "Pf\n1 1\n-1.0x\n",        // junk after the scale
      "Pf\n1 1\n-1.0",           // no separator before the pixels
      "",                        // empty
  };
  for (const char* h : bad) {
    auto r = decodePfm(std::string(h) + pix, "junk.pfm");
    ASSERT_FALSE(r.ok()) << "accepted header: " << h;
    EXPECT_NE(r.error().message.find("junk.pfm"), std::string::npos) << r.error().message;
  }
  auto r = decodePfm("\x89PNG\r\n\x1a\n binary junk", "png.pfm");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("magic"), std::string::npos) << r.error().message;
}

TEST(Pfm, MissingFileAndEmptyImageAreErrors) {
  const std::string dir = tempDir();
  auto r = readPfm(dir + "/nope.pfm");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("nope.pfm"), std::string::npos);
  EXPECT_FALSE(writePfm(dir + "/empty.pfm", Image<float>()).ok());
  EXPECT_FALSE(std::filesystem::exists(dir + "/empty.pfm"));
}

}  // namespace
}  // namespace hw
