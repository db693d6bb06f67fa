// Image<T>/ImageView<T> (core/image.h), file I/O (core/file_io.h: atomic
// writes, PNG round trip, errors that name the file) and the order
// statistics in core/timer.h.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "core/file_io.h"
#include "core/image.h"
#include "core/timer.h"

namespace hw {
namespace {

namespace fs = std::filesystem;

// A fresh, empty directory per test (tests may run in parallel under ctest).
std::string freshDir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const fs::path dir = fs::path(::testing::TempDir()) /
                       ("hw_core_image_" + std::to_string(::getpid()) + "_" +
                        info->test_suite_name() + "_" + info->name());
  std::error_code ec;
  fs::remove_all(dir, ec);
  fs::create_directories(dir);
  return dir.string();
}

std::vector<std::string> listDir(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  return names;
}

Image<Rgba8> randomRgba(int w, int h, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> d(0, 255);
  Image<Rgba8> im(w, h);
  for (Rgba8& p : im.pixels()) {
    p = Rgba8{static_cast<std::uint8_t>(d(rng)), static_cast<std::uint8_t>(d(rng)),
              static_cast<std::uint8_t>(d(rng)), static_cast<std::uint8_t>(d(rng))};
  }
  return im;
}

void writeRaw(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

// ---------------------------------------------------------------- Image

TEST(Image, ConstructionAndFill) {
  const Image<int> empty;
  EXPECT_TRUE(empty.empty());
  EXPECT_EQ(empty.width(), 0);
  EXPECT_EQ(empty.height(), 0);
  EXPECT_EQ(empty.size(), 0u);

  Image<int> im(7, 3, 42);
  EXPECT_FALSE(im.empty());
  EXPECT_EQ(im.width(), 7);
  EXPECT_EQ(im.height(), 3);
  EXPECT_EQ(im.size(), 21u);
  for (int v : im.pixels()) EXPECT_EQ(v, 42);
  im.fill(-1);
  for (int v : im.pixels()) EXPECT_EQ(v, -1);

  // Row-major, row 0 first: (x, y) is element y·width + x.
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 7; ++x) im(x, y) = 100 * y + x;
  for (int i = 0; i < 21; ++i) EXPECT_EQ(im.data()[i], 100 * (i / 7) + i % 7);
  EXPECT_EQ(im.at(6, 2), 206);
  const Image<int>& cim = im;
  EXPECT_EQ(cim.at(0, 1), 100);
  EXPECT_EQ(&cim(3, 2), cim.data() + 2 * 7 + 3);

  // resize discards contents and fills.
  im.resize(2, 5, 9);
  EXPECT_EQ(im.width(), 2);
  EXPECT_EQ(im.height(), 5);
  EXPECT_EQ(im.size(), 10u);
  for (int v : im.pixels()) EXPECT_EQ(v, 9);

  // A zero-width image is empty whatever its height.
  const Image<int> thin(0, 5);
  EXPECT_TRUE(thin.empty());
}

TEST(Image, DefaultFillIsValueInitialised) {
  const Image<Rgba8> im(3, 2);
  for (const Rgba8& p : im.pixels()) EXPECT_EQ(p, (Rgba8{0, 0, 0, 0}));
  const Image<double> d(4, 4);
  for (double v : d.pixels()) EXPECT_EQ(v, 0.0);
}

TEST(Image, AtChecksBounds) {
  Image<int> im(4, 3);
  EXPECT_DEATH((void)im.at(4, 0), "CHECK failed");
  EXPECT_DEATH((void)im.at(0, 3), "CHECK failed");
  EXPECT_DEATH((void)im.at(-1, 0), "CHECK failed");
  EXPECT_DEATH((void)im.at(0, -1), "CHECK failed");
  const Image<int>& cim = im;
  EXPECT_DEATH((void)cim.at(4, 2), "CHECK failed");
  EXPECT_DEATH((void)im.view().at(0, 3), "CHECK failed");
  EXPECT_DEATH(im.resize(-1, 2), "CHECK failed");
}

TEST(Image, ViewAddressesTheSamePixels) {
  Image<int> im(5, 4);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 5; ++x) im(x, y) = 10 * y + x;
  const ImageView<int> v = im.view();
  EXPECT_EQ(v.data, im.data());
  EXPECT_EQ(v.width, 5);
  EXPECT_EQ(v.height, 4);
  EXPECT_EQ(v.stride, 5);
  EXPECT_FALSE(v.empty());
  for (int y = 0; y < 4; ++y) {
    EXPECT_EQ(v.row(y), im.data() + 5 * y);
    for (int x = 0; x < 5; ++x) {
      EXPECT_EQ(&v(x, y), &im(x, y));
      EXPECT_EQ(&v.at(x, y), &im(x, y));
    }
  }
  v(2, 3) = -5;  // writes through
  EXPECT_EQ(im(2, 3), -5);
  const ImageView<const int> cv = v;  // implicit const conversion
  EXPECT_EQ(cv.data, v.data);
  EXPECT_EQ(cv.stride, v.stride);
  EXPECT_EQ(cv(2, 3), -5);
  const Image<int>& cim = im;
  const ImageView<const int> cv2 = cim.view();
  EXPECT_EQ(cv2.data, im.data());
  EXPECT_EQ(cv2.stride, 5);
  EXPECT_TRUE(ImageView<int>{}.empty());
}

TEST(Image, SubViewAddressingAndStride) {
  const int w = 9, h = 7;
  Image<int> im(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) im(x, y) = 100 * y + x;
  const ImageView<int> v = im.view();

  // Every sub-rectangle: sub(x, y) is parent(x0 + x, y0 + y), the stride is
  // the parent's, rows step by the parent's width.
  for (int y0 = 0; y0 <= h; ++y0) {
    for (int x0 = 0; x0 <= w; ++x0) {
      for (int sh = 0; y0 + sh <= h; ++sh) {
        for (int sw = 0; x0 + sw <= w; ++sw) {
          const ImageView<int> s = v.sub(x0, y0, sw, sh);
          ASSERT_EQ(s.width, sw);
          ASSERT_EQ(s.height, sh);
          ASSERT_EQ(s.stride, w);
          ASSERT_EQ(s.empty(), sw == 0 || sh == 0);
          for (int y = 0; y < sh; ++y) {
            ASSERT_EQ(s.row(y), &im(x0, y0 + y));
            for (int x = 0; x < sw; ++x) ASSERT_EQ(&s(x, y), &im(x0 + x, y0 + y));
          }
        }
      }
    }
  }

  // Nested sub-views compose offsets; writes land in the parent.
  const ImageView<int> a = v.sub(2, 1, 6, 5);
  const ImageView<int> b = a.sub(1, 2, 3, 2);
  EXPECT_EQ(b.stride, w);
  EXPECT_EQ(&b(0, 0), &im(3, 3));
  EXPECT_EQ(&b(2, 1), &im(5, 4));
  b(2, 1) = -1;
  EXPECT_EQ(im(5, 4), -1);
  EXPECT_EQ(a(3, 3), -1);
  // The whole view is a sub-view of itself.
  const ImageView<int> all = v.sub(0, 0, w, h);
  EXPECT_EQ(all.data, v.data);
  EXPECT_EQ(all.width, w);
  EXPECT_EQ(all.height, h);
  // at() on a sub-view checks the sub-view's bounds, not the parent's.
  EXPECT_EQ(b.at(2, 1), -1);
  EXPECT_DEATH((void)b.at(3, 0), "CHECK failed");
  EXPECT_DEATH((void)b.at(0, 2), "CHECK failed");
}

TEST(Image, SubViewChecksBounds) {
  Image<int> im(6, 4);
  const ImageView<int> v = im.view();
  EXPECT_DEATH((void)v.sub(0, 0, 7, 1), "CHECK failed");
  EXPECT_DEATH((void)v.sub(5, 0, 2, 1), "CHECK failed");
  EXPECT_DEATH((void)v.sub(0, 3, 1, 2), "CHECK failed");
  EXPECT_DEATH((void)v.sub(-1, 0, 1, 1), "CHECK failed");
  EXPECT_DEATH((void)v.sub(0, 0, -1, 1), "CHECK failed");
  EXPECT_DEATH((void)v.sub(1, 1, 2, 2).sub(1, 1, 2, 1), "CHECK failed");
}

// ---------------------------------------------------------------- file I/O

TEST(FileIo, PngRoundTripIsBitIdentical) {
  const std::string dir = freshDir();
  int seed = 1;
  for (auto [w, h] : {std::pair{1, 1}, std::pair{37, 13}, std::pair{13, 37}, std::pair{256, 3}}) {
    Image<Rgba8> im = randomRgba(w, h, static_cast<std::uint32_t>(seed++));
    // Extreme alpha with non-zero colour: must survive (no premultiplication).
    im(0, 0) = Rgba8{255, 128, 7, 0};
    if (w > 1) im(1, 0) = Rgba8{0, 0, 0, 255};
    const std::string path = dir + "/im_" + std::to_string(w) + "x" + std::to_string(h) + ".png";
    ASSERT_TRUE(writePng(path, im).ok()) << writePng(path, im).error().message;
    auto back = readPng(path);
    ASSERT_TRUE(back.ok()) << back.error().message;
    ASSERT_EQ(back->width(), w);
    ASSERT_EQ(back->height(), h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) ASSERT_EQ((*back)(x, y), im(x, y)) << "(" << x << ", " << y << ")";
  }
  // Only the PNGs are left: no temporaries.
  for (const std::string& name : listDir(dir)) EXPECT_EQ(fs::path(name).extension(), ".png") << name;
}

TEST(FileIo, PngGrayMapsRangeToBytes) {
  const std::string dir = freshDir();
  // [lo, hi] → [0, 255], clamped outside; opaque grey.
  Image<float> g(6, 1);
  const float inf = std::numeric_limits<float>::infinity();
  const float vals[] = {2.0f, 4.0f, 3.0f, 1.0f, 10.0f, inf};
  for (int x = 0; x < 6; ++x) g(x, 0) = vals[x];
  const std::string path = dir + "/gray.png";
  ASSERT_TRUE(writePngGray(path, g, 2.0f, 4.0f).ok());
  auto back = readPng(path);
  ASSERT_TRUE(back.ok()) << back.error().message;
  const int expected[] = {0, 255, 128, 0, 255, 255};  // 3 → 127.5, rounded half up
  for (int x = 0; x < 6; ++x) {
    const Rgba8 p = (*back)(x, 0);
    EXPECT_EQ(p.r, expected[x]) << x;
    EXPECT_EQ(p.g, p.r);
    EXPECT_EQ(p.b, p.r);
    EXPECT_EQ(p.a, 255);
  }
  // Monotone in the value over the range.
  Image<float> ramp(256, 1);
  for (int x = 0; x < 256; ++x) ramp(x, 0) = static_cast<float>(x) / 255.0f;
  ASSERT_TRUE(writePngGray(path, ramp, 0.0f, 1.0f).ok());
  auto r = readPng(path);
  ASSERT_TRUE(r.ok());
  for (int x = 0; x < 256; ++x) EXPECT_EQ((*r)(x, 0).r, x);
}

TEST(FileIo, ReadPngErrorsNameTheFile) {
  const std::string dir = freshDir();
  const std::string missing = dir + "/does_not_exist.png";
  const std::string truncated = dir + "/truncated.png";
  const std::string text = dir + "/notes.png";
  const std::string zero = dir + "/zero.png";

  const Image<Rgba8> im = randomRgba(32, 32, 7);
  ASSERT_TRUE(writePng(truncated, im).ok());
  auto full = readFile(truncated);
  ASSERT_TRUE(full.ok());
  ASSERT_GT(full->size(), 64u);
  writeRaw(truncated, full->substr(0, full->size() / 2));
  writeRaw(text, "this is not a PNG file\n");
  writeRaw(zero, "");

  for (const std::string& path : {missing, truncated, text, zero, dir}) {
    auto r = readPng(path);
    ASSERT_FALSE(r.ok()) << path;
    EXPECT_NE(r.error().message.find(path), std::string::npos)
        << "message '" << r.error().message << "' does not name " << path;
  }
  // Every truncation of a valid PNG is an error, never a crash or a success
  // with wrong pixels.
  for (std::size_t len = 0; len < full->size(); len += 7) {
    writeRaw(truncated, full->substr(0, len));
    auto r = readPng(truncated);
    if (r.ok()) {
      // stb may accept a PNG missing only its trailing IEND chunk; then the
      // pixels must all be there.
      ASSERT_GE(len, full->size() - 12) << len;
      for (int i = 0; i < 32 * 32; ++i) ASSERT_EQ(r->data()[i], im.data()[i]);
    } else {
      ASSERT_NE(r.error().message.find(truncated), std::string::npos);
    }
  }
}

// The PNG chunk `type` with `data`: length, type, data, CRC-32 over type and data.
std::string pngChunk(const std::string& type, const std::string& data) {
  auto be32 = [](std::uint32_t v) {
    return std::string{static_cast<char>(v >> 24), static_cast<char>(v >> 16),
                       static_cast<char>(v >> 8), static_cast<char>(v)};
  };
  std::uint32_t crc = 0xffffffffu;
  for (const char c : type + data) {
    crc ^= static_cast<std::uint8_t>(c);
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
  }
  return be32(static_cast<std::uint32_t>(data.size())) + type + data + be32(~crc);
}

// Offset of the first chunk of type `type` in a PNG (chunks start at byte 8).
std::size_t pngChunkOffset(const std::string& png, const std::string& type) {
  std::size_t pos = 8;
  while (pos + 8 <= png.size() && png.compare(pos + 4, 4, type) != 0) {
    const auto* b = reinterpret_cast<const std::uint8_t*>(png.data() + pos);
    pos += 12 + ((std::size_t{b[0]} << 24) | (std::size_t{b[1]} << 16) | (std::size_t{b[2]} << 8) |
                 b[3]);
  }
  return pos;
}

// stb_image would call memcpy(NULL, p, 0) on a PNG whose first IDAT chunk is
// empty (undefined behaviour: the ASan + UBSan build aborts here without the
// fix in core/file_io.cpp). Empty IDATs carry no data, so the image must
// decode to the same pixels wherever they sit, and a PNG with no IDAT data
// at all must be an error that names the file.
TEST(FileIo, EmptyIdatChunksDecodeLikeNone) {
  const std::string dir = freshDir();
  const Image<Rgba8> im = randomRgba(16, 16, 11);
  const std::string path = dir + "/plain.png";
  ASSERT_TRUE(writePng(path, im).ok());
  auto png = readFile(path);
  ASSERT_TRUE(png.ok());
  const std::size_t idat = pngChunkOffset(*png, "IDAT");
  const std::size_t iend = pngChunkOffset(*png, "IEND");
  ASSERT_LT(idat, iend);
  ASSERT_EQ(iend + 12, png->size());
  const std::string empty = pngChunk("IDAT", "");
  ASSERT_EQ(empty.substr(8), std::string("\x35\xaf\x06\x1e", 4));  // CRC-32 of "IDAT"

  const std::string head = png->substr(0, idat), data = png->substr(idat, iend - idat),
                    tail = png->substr(iend);
  const std::pair<const char*, std::string> same[] = {
      {"first", head + empty + data + tail},
      {"first-two", head + empty + empty + data + tail},
      {"around", head + empty + data + empty + tail},
      {"after", head + data + empty + tail},
  };
  for (const auto& [name, bytes] : same) {
    const std::string file = dir + "/" + name + ".png";
    writeRaw(file, bytes);
    auto r = readPng(file);
    ASSERT_TRUE(r.ok()) << name << ": " << r.error().message;
    std::string warning;
    auto t = decodeTexture(bytes.data(), bytes.size(), file, &warning);
    ASSERT_TRUE(t.ok()) << name << ": " << t.error().message;
    EXPECT_EQ(warning, "") << name;
    for (const auto* got : {&*r, &*t}) {
      ASSERT_EQ(got->width(), 16) << name;
      ASSERT_EQ(got->height(), 16) << name;
      for (int i = 0; i < 16 * 16; ++i)
        ASSERT_EQ(got->data()[i], im.data()[i]) << name << " pixel " << i;
    }
  }

  const std::pair<const char*, std::string> broken[] = {
      {"only-empty", head + empty + tail},
      {"empty-crc-cut", head + empty.substr(0, 10)},
      {"empty-no-crc", head + empty.substr(0, 8)},
  };
  for (const auto& [name, bytes] : broken) {
    const std::string file = dir + "/" + name + ".png";
    writeRaw(file, bytes);
    auto r = readPng(file);
    ASSERT_FALSE(r.ok()) << name;
    EXPECT_NE(r.error().message.find(file), std::string::npos) << r.error().message;
    auto t = decodeTexture(bytes.data(), bytes.size(), file, nullptr);
    ASSERT_FALSE(t.ok()) << name;
    EXPECT_NE(t.error().message.find(file), std::string::npos) << t.error().message;
  }

  // Every truncation of the PNG with an empty first IDAT: an error naming
  // the file, or (missing only the IEND chunk) every pixel.
  const std::string first = head + empty + data + tail;
  const std::string cut = dir + "/cut.png";
  for (std::size_t len = 0; len < first.size(); ++len) {
    writeRaw(cut, first.substr(0, len));
    auto r = readPng(cut);
    if (r.ok()) {
      ASSERT_GE(len, first.size() - 12) << len;
      for (int i = 0; i < 16 * 16; ++i) ASSERT_EQ(r->data()[i], im.data()[i]) << len;
    } else {
      ASSERT_NE(r.error().message.find(cut), std::string::npos) << len << ": " << r.error().message;
    }
  }
}

TEST(FileIo, WritePngToMissingDirectoryFailsCleanly) {
  const std::string dir = freshDir();
  const std::string path = dir + "/no/such/dir/out.png";
  const Status s = writePng(path, randomRgba(4, 4, 3));
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find(path), std::string::npos) << s.error().message;
  EXPECT_TRUE(listDir(dir).empty());
  EXPECT_FALSE(fs::exists(dir + "/no"));
}

TEST(FileIo, WritePngEmptyImageIsAnError) {
  const std::string dir = freshDir();
  const std::string path = dir + "/empty.png";
  const Status s = writePng(path, Image<Rgba8>());
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find(path), std::string::npos);
  EXPECT_TRUE(listDir(dir).empty());
}

TEST(FileIo, FailedRenameLeavesNoTemporary) {
  // The target is an existing non-empty directory: the temporary is written
  // beside it, the rename fails, and the temporary must be removed.
  const std::string dir = freshDir();
  const std::string target = dir + "/target";
  fs::create_directories(target + "/child");
  const Status s = writeFileAtomic(target, "payload");
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find(target), std::string::npos) << s.error().message;
  EXPECT_EQ(listDir(dir), std::vector<std::string>{"target"});
  EXPECT_TRUE(fs::is_directory(target + "/child"));
  // Same through writePng.
  ASSERT_FALSE(writePng(target, randomRgba(2, 2, 1)).ok());
  EXPECT_EQ(listDir(dir), std::vector<std::string>{"target"});
}

TEST(FileIo, WriteFileAtomicReplacesExistingFile) {
  const std::string dir = freshDir();
  const std::string path = dir + "/data.bin";
  const std::string oldBytes = "old contents, longer than the new ones";
  ASSERT_TRUE(writeFileAtomic(path, oldBytes).ok());
  auto r0 = readFile(path);
  ASSERT_TRUE(r0.ok());
  EXPECT_EQ(*r0, oldBytes);

  struct stat before {};
  ASSERT_EQ(::stat(path.c_str(), &before), 0);
  // A reader that opened the old file keeps seeing the complete old
  // contents: the new file is a different inode renamed over the name, not
  // the old one truncated and rewritten in place.
  std::ifstream reader(path, std::ios::binary);
  ASSERT_TRUE(reader.good());

  std::string newBytes = "new";
  newBytes.push_back('\0');
  newBytes += "\xff\x01 binary";
  ASSERT_TRUE(writeFileAtomic(path, newBytes).ok());

  std::string seen((std::istreambuf_iterator<char>(reader)), std::istreambuf_iterator<char>());
  EXPECT_EQ(seen, oldBytes);
  struct stat after {};
  ASSERT_EQ(::stat(path.c_str(), &after), 0);
  EXPECT_NE(before.st_ino, after.st_ino);

  auto r1 = readFile(path);
  ASSERT_TRUE(r1.ok());
  EXPECT_EQ(*r1, newBytes);  // exact bytes, embedded NUL included
  EXPECT_EQ(listDir(dir), std::vector<std::string>{"data.bin"});

  // Empty contents are a valid file.
  ASSERT_TRUE(writeFileAtomic(path, "").ok());
  auto r2 = readFile(path);
  ASSERT_TRUE(r2.ok());
  EXPECT_EQ(*r2, "");
}

TEST(FileIo, ReadFileErrorsNameTheFile) {
  const std::string dir = freshDir();
  for (const std::string& path : {dir + "/missing.txt", dir}) {
    auto r = readFile(path);
    ASSERT_FALSE(r.ok()) << path;
    EXPECT_NE(r.error().message.find(path), std::string::npos) << r.error().message;
  }
}

TEST(FileIo, EnsureWritableDirCreatesNestedDirs) {
  const std::string dir = freshDir();
  const std::string nested = dir + "/a/b/c";
  ASSERT_TRUE(ensureWritableDir(nested).ok());
  EXPECT_TRUE(fs::is_directory(nested));
  ASSERT_TRUE(ensureWritableDir(nested).ok());  // idempotent
  ASSERT_TRUE(writeFileAtomic(nested + "/x", "1").ok());
}

TEST(FileIo, EnsureWritableDirRejectsFiles) {
  const std::string dir = freshDir();
  const std::string file = dir + "/plain";
  writeRaw(file, "x");
  for (const std::string& path : {file, file + "/sub", file + "/sub/deeper"}) {
    const Status s = ensureWritableDir(path);
    ASSERT_FALSE(s.ok()) << path;
    EXPECT_NE(s.error().message.find(path), std::string::npos) << s.error().message;
  }
  auto still = readFile(file);
  ASSERT_TRUE(still.ok());
  EXPECT_EQ(*still, "x");  // left untouched
}

TEST(FileIo, EnsureWritableDirRejectsReadOnlyDir) {
  // A directory nobody can create files in, root included (procfs); permission
  // bits alone would not stop root, so ensureWritableDir probes with a file.
  const std::string ro = "/proc/self";
  const Status s = ensureWritableDir(ro);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find(ro), std::string::npos) << s.error().message;
}

// ---------------------------------------------------------------- timer.h

TEST(Percentile, KnownValuesWithInterpolation) {
  // Position p/100·(n−1) in the sorted list, linear between neighbours.
  const std::vector<double> v = {40, 10, 30, 20, 50};  // unsorted on purpose
  EXPECT_EQ(percentile(v, 0), 10);
  EXPECT_EQ(percentile(v, 25), 20);
  EXPECT_EQ(percentile(v, 50), 30);
  EXPECT_EQ(percentile(v, 100), 50);
  EXPECT_DOUBLE_EQ(percentile(v, 10), 14);  // pos 0.4 → 10 + 0.4·10
  EXPECT_DOUBLE_EQ(percentile(v, 95), 48);  // pos 3.8 → 40 + 0.8·10
  EXPECT_EQ(median(v), 30);
  EXPECT_DOUBLE_EQ(median({1, 2, 3, 4}), 2.5);
  EXPECT_DOUBLE_EQ(percentile({0, 10}, 10), 1.0);
  EXPECT_EQ(median({7}), 7);
  EXPECT_EQ(percentile({7}, 0), 7);
  EXPECT_EQ(percentile({7}, 100), 7);
  EXPECT_EQ(median({3, 3, 3}), 3);
}

TEST(Percentile, NansIgnoredAndEmptyIsNan) {
  const double nan = std::nan("");
  EXPECT_DOUBLE_EQ(median({nan, 1, nan, 3}), 2.0);
  EXPECT_EQ(percentile({nan, 5, nan}, 90), 5);
  EXPECT_TRUE(std::isnan(median({})));
  EXPECT_TRUE(std::isnan(percentile({}, 95)));
  EXPECT_TRUE(std::isnan(median({nan, nan})));
}

TEST(Percentile, InfinitiesAreValues) {
  const double inf = std::numeric_limits<double>::infinity();
  // Infinities are values (PSNR of identical images is +inf): the maximum of
  // {1, 2, inf} is inf and its median is 2. An interpolation weight of 0
  // must not turn 0·(inf − x) into NaN.
  EXPECT_EQ(percentile({1, inf, 2}, 100), inf);
  EXPECT_EQ(median({1, inf, 2}), 2);
  EXPECT_EQ(percentile({-inf, 1, 2}, 0), -inf);
  EXPECT_EQ(percentile({1, 2, inf}, 75), inf);  // between 2 and inf: inf
}

TEST(Percentile, MonotoneAndBounded) {
  std::mt19937 rng(21);
  std::normal_distribution<double> g(0.0, 100.0);
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<double> v(1 + trial * 3);
    for (double& x : v) x = g(rng);
    const double lo = *std::min_element(v.begin(), v.end());
    const double hi = *std::max_element(v.begin(), v.end());
    EXPECT_EQ(percentile(v, 0), lo);
    EXPECT_EQ(percentile(v, 100), hi);
    double prev = lo;
    for (double p = 0; p <= 100; p += 2.5) {
      const double q = percentile(v, p);
      EXPECT_GE(q, prev);
      EXPECT_LE(q, hi);
      prev = q;
    }
    // Order of the input does not matter.
    std::vector<double> shuffled = v;
    std::shuffle(shuffled.begin(), shuffled.end(), rng);
    EXPECT_EQ(median(shuffled), median(v));
  }
}

}  // namespace
}  // namespace hw
