// Replays the fuzz targets' inputs in the normal build: every seed of tests/fuzz/corpus/<target>/
// is a valid file and must read without error; every input the fuzzer found a bug with
// (tests/fuzz/regressions/<target>/, named after the bug) must end in the sss::Error that kFound
// expects (or read fine), never crash, hang or throw anything else (the sanitizer build also
// checks for leaks and undefined behaviour on them).
#include <gtest/gtest.h>

#include <algorithm>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "core/error.h"
#include "fuzz_readers.h"
#include "support/tool_test.h"

namespace sss {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> filesIn(const fs::path& dir) {
  std::vector<fs::path> files;
  if (!fs::is_directory(dir)) return files;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.is_regular_file()) files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::string bytesOf(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

const fs::path kFuzzDir = fs::path(SSS_SOURCE_DIR) / "tests" / "fuzz";

class FuzzInputs : public ::testing::TestWithParam<std::string> {
 protected:
  test::ScratchDir scratch_;
};

TEST_P(FuzzInputs, EverySeedReads) {
  const std::vector<fs::path> seeds = filesIn(kFuzzDir / "corpus" / GetParam());
  ASSERT_GE(seeds.size(), 3u) << "a seed corpus of valid files for each target";
  for (const fs::path& seed : seeds) {
    SCOPED_TRACE(seed.string());
    EXPECT_LE(fs::file_size(seed), 8192u) << "seeds stay small";
    try {
      fuzz::readInput(GetParam(), bytesOf(seed), scratch_.path(""));
    } catch (const std::exception& e) {
      ADD_FAILURE() << "a seed must be a valid file: " << e.what();
    }
  }
}

// Each input the fuzzer found, "<target>/<file>", and what its reader must say ("": read
// fine). A new file in regressions/ needs its line here.
const std::map<std::string, std::string> kFound = {
    // OpenMesh's OBJ reader aborts on an assertion (a first corner "/1/1").
    {"obj/face_corner_without_vertex_index", "OBJ line 17: face corner '/1/1' has no vertex index"},
    // OpenMesh's OFF reader reads the face count "-1..." as 4294967295 corners: 1 GB allocated.
    {"off/face_count_with_garbage_suffix", "OFF face 1 corner count: bad number '-1p"},
    // A binary COFF's faces: OpenMesh reads a face of 892477488 corners (1 GB of handles).
    {"off/binary_coff_face_count", "OFF face 0 declares 892477488 corners"},
    // OpenMesh reads the OFF counts after the keyword's line ("OFF4OFF 6" has none for it): a
    // check that reads others lets OpenMesh go on to a face of 4294967295 corners.
    {"off/counts_on_the_keyword_line", "OFF header declares 0 vertices and 420 faces"},
    // A file of the keyword alone: the check of the BINARY tag must not read past the end.
    {"off/keyword_alone", "OFF header lacks the vertex and face counts"},
    // A '#' comment before the counts: OpenMesh's reads fail and leave its face count unset (a
    // check that skips the comment reads others); 1 GB of empty faces.
    {"off/comment_before_the_counts", "bad OFF count '#'"},
    // "COFFNOFF" is COFF to OpenMesh, not NOFF: records of the wrong size, then a face of
    // 4294967295 corners.
    {"off/keyword_followed_by_letters", "OFF face 0 declares -1 corners"},
    // OpenEXR allocates the 1.7 GB an unknown attribute declares in a 553-byte file.
    {"environment/exr_attribute_larger_than_file",
     "EXR header attribute 'capDate' declares 1768712291 bytes, but the file has 494 left"},
    // A channel list longer than its size field: a walk that trusts the size field loses step
    // with OpenEXR, which then allocates 1.7 GB for the next attribute.
    {"environment/exr_channel_list_longer_than_its_size",
     "declares 1767325440 bytes, but the file has 477 left"},
    // A 1903-byte PIZ EXR declaring 393459 x 8 pixels: OpenImageIO allocates 1.2 GB to decode
    // 256 of its scanlines at once.
    {"environment/exr_data_window_393459_wide",
     "EXR header declares chunks of 100725504 pixels of 12 bytes (393459x8 data window)"},
    // libpng reads a text chunk whole at its declared length (1.19 GB in an 88-byte file), past
    // its own warning that the chunk is too large.
    {"png/text_chunk_larger_than_file", "PNG: the file ends early (truncated?)"},
    // Messages must not quote the file's bytes raw, newlines and terminal escapes included.
    {"ply/control_character_in_message", "PLY header line 6: unknown format 'as\\x1f\\x1f"},
    {"obj/control_character_in_message", "\\x04' has no vertex index"},
    {"off/control_character_in_message", "bad OFF count '2\\x18j0'"},
    {"environment/control_character_in_openexr_message",
     "Pixel type of \"\\x01\" image channel is invalid."},
    {"baked_ply/control_character_in_message", "bad element count '12\\x1f\\x1f"},
    // A relightable bake's transport key naming its method with a control character: the enum's
    // own message quoted it raw, without the file's name.
    {"baked_ply/control_character_in_transport_method", "bad relight_transport 'ex\\x01act,"},
};

TEST_P(FuzzInputs, FoundInputsEndInTheirErrorOrRead) {
  for (const fs::path& input : filesIn(kFuzzDir / "regressions" / GetParam())) {
    SCOPED_TRACE(input.string());
    const auto expected = kFound.find(GetParam() + "/" + input.filename().string());
    ASSERT_NE(expected, kFound.end()) << "no expectation in kFound";
    std::string message;
    try {
      fuzz::readInput(GetParam(), bytesOf(input), scratch_.path(""));
    } catch (const Error& e) {
      message = e.what();
    } catch (const std::exception& e) {
      ADD_FAILURE() << "not an sss::Error: " << e.what();
    }
    if (expected->second.empty()) {
      EXPECT_EQ(message, "");
    } else {
      // One printable line that names the file it read (the bytes went to input.<ext>) and the
      // problem.
      EXPECT_EQ(message.rfind(scratch_.path("input."), 0), 0u) << message;
      EXPECT_NE(message.find(expected->second), std::string::npos) << message;
      EXPECT_TRUE(std::none_of(message.begin(), message.end(), [](char c) {
        return static_cast<unsigned char>(c) < 0x20;
      })) << message;
    }
  }
}

TEST(FuzzFindings, EveryExpectationHasItsInput) {
  for (const auto& [input, message] : kFound) {
    EXPECT_TRUE(fs::is_regular_file(kFuzzDir / "regressions" / input)) << input;
  }
}

INSTANTIATE_TEST_SUITE_P(Targets, FuzzInputs, ::testing::ValuesIn(fuzz::targetNames()),
                         [](const auto& info) { return info.param; });

}  // namespace
}  // namespace sss
