// What every command-line tool shares: one-line errors, warnings, exit codes.
#pragma once

#include <functional>
#include <string>

namespace sss {

// Runs a tool's body. sss::Error and other exceptions become "<tool>: error: <message>" on
// stderr and exit code 1; CLI11 parse errors keep CLI11's own handling (exit code 2 or help).
int runTool(const char* toolName, const std::function<int()>& body);

// "<tool>: warning: <message>" on stderr.
void warn(const std::string& message);
// "<tool>: <message>" on stderr, unless quiet.
void info(const std::string& message, bool quiet);

}  // namespace sss
