// Guards at the file-system boundary (core/safe_io.h, core/json_guard.h):
// special files are neither read nor replaced, size limits hold before a
// byte is read, temporaries are removed, JSON nesting and duplicate keys are
// errors that name the place.
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/file_io.h"
#include "core/json_guard.h"
#include "core/output_dir.h"
#include "core/safe_io.h"

namespace hw {
namespace {

std::string tempDir() {
  const auto d = std::filesystem::temp_directory_path() /
                 ("hw_safe_io_test_" + std::to_string(::getpid()) + "_" +
                  ::testing::UnitTest::GetInstance()->current_test_info()->name());
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d.string();
}

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

TEST(SafeIo, FifoIsRefusedAsInputWithoutBlocking) {
  const std::string dir = tempDir();
  const std::string fifo = dir + "/in.json";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  auto r = readFile(fifo);  // would block forever if the FIFO were opened for a plain read
  ASSERT_FALSE(r.ok());
  EXPECT_TRUE(contains(r.error().message, "FIFO")) << r.error().message;
  EXPECT_TRUE(contains(r.error().message, fifo)) << r.error().message;
}

TEST(SafeIo, DevicesAreRefusedAsInput) {
  for (const char* dev : {"/dev/zero", "/dev/null", "/dev/urandom"}) {
    auto r = readFile(dev);
    ASSERT_FALSE(r.ok()) << dev;
    EXPECT_TRUE(contains(r.error().message, "character device")) << r.error().message;
  }
}

TEST(SafeIo, SizeLimitIsCheckedBeforeReading) {
  const std::string dir = tempDir();
  const std::string f = dir + "/big.bin";
  std::ofstream(f) << std::string(1000, 'x');
  EXPECT_TRUE(readRegularFile(f, 1000).ok());
  auto r = readRegularFile(f, 999);
  ASSERT_FALSE(r.ok());
  EXPECT_TRUE(contains(r.error().message, "1000 bytes")) << r.error().message;
  EXPECT_TRUE(contains(r.error().message, "999 bytes")) << r.error().message;
}

TEST(SafeIo, OutputOverFifoOrSocketIsRefusedAndNothingIsWritten) {
  const std::string dir = tempDir();
  const std::string fifo = dir + "/out.png";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  auto st = writeFileAtomic(fifo, "data");
  ASSERT_FALSE(st.ok());
  EXPECT_TRUE(contains(st.error().message, "FIFO")) << st.error().message;
  struct stat s {};
  ASSERT_EQ(::stat(fifo.c_str(), &s), 0);
  EXPECT_TRUE(S_ISFIFO(s.st_mode));  // still the FIFO, not replaced by a file
  // A symlink to a device counts as the device.
  const std::string link = dir + "/null.png";
  std::filesystem::create_symlink("/dev/null", link);
  EXPECT_FALSE(writeFileAtomic(link, "data").ok());
  EXPECT_TRUE(std::filesystem::is_symlink(link));
  // A socket.
  const std::string sock = dir + "/s.png";
  const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
  ASSERT_GE(fd, 0);
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  std::snprintf(addr.sun_path, sizeof addr.sun_path, "%s", sock.c_str());
  if (sock.size() < sizeof addr.sun_path &&
      ::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0) {
    auto s2 = writeFileAtomic(sock, "data");
    ASSERT_FALSE(s2.ok());
    EXPECT_TRUE(contains(s2.error().message, "socket")) << s2.error().message;
  }
  ::close(fd);
  // Regular files and new paths are fine; no temporary is left behind.
  EXPECT_TRUE(writeFileAtomic(dir + "/new.txt", "x").ok());
  EXPECT_TRUE(writeFileAtomic(dir + "/new.txt", "y").ok());
  int entries = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    EXPECT_EQ(e.path().string().find(".tmp-"), std::string::npos) << e.path();
    ++entries;
  }
  EXPECT_EQ(entries, 4);  // out.png, null.png, s.png (or not), new.txt
  EXPECT_FALSE(ensureWritableDir(fifo).ok());
  EXPECT_FALSE(ensureWritableDir("").ok());
  EXPECT_FALSE(writeFileAtomic("", "x").ok());
}

// A process killed by SIGKILL leaves NAME.tmp-PID behind; the next run that
// claims the folder removes the temporaries of the PID its marker recorded
// (in the folder and its direct subfolders), and nothing else; a plain write
// removes nothing.
TEST(SafeIo, TemporariesOfTheRecordedRunAreRemovedAndNothingElse) {
  const std::string dir = tempDir();
  const std::string dead = "999999", other = "999998";
  auto touch = [&](const std::string& name) { std::ofstream(dir + "/" + name) << "x"; };
  const std::vector<std::string> stale = {"report.json.tmp-" + dead, ".report-frames.tmp-" + dead,
                                          "a.png.tmp-1.tmp-" + dead, "frames/f.png.tmp-" + dead};
  const std::vector<std::string> kept = {"other.json.tmp-" + other,  // another run's
                                         "thesis.tmp-" + other,
                                         "notes.tmp-" + dead + ".txt", "notes.tmp-" + dead + "x",
                                         "x.tmp-" + dead + "0", "plain.txt",
                                         "frames/deeper/f.png.tmp-" + dead};  // two levels down
  std::filesystem::create_directories(dir + "/frames/deeper");
  for (const auto& n : stale) touch(n);
  for (const auto& n : kept) touch(n);
  std::filesystem::create_symlink(dir + "/plain.txt", dir + "/link.tmp-" + dead);  // kept
  ASSERT_TRUE(writeFileAtomic(dir + "/report.json", "{}").ok());
  for (const auto& n : stale) EXPECT_TRUE(std::filesystem::exists(dir + "/" + n)) << n;
  EXPECT_EQ(removeTemporariesOfRun(dir, 999999), static_cast<int>(stale.size()));
  for (const auto& n : stale) EXPECT_FALSE(std::filesystem::exists(dir + "/" + n)) << n;
  for (const auto& n : kept) EXPECT_TRUE(std::filesystem::exists(dir + "/" + n)) << n;
  EXPECT_TRUE(std::filesystem::is_symlink(dir + "/link.tmp-" + dead));
  EXPECT_TRUE(std::filesystem::exists(dir + "/report.json"));
  EXPECT_EQ(removeTemporariesOfRun(dir, 0), 0);
}

TEST(SafeIo, TemporaryFileIsRemovedUnlessReleasedAndRegisteredMeanwhile) {
  const std::string dir = tempDir();
  const std::string a = dir + "/a.tmp", b = dir + "/b.tmp";
  {
    TemporaryFile ta(a);
    std::ofstream(a) << "x";
    TemporaryFile tb(b);
    std::ofstream(b) << "y";
    tb.release();
  }
  EXPECT_FALSE(std::filesystem::exists(a));
  EXPECT_TRUE(std::filesystem::exists(b));
  // What the signal handler does: removes every registered file.
  const std::string c = dir + "/c.tmp";
  TemporaryFile tc(c);
  std::ofstream(c) << "z";
  EXPECT_EQ(removeRegisteredTemporaries(), 1);
  EXPECT_FALSE(std::filesystem::exists(c));
}

TEST(SafeIo, ScratchFileLeavesNoNameWhereTheFileSystemAllows) {
  const std::string dir = tempDir();
  std::string named;
  std::FILE* f = openScratchFile(dir, "scratch.tmp", &named);
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(std::fputs("hello", f) >= 0, true);
  int entries = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++entries;
  EXPECT_EQ(entries, named.empty() ? 0 : 1);
  std::fclose(f);
  if (!named.empty()) std::remove(named.c_str());
}

TEST(JsonGuard, NestingIsCountedOutsideStringsOnly) {
  EXPECT_TRUE(checkJsonNesting("[[[]]]", "x", 3).ok());
  auto deep = checkJsonNesting("[[[[]]]]", "x.json", 3);
  ASSERT_FALSE(deep.ok());
  EXPECT_TRUE(contains(deep.error().message, "x.json")) << deep.error().message;
  EXPECT_TRUE(contains(deep.error().message, "at byte 4")) << deep.error().message;
  // Brackets inside strings, escaped quotes included, do not count.
  EXPECT_TRUE(checkJsonNesting(R"({"a": "[[[[[[\"[[[[", "b": [1]})", "x", 2).ok());
  // Depth returns after closing: many siblings are fine.
  std::string wide = "[";
  for (int i = 0; i < 1000; ++i) wide += "[[]],";
  wide += "[]]";
  EXPECT_TRUE(checkJsonNesting(wide, "x", 3).ok());
}

TEST(JsonGuard, DuplicateKeysAreNamedByTheirPath) {
  auto ok = parseJsonStrict(R"({"a": 1, "b": [{"c": 1}, {"c": 2}]})", "f.json");
  ASSERT_TRUE(ok.ok()) << ok.error().message;
  EXPECT_EQ((*ok)["b"][1]["c"], 2);
  auto top = parseJsonStrict(R"({"a": 1, "a": 2})", "f.json");
  ASSERT_FALSE(top.ok());
  EXPECT_TRUE(contains(top.error().message, "f.json: a: duplicate key")) << top.error().message;
  auto nested = parseJsonStrict(R"({"k": [{"x": 1}, {"e": 1, "e": 2}]})", "f.json");
  ASSERT_FALSE(nested.ok());
  EXPECT_TRUE(contains(nested.error().message, "k[1].e: duplicate key"))
      << nested.error().message;
  // The empty key is a key like any other (a repeated one was once missed:
  // its path was the empty string that meant "no duplicate").
  auto emptyTop = parseJsonStrict(R"({"": 1,"":0e2})", "f.json");
  ASSERT_FALSE(emptyTop.ok());
  EXPECT_TRUE(contains(emptyTop.error().message, R"(f.json: "": duplicate key)"))
      << emptyTop.error().message;
  auto emptyNested = parseJsonStrict(R"({"k": [{"": 1, "": 2}]})", "f.json");
  ASSERT_FALSE(emptyNested.ok());
  EXPECT_TRUE(contains(emptyNested.error().message, R"(k[0]."": duplicate key)"))
      << emptyNested.error().message;
  auto emptyOnce = parseJsonStrict(R"({"": 1, "a": {"": 2}})", "f.json");
  ASSERT_TRUE(emptyOnce.ok()) << emptyOnce.error().message;
  EXPECT_EQ((*emptyOnce)["a"][""], 2);
  auto bad = parseJsonStrict("{\"a\": ", "f.json");
  ASSERT_FALSE(bad.ok());
  EXPECT_TRUE(contains(bad.error().message, "invalid JSON at byte")) << bad.error().message;
  auto deep = parseJsonStrict(std::string(100, '[') + std::string(100, ']'), "f.json");
  ASSERT_FALSE(deep.ok());
  EXPECT_TRUE(contains(deep.error().message, "nested deeper than 64")) << deep.error().message;
}

// An uncompressed-size bomb: a TGA header declaring W×H pixels and one RLE
// packet. stb reads the header alone for the size check.
std::string rleTga(int w, int h) {
  std::string t(18, '\0');
  t[2] = 10;  // run-length encoded true-colour
  t[12] = static_cast<char>(w & 0xFF);
  t[13] = static_cast<char>(w >> 8);
  t[14] = static_cast<char>(h & 0xFF);
  t[15] = static_cast<char>(h >> 8);
  t[16] = 32;
  for (int i = 0; i < 64; ++i) t += std::string("\xFF\x10\x20\x30\xFF", 5);  // 128-pixel runs
  return t;
}

TEST(DecodeTexture, SizeBombIsRefusedBeforeDecoding) {
  const std::string tga = rleTga(16384, 16384);
  std::string warning;
  auto img = decodeTexture(tga.data(), tga.size(), "bomb.tga", &warning);
  ASSERT_FALSE(img.ok());
  EXPECT_TRUE(contains(img.error().message, "16384x16384")) << img.error().message;
  EXPECT_TRUE(contains(img.error().message, "decode budget")) << img.error().message;
}

TEST(DecodeTexture, LargeSideIsDownscaledWithAWarning) {
  setMaxTextureSize(64);
  const std::string tga = rleTga(256, 32);  // 8192 pixels in 64 runs of 128
  std::string warning;
  auto img = decodeTexture(tga.data(), tga.size(), "wide.tga", &warning);
  setMaxTextureSize(8192);
  ASSERT_TRUE(img.ok()) << img.error().message;
  EXPECT_EQ(img->width(), 64);
  EXPECT_EQ(img->height(), 8);
  EXPECT_TRUE(contains(warning, "256x32 downscaled to 64x8")) << warning;
  // The box filter of a constant image is that constant (TGA stores BGRA).
  for (const Rgba8& p : img->pixels()) {
    EXPECT_EQ(p.r, 0x30);
    EXPECT_EQ(p.g, 0x20);
    EXPECT_EQ(p.b, 0x10);
  }
  std::string none;
  auto small = decodeTexture(tga.data(), tga.size(), "wide.tga", &none);
  ASSERT_TRUE(small.ok());
  EXPECT_EQ(small->width(), 256);
  EXPECT_TRUE(none.empty());
}

}  // namespace
}  // namespace hw
