#include "core/tool.h"

#include <cstdio>
#include <exception>

#include <CLI/CLI.hpp>

namespace sss {
namespace {

const char* gToolName = "sss";

int printError(const char* message, int status) {
  std::fprintf(stderr, "%s: error: %s\n", gToolName, message);
  return status;
}

}  // namespace

int runTool(const char* toolName, CLI::App& app, int argc, char** argv,
            const std::function<int()>& body) {
  gToolName = toolName;
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return app.exit(e);  // --help: the help on stdout, status 0
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
  try {
    return body();
  } catch (const UsageError& e) {
    return printError(e.what(), kExitUsage);
  } catch (const std::exception& e) {
    return printError(e.what(), kExitFailure);
  }
}

void warn(const std::string& message) {
  std::fprintf(stderr, "%s: warning: %s\n", gToolName, message.c_str());
}

void info(const std::string& message, bool quiet) {
  if (!quiet) std::fprintf(stderr, "%s: %s\n", gToolName, message.c_str());
}

}  // namespace sss
