#include "core/tool.h"

#include <cstdio>
#include <exception>

#include "core/error.h"

namespace sss {
namespace {
const char* gToolName = "sss";
}

int runTool(const char* toolName, const std::function<int()>& body) {
  gToolName = toolName;
  try {
    return body();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: error: %s\n", gToolName, e.what());
    return 1;
  }
}

void warn(const std::string& message) {
  std::fprintf(stderr, "%s: warning: %s\n", gToolName, message.c_str());
}

void info(const std::string& message, bool quiet) {
  if (!quiet) std::fprintf(stderr, "%s: %s\n", gToolName, message.c_str());
}

}  // namespace sss
