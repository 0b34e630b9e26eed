// Helpers for the mesh tests: raw file writing, error matching (and the shared ScratchDir).
#pragma once

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "mesh/load_mesh.h"
#include "support/tool_test.h"

namespace sss::test {

// The same bytes (floats compared bit for bit, NaN and -0 included).
template <class T>
bool bitEqual(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

inline void writeFile(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

inline std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Runs f, expects sss::Error whose message starts with `path` and contains `part`.
template <class F>
void expectError(F&& f, const std::string& path, const std::string& part) {
  try {
    f();
    ADD_FAILURE() << "no error; expected one containing '" << part << "'";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << message;
    EXPECT_NE(message.find(part), std::string::npos) << message;
  }
}

// Writes `bytes` to `name` in `dir` and expects loadMesh to refuse the file with an sss::Error
// whose message starts with its path and contains `part`.
inline void expectLoadRefused(const ScratchDir& dir, const std::string& name,
                              const std::string& bytes, const std::string& part) {
  SCOPED_TRACE(name);
  const std::string file = dir.path(name);
  writeFile(file, bytes);
  expectError([&] { loadMesh(file); }, file, part);
}

}  // namespace sss::test
