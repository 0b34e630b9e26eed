#include "core/tool.h"

#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstring>
#include <exception>
#include <new>

#include <CLI/CLI.hpp>

#include "core/atomic_output.h"

namespace sss {
namespace {

const char* gToolName = "sss";
bool gStderrIsTerminal = false;

// SIGINT, SIGTERM, SIGHUP: remove the unfinished outputs (core/atomic_output.h), say so, and
// exit 128 + the signal (130, 143, 129) like a shell's interrupted command. Async-signal-safe:
// unlink, write and _exit on buffers prepared before.
extern "C" void onInterrupt(int signal) {
  removeLiveTemporaries();
  const char* name = signal == SIGINT ? "SIGINT" : signal == SIGTERM ? "SIGTERM" : "SIGHUP";
  char line[256];
  std::size_t n = 0;
  auto put = [&](const char* text) {
    while (*text && n < sizeof line - 1) line[n++] = *text++;
  };
  if (gStderrIsTerminal) put("\n");  // after a progress bar's carriage return
  put(gToolName);
  put(": error: interrupted by ");
  put(name);
  put(" (unfinished output files removed)\n");
  [[maybe_unused]] const ssize_t written = ::write(STDERR_FILENO, line, n);
  ::_exit(128 + signal);
}

// Signals the parent ignores stay ignored (a background job's SIGINT, nohup's SIGHUP).
void installInterruptHandlers() {
  gStderrIsTerminal = ::isatty(STDERR_FILENO) != 0;
  for (const int signal : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction current {};
    if (::sigaction(signal, nullptr, &current) != 0 || current.sa_handler == SIG_IGN) continue;
    struct sigaction action {};
    action.sa_handler = onInterrupt;
    sigfillset(&action.sa_mask);  // no second signal inside the handler
    ::sigaction(signal, &action, nullptr);
  }
}

int printError(const char* message, int status) {
  std::fprintf(stderr, "%s: error: %s\n", gToolName, message);
  return status;
}

// The end of every tool's --help: the exit statuses, then the tool's own footer (its typical
// command lines, "Examples:"), as help2man turns "Title:" paragraphs into man page sections.
void addVersionAndFooter(const char* toolName, CLI::App& app) {
  app.set_version_flag("--version", std::string(toolName) + " (sss-tools) " + SSS_VERSION,
                       "Print the version and exit");
  std::string footer =
      "Exit status:\n"
      "  0        success, --help, --version\n"
      "  1        bad input or a failed operation (a missing, corrupt or invalid file, an\n"
      "           unwritable output, no OpenGL)\n"
      "  2        usage: the command line is wrong whatever the files hold\n"
      "  130 143 129  interrupted by SIGINT, SIGTERM, SIGHUP (unfinished outputs removed)";
  if (!app.get_footer().empty()) footer += "\n\n" + app.get_footer();
  app.footer(footer);
}

}  // namespace

int runTool(const char* toolName, CLI::App& app, int argc, char** argv,
            const std::function<int()>& body) {
  gToolName = toolName;
  addVersionAndFooter(toolName, app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return app.exit(e);  // --help, --version: on stdout, status 0
  } catch (const CLI::ParseError& e) {
    return printError(e.what(), kExitUsage);
  } catch (const std::exception& e) {
    // Raised by an option's own callback while the command line was read.
    return printError(e.what(), kExitUsage);
  }
  return runTool(toolName, body);
}

int runTool(const char* toolName, const std::function<int()>& body) {
  gToolName = toolName;
  installInterruptHandlers();
  try {
    return body();
  } catch (const UsageError& e) {
    return printError(e.what(), kExitUsage);
  } catch (const std::bad_alloc&) {
    // The last line of defence: readers check declared sizes before allocating.
    return printError("out of memory", kExitFailure);
  } catch (const std::exception& e) {
    return printError(e.what(), kExitFailure);
  }
}

void printError(const std::string& message) {
  std::fprintf(stderr, "%s: error: %s\n", gToolName, escapeControl(message).c_str());
}

void warn(const std::string& message) {
  std::fprintf(stderr, "%s: warning: %s\n", gToolName, escapeControl(message).c_str());
}

void info(const std::string& message, bool quiet) {
  if (!quiet) std::fprintf(stderr, "%s: %s\n", gToolName, message.c_str());
}

}  // namespace sss
