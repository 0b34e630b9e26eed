// The reference GLSL function for engines in docs/relighting.md, compiled as the docs print it
// (llvmpipe, a compute shader) and run on a relightable GLB's attributes as a GPU reads them: its
// radiance along the normal must be what the transfer read back by readBakedGlb gives under the
// same SH light (sum_k T_k L_k, clamped at zero, times g). A change to the GLB's packing or to
// the function that the other does not follow fails here.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "core/random.h"
#include "mesh/baked_glb.h"
#include "mesh/primitives.h"
#include "render/gl.h"
#include "render/gl_context.h"
#include "support/glb_test.h"

namespace sss {
namespace {

std::string readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The ```glsl block of docs/relighting.md that defines relitRadiance.
std::string documentedFunction() {
  const std::string doc = readText(SSS_SOURCE_DIR "/docs/relighting.md");
  for (std::size_t at = doc.find("```glsl\n"); at != std::string::npos;
       at = doc.find("```glsl\n", at + 1)) {
    const std::size_t begin = at + 8, end = doc.find("```", begin);
    const std::string block = doc.substr(begin, end - begin);
    if (block.find("vec3 relitRadiance(") != std::string::npos) return block;
  }
  ADD_FAILURE() << "docs/relighting.md has no relitRadiance";
  return "";
}

// One vertex's inputs as the vertex shader would receive them (std430: vec4s in a row).
struct VertexInputs {
  float low[12][4];   // _TRANSFER_LOW_<j>, normalized SHORT: q / 32767
  float exponent[4];  // _TRANSFER_EXPONENT, BYTE, not normalized: e
  float gain[4];      // _RADIANCE_GAIN
};

GLuint compileCompute(const std::string& source) {
  const GLuint shader = glCreateShader(GL_COMPUTE_SHADER);
  const char* text = source.c_str();
  glShaderSource(shader, 1, &text, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[4096] = {};
    glGetShaderInfoLog(shader, sizeof log, nullptr, log);
    ADD_FAILURE() << "the documented GLSL does not compile:\n" << log << "\n" << source;
  }
  const GLuint program = glCreateProgram();
  glAttachShader(program, shader);
  glLinkProgram(program);
  glDeleteShader(shader);
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  EXPECT_TRUE(ok);
  return program;
}

GLuint storage(const void* data, std::size_t bytes, GLuint binding) {
  GLuint buffer = 0;
  glCreateBuffers(1, &buffer);
  glNamedBufferStorage(buffer, GLsizeiptr(bytes), data, GL_DYNAMIC_STORAGE_BIT);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, buffer);
  return buffer;
}

// The raw bytes of a primitive attribute's elements (tightly packed, as the writer puts them).
const char* attributeBytes(const test::GlbFile& glb, const std::string& name) {
  const auto& attributes = glb.json["meshes"][0]["primitives"][0]["attributes"];
  const auto& accessor = glb.json["accessors"][attributes[name].get<int>()];
  const auto& view = glb.json["bufferViews"][accessor["bufferView"].get<int>()];
  return glb.bin.data() + view["byteOffset"].get<std::size_t>();
}

TEST(RelightGlsl, TheDocumentedFunctionRelightsTheGlbsAttributes) {
  const GlContext context;
  BakedMesh baked;
  baked.mesh = makeIcosphere(1, 1.0f);
  const std::size_t n = baked.mesh.vertexCount(), count = 16;
  Pcg32 rng(11, 0);
  baked.relightOrder = 3;
  baked.relightTransfer.resize(n * count);
  for (std::size_t v = 0; v < n; ++v) {
    const float magnitude = std::pow(10.0f, 4.0f * rng.uniform() - 2.0f);
    for (std::size_t k = 0; k < count; ++k)
      for (int c = 0; c < 3; ++c)
        baked.relightTransfer[v * count + k][c] =
            magnitude * (k == 0 ? 1.0f + rng.uniform() : 2.0f * rng.uniform() - 1.0f);
  }
  baked.exitance.assign(n, glm::vec3(0.5f));
  baked.radianceGain.assign(n, glm::vec3(0.3f, 0.4f, 0.5f));
  baked.exitancePerRadiance.assign(n, glm::vec3(3.0f));
  baked.relightTransport = "hierarchical,0.01,gauss,halfspace,0.9,0.8,0.7,directional,2,64";
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("sss-test-" + std::to_string(::getpid()) + "-glsl.glb"))
                               .string();
  writeBakedGlb(path, baked);
  const test::GlbFile glb(path);
  const BakedMesh read = readBakedGlb(path).baked;
  std::filesystem::remove(path);

  std::vector<VertexInputs> inputs(n);
  const auto* exponents =
      reinterpret_cast<const int8_t*>(attributeBytes(glb, "_TRANSFER_EXPONENT"));
  const std::vector<glm::vec3> gain = glb.vec3("_RADIANCE_GAIN");
  for (std::size_t j = 0; j < 12; ++j) {
    const char* low = attributeBytes(glb, "_TRANSFER_LOW_" + std::to_string(j));
    for (std::size_t v = 0; v < n; ++v)
      for (int c = 0; c < 4; ++c) {
        int16_t q = 0;
        std::memcpy(&q, low + (4 * v + c) * 2, 2);
        inputs[v].low[j][c] = std::max(float(q) / 32767.0f, -1.0f);  // GL's SNORM rule
      }
  }
  for (std::size_t v = 0; v < n; ++v)
    for (int c = 0; c < 4; ++c) {
      inputs[v].exponent[c] = float(exponents[4 * v + c]);
      inputs[v].gain[c] = c < 3 ? gain[v][c] : 0.0f;
    }
  std::array<glm::vec4, 16> light{};
  for (glm::vec4& l : light)
    l = glm::vec4(rng.uniform(), rng.uniform(), rng.uniform(), 0.0f) * 2.0f - 0.6f;

  const GLuint program =
      compileCompute("#version 450\nlayout(local_size_x = 1) in;\n" + documentedFunction() + R"(
struct VertexInputs { vec4 low[12]; vec4 exponent; vec4 gain; };
layout(std430, binding = 0) readonly buffer Vertices { VertexInputs vertices[]; };
layout(std430, binding = 1) readonly buffer Light { vec4 lightSh[16]; };
layout(std430, binding = 2) writeonly buffer Radiance { vec4 radiance[]; };
void main() {
  uint v = gl_GlobalInvocationID.x;
  vec3 sh[16];
  for (int k = 0; k < 16; ++k) sh[k] = lightSh[k].xyz;
  radiance[v] = vec4(relitRadiance(vertices[v].low, vertices[v].exponent, vertices[v].gain.xyz,
                                   sh), 0.0);
}
)");
  std::vector<glm::vec4> radiance(n);
  const GLuint buffers[] = {storage(inputs.data(), inputs.size() * sizeof(VertexInputs), 0),
                            storage(light.data(), sizeof light, 1),
                            storage(radiance.data(), radiance.size() * sizeof(glm::vec4), 2)};
  glUseProgram(program);
  glDispatchCompute(GLuint(n), 1, 1);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  glGetNamedBufferSubData(buffers[2], 0, GLsizeiptr(radiance.size() * sizeof(glm::vec4)),
                          radiance.data());
  glDeleteBuffers(3, buffers);
  glDeleteProgram(program);
  ASSERT_EQ(glGetError(), GLenum(GL_NO_ERROR));

  std::size_t lit = 0;
  for (std::size_t v = 0; v < n; ++v) {
    glm::dvec3 b(0.0), scale(0.0);
    for (std::size_t k = 0; k < count; ++k) {
      const glm::dvec3 t(read.relightTransfer[v * count + k]);
      b += t * glm::dvec3(light[k]);
      scale = glm::max(scale, glm::abs(t * glm::dvec3(light[k])));
    }
    const glm::dvec3 expected = glm::max(b, 0.0) * glm::dvec3(read.radianceGain[v]);
    for (int c = 0; c < 3; ++c) {
      // Float sums of 16 terms: within a few ulps of their largest term.
      EXPECT_NEAR(radiance[v][c], expected[c], 1e-5 * scale[c] * read.radianceGain[v][c] + 1e-30)
          << "vertex " << v << " channel " << c;
      lit += expected[c] > 0.0;
    }
  }
  EXPECT_GT(lit, n);  // the check sees lit vertices, not only clamped ones
}

}  // namespace
}  // namespace sss
