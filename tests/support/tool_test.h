// Helpers for tests that write files or run the tools: a fresh scratch directory per test, and a
// tool run that returns the exit code and what the tool printed.
#pragma once

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

namespace sss::test {

// A whole file's bytes ("" when it cannot be read).
inline std::string readFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Names of everything in `dir`, sorted (none when it does not exist): a batch's outputs, and no
// temporary file among them.
inline std::vector<std::string> fileNamesIn(const std::string& dir) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec))
    names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

// A fresh directory per test under the system temp directory, removed afterwards. The process id
// and the test's name keep parallel test processes apart.
class ScratchDir {
 public:
  ScratchDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = "sss-test-" + std::to_string(::getpid()) + "-" + info->test_suite_name() +
                       "-" + info->name();
    std::replace(name.begin(), name.end(), '/', '_');  // parameterized tests: Suite/Name/0
    dir_ = std::filesystem::temp_directory_path() / name;
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  ~ScratchDir() { remove(); }
  // The directory and all in it, now: for a death test's child, whose std::exit skips the
  // destructor.
  void remove() const {
    std::error_code ignored;
    std::filesystem::remove_all(dir_, ignored);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;

  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  // Names of everything in the directory, sorted: what a failed run must leave unchanged.
  std::vector<std::string> fileNames() const { return fileNamesIn(dir_.string()); }
  std::size_t fileCount() const { return fileNames().size(); }
  // Each file's name and bytes ("<directory>" for a folder): what a refused run must leave as
  // it was.
  std::vector<std::pair<std::string, std::string>> contents() const {
    std::vector<std::pair<std::string, std::string>> files;
    for (const std::string& name : fileNames()) {
      files.emplace_back(
          name, std::filesystem::is_directory(dir_ / name) ? "<directory>" : readFile(dir_ / name));
    }
    return files;
  }
  void makeDir(const std::string& name) const { std::filesystem::create_directories(dir_ / name); }

 private:
  std::filesystem::path dir_;
};

struct ToolRun {
  int exitCode = -1;   // -1 when the tool did not exit normally
  std::string output;  // the captured streams
};

enum class Capture {
  Stderr,           // stdout goes to the test's stderr, out of the way of exact message checks
  StdoutAndStderr,  // both, interleaved
};

// Runs a shell command line as is; its stdout is captured.
inline ToolRun runShell(const std::string& command) {
  ToolRun result;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return result;
  char buffer[4096];
  for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;)
    result.output.append(buffer, n);
  const int status = ::pclose(pipe);
  result.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

inline void writeText(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

// Runs SSS_BINARY_DIR/tools/<tool> with `args` (shell words); `environment` (VAR=value ...) is
// set for the tool only.
inline ToolRun runTool(const std::string& tool, const std::string& args, Capture capture,
                       const std::string& environment = "") {
  const std::string redirect = capture == Capture::Stderr ? " 3>&2 2>&1 1>&3 3>&-" : " 2>&1";
  return runShell(environment + " " + std::string(SSS_BINARY_DIR) + "/tools/" + tool + " " + args +
                  redirect);
}

}  // namespace sss::test
