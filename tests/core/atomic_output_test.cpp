// AtomicOutput (core/atomic_output.h): unique temporaries created beside the target, the target
// replaced whole, the registry of live temporaries that runTool's signal handler empties, and
// several processes writing one target at once.
#include "core/atomic_output.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>

#include "child_process.h"
#include "core/error.h"
#include "core/tool.h"
#include "support/tool_test.h"

namespace fs = std::filesystem;

namespace sss {
namespace {

using test::ScratchDir;

using test::readFile;

void writeFile(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

TEST(AtomicOutput, TemporariesAreUniqueCreatedBesideTheTargetAndRemovedUncommitted) {
  const ScratchDir dir;
  const std::string target = dir.path("out.ply");
  {
    const AtomicOutput a(target), b(target);
    EXPECT_NE(a.tempPath(), b.tempPath());
    for (const AtomicOutput* o : {&a, &b}) {
      const fs::path temp(o->tempPath());
      EXPECT_EQ(temp.parent_path(), fs::path(target).parent_path());
      const std::string name = temp.filename().string();
      const std::string prefix = ".out." + std::to_string(::getpid()) + ".";
      EXPECT_EQ(name.rfind(prefix, 0), 0u) << name;
      EXPECT_EQ(name.substr(name.size() - 8), ".tmp.ply") << name;  // the writer's format
      EXPECT_TRUE(fs::is_regular_file(temp)) << "reserved at construction (O_EXCL)";
      EXPECT_EQ(fs::file_size(temp), 0u);
    }
    EXPECT_EQ(dir.fileCount(), 2u);
  }
  EXPECT_EQ(dir.fileCount(), 0u) << "uncommitted temporaries are removed";
}

TEST(AtomicOutput, CommitReplacesTheTargetWhole) {
  const ScratchDir dir;
  const std::string target = dir.path("report.json");
  writeFile(target, "old");
  AtomicOutput out(target);
  writeFile(out.tempPath(), "new contents");
  EXPECT_EQ(readFile(target), "old") << "the target is untouched until the commit";
  out.commit();
  EXPECT_EQ(readFile(target), "new contents");
  EXPECT_EQ(dir.fileNames(), std::vector<std::string>{"report.json"});
}

TEST(AtomicOutput, AMissingFolderFailsAtConstructionNamingTheTarget) {
  const ScratchDir dir;
  const std::string target = dir.path("no/such/out.exr");
  try {
    const AtomicOutput out(target);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), target + ": cannot write (No such file or directory)");
  }
  EXPECT_EQ(dir.fileCount(), 0u);
}

// A killed process (SIGKILL) leaves its temporary behind, under its pid, which a later process
// may get again: the later run writes its own temporary and leaves the stale one alone.
TEST(AtomicOutput, StaleTemporariesOfTheSamePidAreNeitherReadNorTouched) {
  const ScratchDir dir;
  const std::string target = dir.path("out.ply");
  const std::string pid = std::to_string(::getpid());
  const std::vector<std::string> stale{".out." + pid + ".tmp.ply",  // without the random part
                                       ".out." + pid + ".00000000.tmp.ply"};
  for (const std::string& name : stale) writeFile(dir.path(name), "partial " + name);
  writeFileAtomically(target, "whole");
  EXPECT_EQ(readFile(target), "whole");
  for (const std::string& name : stale) EXPECT_EQ(readFile(dir.path(name)), "partial " + name);
  EXPECT_EQ(dir.fileCount(), 3u);
}

TEST(AtomicOutput, RemoveLiveTemporariesUnlinksExactlyTheUncommittedOnes) {
  const ScratchDir dir;
  AtomicOutput done(dir.path("done.txt"));
  writeFile(done.tempPath(), "done");
  done.commit();
  const AtomicOutput a(dir.path("a.exr")), b(dir.path("b.ply"));
  EXPECT_EQ(removeLiveTemporaries(), 2);
  EXPECT_FALSE(fs::exists(a.tempPath()));
  EXPECT_FALSE(fs::exists(b.tempPath()));
  EXPECT_EQ(readFile(dir.path("done.txt")), "done") << "a committed output stays";
}

// A child process runs a tool body (runTool installs the handlers) that writes half an output
// and waits; the parent signals it once the temporary holds data.
int interruptWhileWriting(const ScratchDir& dir, int sig, std::string* temp, std::string* message) {
  int toParent[2], errors[2];
  if (::pipe(toParent) != 0 || ::pipe(errors) != 0) return -1;
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::dup2(errors[1], STDERR_FILENO);
    for (int s : {SIGINT, SIGTERM, SIGHUP}) std::signal(s, SIG_DFL);  // whatever ctest set
    const int status = runTool("sss-test", [&] {
      AtomicOutput out(dir.path("out.exr"));
      writeFile(out.tempPath(), "half an image");
      const std::string line = out.tempPath() + "\n";
      if (::write(toParent[1], line.data(), line.size()) < 0) return 3;
      for (;;) ::pause();
      return 0;
    });
    ::_exit(status);
  }
  ::close(toParent[1]);
  ::close(errors[1]);
  char buffer[4096];
  const ssize_t n = ::read(toParent[0], buffer, sizeof buffer);
  if (n > 0) {
    temp->assign(buffer, static_cast<std::size_t>(n) - 1);
    EXPECT_EQ(readFile(*temp), "half an image");
  }
  ::kill(pid, sig);
  int status = 0;
  ::waitpid(pid, &status, 0);
  const ssize_t m = ::read(errors[0], buffer, sizeof buffer);
  if (m > 0) message->assign(buffer, static_cast<std::size_t>(m));
  ::close(toParent[0]);
  ::close(errors[0]);
  return status;
}

TEST(AtomicOutput, SigintAndSigtermRemoveTheTemporaryAndExit130And143) {
  for (const auto& [sig, code, name] :
       {std::tuple{SIGINT, 130, "SIGINT"}, std::tuple{SIGTERM, 143, "SIGTERM"},
        std::tuple{SIGHUP, 129, "SIGHUP"}}) {
    const ScratchDir dir;
    std::string temp, message;
    const int status = interruptWhileWriting(dir, sig, &temp, &message);
    ASSERT_FALSE(temp.empty());
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == code)
        << name << ": " << test::describeStatus(status);
    EXPECT_EQ(message, std::string("sss-test: error: interrupted by ") + name +
                           " (unfinished output files removed)\n");
    EXPECT_FALSE(fs::exists(temp));
    EXPECT_EQ(dir.fileCount(), 0u) << name << ": no output, no temporary";
  }
}

TEST(AtomicOutput, SigkillLeavesOnlyTheTemporaryAndALaterWriteSucceeds) {
  const ScratchDir dir;
  std::string temp, message;
  const int status = interruptWhileWriting(dir, SIGKILL, &temp, &message);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) << test::describeStatus(status);
  EXPECT_EQ(dir.fileNames(), std::vector<std::string>{fs::path(temp).filename().string()});
  writeFileAtomically(dir.path("out.exr"), "a whole image");
  EXPECT_EQ(readFile(dir.path("out.exr")), "a whole image");
  EXPECT_EQ(readFile(temp), "half an image") << "the stale temporary is not reused";
}

// Four processes replace one target 40 times each with 256 KiB of their own byte while the
// parent reads it: every read is whole and one writer's, and no temporary is left.
TEST(AtomicOutput, ConcurrentWritersOfOneTargetAlwaysLeaveAWholeFile) {
  const ScratchDir dir;
  const std::string target = dir.path("out.bin");
  constexpr std::size_t kBytes = 256 * 1024;
  constexpr int kWriters = 4, kRounds = 40;
  std::vector<pid_t> writers;
  for (int w = 0; w < kWriters; ++w) {
    const pid_t pid = ::fork();
    if (pid == 0) {
      int status = 0;
      try {
        for (int round = 0; round < kRounds; ++round) {
          writeFileAtomically(target, std::string(kBytes, static_cast<char>('a' + w)));
        }
      } catch (const std::exception&) {
        status = 1;
      }
      ::_exit(status);
    }
    writers.push_back(pid);
  }
  std::vector<int> statuses(kWriters, -1);  // -1: still running
  int reads = 0, broken = 0;
  auto running = [&] {
    bool any = false;
    for (int w = 0; w < kWriters; ++w) {
      if (statuses[w] == -1 && ::waitpid(writers[w], &statuses[w], WNOHANG) == 0) {
        statuses[w] = -1;
        any = true;
      }
    }
    return any;
  };
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (running() && std::chrono::steady_clock::now() < end) {
    const std::string text = readFile(target);
    if (text.empty()) continue;  // before the first commit
    ++reads;
    broken += text.size() != kBytes || text.find_first_not_of(text[0]) != std::string::npos;
  }
  for (int w = 0; w < kWriters; ++w) {
    if (statuses[w] == -1) ::waitpid(writers[w], &statuses[w], 0);
    EXPECT_TRUE(WIFEXITED(statuses[w]) && WEXITSTATUS(statuses[w]) == 0)
        << test::describeStatus(statuses[w]);
  }
  EXPECT_GT(reads, 0);
  EXPECT_EQ(broken, 0) << "of " << reads << " reads";
  const std::string last = readFile(target);
  EXPECT_EQ(last.size(), kBytes);
  EXPECT_EQ(dir.fileNames(), std::vector<std::string>{"out.bin"});
}

}  // namespace
}  // namespace sss
