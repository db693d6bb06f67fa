// Output folders (core/output_dir.h, docs/output-folders.md): claimed with a
// marker, locked for the run against other processes, foreign folders and
// symlinks refused unless forced, summaries removed unless committed.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "core/output_dir.h"

namespace hw {
namespace {

namespace fs = std::filesystem;

std::string tempDir() {
  const auto d =
      fs::temp_directory_path() / ("hw_output_dir_test_" + std::to_string(::getpid()) + "_" +
                                   ::testing::UnitTest::GetInstance()->current_test_info()->name());
  fs::remove_all(d);
  fs::create_directories(d);
  return d.string();
}

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

TEST(OutputDir, NewFolderIsClaimedAndNamesItsCommand) {
  const std::string dir = tempDir() + "/new";
  auto out = OutputDir::open(dir, "walk", false);
  ASSERT_TRUE(out.ok()) << out.error().message;
  const OutputDirOwner o = readOutputDirOwner(dir);
  EXPECT_TRUE(o.readable);
  EXPECT_EQ(o.command, "walk");
  EXPECT_EQ(o.pid, static_cast<long>(::getpid()));
  EXPECT_EQ(o.started.size(), 20u) << o.started;  // 2026-01-02T03:04:05Z
  EXPECT_EQ((*out)->previousOwner().readable, false);
}

TEST(OutputDir, FailedRunIntoANewFolderLeavesNothing) {
  const std::string dir = tempDir() + "/new";
  {
    auto out = OutputDir::open(dir, "walk", false);
    ASSERT_TRUE(out.ok());
  }
  EXPECT_FALSE(fs::exists(dir));
  const std::string empty = tempDir() + "/empty";
  fs::create_directory(empty);
  {
    auto out = OutputDir::open(empty, "walk", false);
    ASSERT_TRUE(out.ok());
  }
  EXPECT_TRUE(fs::is_directory(empty));  // not ours to remove
  EXPECT_TRUE(fs::is_empty(empty));
}

TEST(OutputDir, ForeignFolderOtherCommandAndSymlinkAreRefusedUnlessForced) {
  const std::string root = tempDir();
  const std::string foreign = root + "/foreign";
  fs::create_directory(foreign);
  std::ofstream(foreign + "/thesis.tmp-999999") << "data";
  auto a = OutputDir::open(foreign, "walk", false);
  ASSERT_FALSE(a.ok());
  EXPECT_TRUE(contains(a.error().message, "not empty and was not made by hybridwalk"))
      << a.error().message;
  EXPECT_FALSE(fs::exists(foreign + "/" + kOwnerMarkerName));
  {
    auto forced = OutputDir::open(foreign, "walk", true);
    ASSERT_TRUE(forced.ok()) << forced.error().message;
    (*forced)->commit();
  }
  EXPECT_EQ(slurp(foreign + "/thesis.tmp-999999"), "data");  // never removed

  auto other = OutputDir::open(foreign, "render", false);
  ASSERT_FALSE(other.ok());
  EXPECT_TRUE(contains(other.error().message, "belongs to 'hybridwalk walk'"))
      << other.error().message;
  EXPECT_TRUE(contains(other.error().message, "render outputs")) << other.error().message;

  fs::create_symlink(foreign, root + "/link");
  auto link = OutputDir::open(root + "/link", "walk", false);
  ASSERT_FALSE(link.ok());
  EXPECT_TRUE(contains(link.error().message, "is a symbolic link (to " + foreign + ")"))
      << link.error().message;
  EXPECT_TRUE(OutputDir::open(root + "/link", "walk", true).ok());
}

// The lock is held against other processes for as long as the OutputDir lives,
// and released when it goes (or the process dies).
TEST(OutputDir, SecondProcessIsRefusedWhileTheFirstHoldsTheFolder) {
  const std::string dir = tempDir() + "/w";
  auto out = OutputDir::open(dir, "walk", false);
  ASSERT_TRUE(out.ok());
  int pipefd[2];
  ASSERT_EQ(::pipe(pipefd), 0);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    ::close(pipefd[0]);
    auto second = OutputDir::open(dir, "walk", true);
    const std::string msg = second.ok() ? "claimed" : second.error().message;
    (void)!::write(pipefd[1], msg.data(), msg.size());
    ::_exit(0);
  }
  ::close(pipefd[1]);
  std::string msg;
  char buf[512];
  for (ssize_t n; (n = ::read(pipefd[0], buf, sizeof buf)) > 0;) msg.append(buf, n);
  ::close(pipefd[0]);
  int status = 0;
  ::waitpid(child, &status, 0);
  EXPECT_TRUE(
      contains(msg, dir + " is in use by PID " + std::to_string(::getpid()) + " (walk, started "))
      << msg;
  out = makeError("released");  // the first run ends
  auto third = OutputDir::open(dir, "walk", false);
  EXPECT_TRUE(third.ok()) << third.error().message;
}

TEST(OutputDir, SummariesStayOnlyWhenCommittedAndTheMarkerIsPutBackOtherwise) {
  const std::string dir = tempDir() + "/w";
  {
    auto out = OutputDir::open(dir, "walk", false);
    ASSERT_TRUE(out.ok());
    (*out)->provisional("report.json");
    std::ofstream(dir + "/report.json") << "{}";
    std::ofstream(dir + "/frame_times.png") << "png";
    (*out)->commit();
  }
  EXPECT_TRUE(fs::exists(dir + "/report.json"));
  const std::string marker = slurp(dir + "/" + kOwnerMarkerName);
  {
    auto out = OutputDir::open(dir, "walk", false);
    ASSERT_TRUE(out.ok());
    (*out)->provisional("report.json");
    EXPECT_FALSE(fs::exists(dir + "/report.json"));  // the earlier run's: gone at the start
    std::ofstream(dir + "/report.json") << "{}";
    // fails: no commit
  }
  EXPECT_FALSE(fs::exists(dir + "/report.json"));
  EXPECT_TRUE(fs::exists(dir + "/frame_times.png"));
  EXPECT_EQ(slurp(dir + "/" + kOwnerMarkerName), marker);
  {
    auto out = OutputDir::open(dir, "walk", false);
    ASSERT_TRUE(out.ok());
    ASSERT_EQ(OutputDir::held(dir), out->get());
    (*out)->commit();
    (*out)->leaveAsFound();
  }
  EXPECT_EQ(OutputDir::held(dir), nullptr);
  EXPECT_EQ(slurp(dir + "/" + kOwnerMarkerName), marker);
}

TEST(OutputDir, AnUnreadableMarkerIsNotTakenOverUnlessForced) {
  const std::string dir = tempDir() + "/w";
  fs::create_directory(dir);
  std::ofstream(dir + "/" + kOwnerMarkerName) << "not json";
  auto out = OutputDir::open(dir, "walk", false);
  ASSERT_FALSE(out.ok());
  EXPECT_TRUE(contains(out.error().message, "not a hybridwalk marker")) << out.error().message;
  EXPECT_TRUE(OutputDir::open(dir, "walk", true).ok());
}

}  // namespace
}  // namespace hw
