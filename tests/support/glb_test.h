// Helpers for tests of the baked GLB (mesh/baked_glb.h): its JSON and attributes read straight
// from the file (independently of our reader), the Khronos validator (tests/mesh/
// validate_gltf.js, gltf-validator fetched by data/fetch.sh) and assimp as a second reader.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include "support/tool_test.h"

namespace sss::test {

// A GLB's JSON and BIN chunks, split by the layout of glTF 2.0 section 4.4 (no checks: the file
// is ours; a wrong layout fails the test through the JSON parse or a size assertion).
struct GlbFile {
  nlohmann::json json;
  std::string bin;

  explicit GlbFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    const std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    std::uint32_t jsonLength = 0, binLength = 0;
    EXPECT_GE(bytes.size(), 28u);
    if (bytes.size() < 28) return;
    std::memcpy(&jsonLength, bytes.data() + 12, 4);
    json = nlohmann::json::parse(bytes.substr(20, jsonLength));
    std::memcpy(&binLength, bytes.data() + 20 + jsonLength, 4);
    bin = bytes.substr(28 + jsonLength, binLength);
  }

  // The float VEC3 accessor of a primitive attribute ("POSITION", "COLOR_0", "_EXITANCE").
  std::vector<glm::vec3> vec3(const std::string& attribute) const {
    const auto& accessor =
        json["accessors"][json["meshes"][0]["primitives"][0]["attributes"][attribute].get<int>()];
    const auto& view = json["bufferViews"][accessor["bufferView"].get<int>()];
    std::vector<glm::vec3> values(accessor["count"].get<std::size_t>());
    const std::size_t offset = view.value("byteOffset", 0) + accessor.value("byteOffset", 0);
    EXPECT_LE(offset + values.size() * 12, bin.size());
    if (offset + values.size() * 12 <= bin.size())
      std::memcpy(values.data(), bin.data() + offset, values.size() * 12);
    return values;
  }

  const nlohmann::json& sssExtras() const { return json["asset"]["extras"]["sss"]; }
};

// Runs a shell command, capturing stdout and stderr.
inline ToolRun runCommand(const std::string& command) {
  return runShell(command + " 2>&1");
}

// The Khronos validator on `path`: zero errors and zero warnings expected.
inline void expectValidGltf(const std::string& path) {
  const ToolRun r =
      runCommand("node " SSS_SOURCE_DIR "/tests/mesh/validate_gltf.js '" + path + "'");
  EXPECT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find(": 0 errors, 0 warnings"), std::string::npos) << r.output;
}

// The number after `label` in `text` ("Vertices:   42" in assimp's report); -1 when it is absent.
// (std::regex would do it too, at ~3 s more compile for every test file that includes this.)
inline long numberAfter(const std::string& text, const std::string& label) {
  const std::size_t at = text.find(label);
  if (at == std::string::npos) return -1;
  return std::strtol(text.c_str() + at + label.size(), nullptr, 10);  // skips the spaces
}

// assimp (a second glTF reader) reads `path` with these vertex and face counts.
inline void expectAssimpReads(const std::string& path, std::size_t vertices, std::size_t faces) {
  const ToolRun r = runCommand("assimp info '" + path + "'");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_EQ(numberAfter(r.output, "Vertices:"), static_cast<long>(vertices)) << r.output;
  EXPECT_EQ(numberAfter(r.output, "Faces:"), static_cast<long>(faces)) << r.output;
}

}  // namespace sss::test
