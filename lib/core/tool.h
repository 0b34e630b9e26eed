// What every command-line tool shares: how it runs, its one-line errors and its exit statuses.
//
//   int main(int argc, char** argv) {
//     CLI::App app{"..."};
//     Arguments a;
//     app.add_option(...);                       // see core/cli.h for the shared options
//     return sss::runTool("sss-x", app, argc, argv, [&] { return run(a); });
//   }
//
// Exit statuses (the same for every tool):
//   0  success, and --help or --version (on stdout)
//   1  bad input or a failed operation: sss::Error or any other exception from the tool's body
//      (an unreadable or invalid file, a missing output folder, no OpenGL, ...)
//   2  usage: the command line is wrong whatever the files hold. CLI11's parse errors (an unknown
//      option, a value that does not convert or fails its ->check, a missing required option,
//      options that exclude or need each other) and UsageError from the body (combinations CLI11
//      cannot express, e.g. "nothing to write")
//   130, 143, 129  interrupted by SIGINT (Ctrl-C), SIGTERM or SIGHUP (128 + the signal) while the
//      body ran: the outputs being written are removed (their temporary files, core/
//      atomic_output.h; finished outputs stay) and "<tool>: error: interrupted by SIGINT ..." is
//      printed. A signal the parent ignores stays ignored. After SIGKILL, only a temporary
//      ".<name>.<pid>.<random>.tmp.<ext>" can remain, never a partial file under the output's name.
// Every error is one line on stderr, "<tool>: error: <message>"; nothing is written to stdout.
#pragma once

#include <functional>
#include <string>

#include "core/error.h"

namespace CLI {
class App;
}

namespace sss {

inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;
inline constexpr int kExitUsage = 2;

// A command-line mistake found after parsing (the tool's own rules about its options): exit 2.
class UsageError : public Error {
 public:
  using Error::Error;
};

// Parses the command line with `app`, then runs `body` (its return value is the exit status);
// errors become one line on stderr and the statuses above. Names the tool for warn() and info().
// Adds --version ("<tool> (sss-tools) <CMake project version>") and ends --help with the exit
// statuses, then the app's own footer (set it to the tool's typical command lines, "Examples:").
int runTool(const char* toolName, CLI::App& app, int argc, char** argv,
            const std::function<int()>& body);
// The same for a tool that parses inside `body` itself (CLI11's own errors are then the body's
// concern): exceptions become "<tool>: error: ..." and exit 1, UsageError exit 2.
int runTool(const char* toolName, const std::function<int()>& body);

// "<tool>: error: <message>" on stderr, for an error the tool goes on after (one input of a
// batch, core/batch.h); control characters escaped.
void printError(const std::string& message);
// "<tool>: warning: <message>" on stderr; control characters escaped (a name from a file may
// hold them).
void warn(const std::string& message);
// "<tool>: <message>" on stderr, unless quiet.
void info(const std::string& message, bool quiet);

}  // namespace sss
