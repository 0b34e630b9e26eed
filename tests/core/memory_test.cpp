// core/memory.h (available memory, the SSS_MEMORY_LIMIT_MB cap, the one-line refusal), the mesh
// headers' declared counts (mesh/declared_counts.h) and sss-bake refusing a mesh that would not
// fit: before loading when the header gives the counts, after loading otherwise.
#include "core/memory.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "bake/prepare_mesh.h"
#include "core/error.h"
#include "mesh/declared_counts.h"
#include "mesh/primitives.h"
#include "support/tool_test.h"

namespace sss {
namespace {

using test::ScratchDir;

using test::readFile;

// Sets SSS_MEMORY_LIMIT_MB for one scope.
class MemoryLimit {
 public:
  explicit MemoryLimit(const char* value) { ::setenv("SSS_MEMORY_LIMIT_MB", value, 1); }
  ~MemoryLimit() { ::unsetenv("SSS_MEMORY_LIMIT_MB"); }
};

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

TEST(Memory, AvailableIsMemAvailableOrTheCgroupUnlessTheEnvironmentCapsIt) {
  const AvailableMemory machine = availableMemory();
  EXPECT_GT(machine.bytes, 16u << 20);
  EXPECT_NE(machine.source, "SSS_MEMORY_LIMIT_MB");
  const MemoryLimit limit("100");
  const AvailableMemory capped = availableMemory();
  EXPECT_EQ(capped.bytes, 100u << 20);
  EXPECT_EQ(capped.source, "SSS_MEMORY_LIMIT_MB");
}

TEST(Memory, AMalformedLimitIsAnErrorNamingTheVariable) {
  for (const char* bad : {"abc", "0", "-5", "12MB", "nan"}) {
    const MemoryLimit limit(bad);
    EXPECT_EQ(errorOf([] { availableMemory(); }),
              std::string("SSS_MEMORY_LIMIT_MB: '") + bad + "' is not a positive number of MiB");
  }
}

TEST(Memory, ANeedBeyondTheAvailableIsRefusedWithBothNumbers) {
  const MemoryLimit limit("1000");  // 1.05e9 bytes
  EXPECT_NO_THROW(checkMemoryNeed("m.ply", "baking 5 triangles", 1'000'000'000));
  EXPECT_EQ(errorOf([] { checkMemoryNeed("m.ply", "baking 5 triangles", 2'000'000'000); }),
            "m.ply: baking 5 triangles needs about 2 GB, 1.05 GB available (SSS_MEMORY_LIMIT_MB)");
}

TEST(Memory, PeakResidentSizeGrowsWithTouchedMemory) {
  const std::uint64_t before = peakResidentBytes();
  EXPECT_GT(before, 0u);
  std::string block(64u << 20, 'x');  // written, so resident
  EXPECT_GE(peakResidentBytes(), before + (32u << 20)) << block[12345];
}

TEST(Memory, TheBakeEstimateGrowsPerTriangleAndCountsVerticesTwice) {
  EXPECT_GT(estimateBakeBytes(0, 0), 100'000'000u);  // the environment, the libraries
  const std::uint64_t perTriangle =
      estimateBakeBytes(0, 2'000'000) - estimateBakeBytes(0, 1'000'000);
  EXPECT_GE(perTriangle, 200'000'000u) << "above the measured 235 bytes/triangle at 1e6";
  EXPECT_EQ(estimateBakeBytes(1'000'000, 0), estimateBakeBytes(0, 2'000'000));
  EXPECT_EQ(estimateBakeBytes(1'000'000, 2'000'000), estimateBakeBytes(0, 2'000'000));
}

// Header, then `bodyBytes` zero bytes.
void writeWithBody(const std::string& path, const std::string& header, std::size_t bodyBytes) {
  std::ofstream(path, std::ios::binary) << header << std::string(bodyBytes, '\0');
}

const char* const kBinaryPlyHeader =
    "ply\nformat binary_little_endian 1.0\nelement vertex 100\nproperty float x\n"
    "property float y\nproperty float z\nelement face 1000\nproperty list uchar int "
    "vertex_indices\nend_header\n";

TEST(DeclaredMeshCounts, PlyOffAndBinaryStlHeadersGiveTheirCounts) {
  const ScratchDir dir;
  writeWithBody(dir.path("a.ply"), kBinaryPlyHeader, 100 * 12 + 1000 * 13);
  DeclaredMeshCounts c = declaredMeshCounts(dir.path("a.ply"));
  EXPECT_TRUE(c.known);
  EXPECT_EQ(c.vertices, 100u);
  EXPECT_EQ(c.faces, 1000u);
  std::ofstream(dir.path("b.off")) << "OFF\n# comment\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
                                      "3 0 1 2\n3 0 2 3\n";
  c = declaredMeshCounts(dir.path("b.off"));
  EXPECT_TRUE(c.known);
  EXPECT_EQ(c.vertices, 4u);
  EXPECT_EQ(c.faces, 2u);
  std::string stl(84 + 50 * 3, '\0');
  stl[80] = 3;
  std::ofstream(dir.path("c.stl"), std::ios::binary) << stl;
  c = declaredMeshCounts(dir.path("c.stl"));
  EXPECT_TRUE(c.known);
  EXPECT_EQ(c.faces, 3u);
}

TEST(DeclaredMeshCounts, UnknownWhenTheHeaderCannotBeTrustedOrTheFormatHasNone) {
  const ScratchDir dir;
  // Declares more than the file can hold: the full reader's error, not an estimate, answers it.
  writeWithBody(dir.path("short.ply"), kBinaryPlyHeader, 100 * 12 + 999 * 13);
  std::ofstream(dir.path("huge.off")) << "OFF\n99999999999 99999999999 0\n0 0 0\n";
  std::ofstream(dir.path("text.stl")) << "solid x\nendsolid x\n";
  std::ofstream(dir.path("m.obj")) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  std::ofstream(dir.path("noend.ply")) << "ply\nformat ascii 1.0\nelement vertex 3\n";
  std::filesystem::create_directory(dir.path("folder.ply"));
  for (const char* name :
       {"short.ply", "huge.off", "text.stl", "m.obj", "noend.ply", "folder.ply", "missing.ply"}) {
    EXPECT_FALSE(declaredMeshCounts(dir.path(name)).known) << name;
  }
}

class BakeMemoryRefusal : public ::testing::Test {
 protected:
  test::ToolRun bake(const std::string& mesh, const std::string& limit) const {
    return test::runTool(
        "sss-bake",
        dir_.path(mesh) + " --sky -m marble --mm-per-unit 1 --samples 4 --far-field off -q -o " +
            dir_.path("out.ply"),
        test::Capture::StdoutAndStderr, limit.empty() ? "" : "SSS_MEMORY_LIMIT_MB=" + limit);
  }
  void expectRefused(const test::ToolRun& r, const std::string& message, const std::string& input,
                     const std::string& bytes) const {
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_EQ(r.output, "sss-bake: error: " + message + "\n");
    EXPECT_EQ(dir_.fileNames(), std::vector<std::string>{input}) << "no output, no temporary";
    EXPECT_EQ(readFile(dir_.path(input)), bytes) << "the input changed";
  }
  ScratchDir dir_;
};

// A binary PLY declaring 10^6 faces whose indices are all out of range: refused from its header
// (the estimate, 406 MB, against a 300 MiB cap) before the faces are read; without the cap the
// reader gets to the indices.
TEST_F(BakeMemoryRefusal, APlyIsRefusedFromItsHeaderBeforeLoading) {
  const std::string header =
      "ply\nformat binary_little_endian 1.0\nelement vertex 100\nproperty float x\n"
      "property float y\nproperty float z\nelement face 1000000\nproperty list uchar int "
      "vertex_indices\nend_header\n";
  std::string body(100 * 12, '\0');
  for (int f = 0; f < 1000000; ++f)
    body += std::string("\x03\xff\xff\x00\x00\xff\xff\x00\x00\xff\xff\x00\x00", 13);
  std::ofstream(dir_.path("big.ply"), std::ios::binary) << header << body;
  const std::string bytes = readFile(dir_.path("big.ply"));
  expectRefused(bake("big.ply", "300"),
                dir_.path("big.ply") +
                    ": baking 1000000 triangles needs about 0.406 GB, "
                    "0.315 GB available (SSS_MEMORY_LIMIT_MB)",
                "big.ply", bytes);
  const test::ToolRun unlimited = bake("big.ply", "");
  EXPECT_EQ(unlimited.exitCode, 1);
  EXPECT_EQ(unlimited.output.find("needs about"), std::string::npos) << unlimited.output;
}

// OBJ has no counts in a header: the check runs on the loaded mesh, before the bake's stages.
TEST_F(BakeMemoryRefusal, AnObjIsRefusedOnceLoadedAndBakesUnderARoomyCap) {
  const TriangleMesh sphere = makeIcosphere(3, 10.0f);  // 1280 triangles
  {
    std::ofstream obj(dir_.path("sphere.obj"));
    for (const glm::vec3& p : sphere.positions)
      obj << "v " << p.x << " " << p.y << " " << p.z << "\n";
    for (const glm::uvec3& t : sphere.triangles) {
      obj << "f " << t.x + 1 << " " << t.y + 1 << " " << t.z + 1 << "\n";
    }
  }
  const std::string bytes = readFile(dir_.path("sphere.obj"));
  expectRefused(bake("sphere.obj", "140"),
                dir_.path("sphere.obj") +
                    ": baking 1280 triangles needs about 0.15 GB, 0.147 GB "
                    "available (SSS_MEMORY_LIMIT_MB)",
                "sphere.obj", bytes);
  const test::ToolRun roomy = bake("sphere.obj", "1000");
  EXPECT_EQ(roomy.exitCode, 0) << roomy.output;
}

TEST_F(BakeMemoryRefusal, AMalformedCapIsAnError) {
  std::ofstream(dir_.path("m.obj")) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  expectRefused(bake("m.obj", "lots"),
                "SSS_MEMORY_LIMIT_MB: 'lots' is not a positive number of MiB", "m.obj",
                readFile(dir_.path("m.obj")));
}

}  // namespace
}  // namespace sss
