// What each fuzz target feeds its input to, shared by the libFuzzer targets (tests/fuzz/*_fuzz.cpp,
// built with SSS_FUZZ=ON) and by the regression test that replays the committed seed corpora
// (tests/fuzz/corpus/<target>/) and every input the fuzzer found (tests/fuzz/regressions/<target>/)
// in the normal build. The readers take file names and choose the format by extension, so an
// input is written to a file first, under the extension its target reads.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace sss::fuzz {

// The targets: "ply", "obj", "off", "stl", "environment", "baked_ply", "baked_glb", "gltf" (a
// .gltf with data: URIs), "glb" (a glTF scene in a GLB, through loadMesh).
// The image readers of lib/image: "exr", "hdr", "png". "material_map": sss-bake's --material-map
// JSON file (bake/material_map.h).
const std::vector<std::string>& targetNames();

// Writes `bytes` to `dir`/input.<ext> and reads it as the target's tools do. Bad input must end
// in sss::Error (thrown on); anything else (another exception, a crash, a sanitizer report) is
// a bug the fuzzer reports.
void readInput(std::string_view target, std::string_view bytes, const std::string& dir);

}  // namespace sss::fuzz
