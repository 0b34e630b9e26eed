// The relightable bake's stored transfer (mesh/quantized_transfer.h): within half a step of 2^-13
// of each vertex's largest coefficient (bands 4 and up: 2^-5 of theirs), exact when stored again,
// and what the baked PLY and GLB carry (16-bit steps, 8-bit from band 4) read back bit for bit;
// the float transfer of format 1 files and the all-16-bit high bands of format 2 still read.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"
#include "core/random.h"
#include "mesh/baked_glb.h"
#include "mesh/baked_ply.h"
#include "mesh/primitives.h"
#include "mesh/quantized_transfer.h"
#include "support/glb_test.h"
#include "test_util.h"

namespace sss {
namespace {

// count coefficients per vertex, each vertex and channel with its own magnitude (1e-6 to 1e6),
// signs mixed, one vertex all zero, one whose largest is a power of two.
std::vector<glm::vec3> randomTransfer(std::size_t vertices, std::size_t count) {
  std::vector<glm::vec3> t(vertices * count);
  Pcg32 rng(7, 0);
  for (std::size_t v = 0; v < vertices; ++v) {
    glm::vec3 magnitude;
    for (int c = 0; c < 3; ++c) magnitude[c] = std::pow(10.0f, 12.0f * rng.uniform() - 6.0f);
    for (std::size_t k = 0; k < count; ++k)
      for (int c = 0; c < 3; ++c)
        t[v * count + k][c] = magnitude[c] * (2.0f * rng.uniform() - 1.0f);
  }
  for (std::size_t k = 0; k < count; ++k) t[k] = glm::vec3(0.0f);
  t[count] = glm::vec3(4.0f, -0.25f, 1024.0f);
  return t;
}

// The largest |T| of vertex v's channel c over coefficients [first, last), count per vertex.
float largestMagnitude(const std::vector<glm::vec3>& t, std::size_t count, std::size_t v, int c,
                       std::size_t first, std::size_t last) {
  float largest = 0.0f;
  for (std::size_t k = first; k < last; ++k)
    largest = std::max(largest, std::abs(t[v * count + k][c]));
  return largest;
}

TEST(QuantizedTransfer, KeepsEachCoefficientWithinHalfAStepOfItsVertexsLargest) {
  const std::size_t count = 9, n = 500;
  const std::vector<glm::vec3> t = randomTransfer(n, count);
  const std::vector<glm::vec3> stored = storedTransfer("t", t, count);
  ASSERT_EQ(stored.size(), t.size());
  double worst = 0.0;
  for (std::size_t v = 0; v < n; ++v)
    for (int c = 0; c < 3; ++c) {
      const float largest = largestMagnitude(t, count, v, c, 0, count);
      for (std::size_t k = 0; k < count; ++k) {
        const float error = std::abs(stored[v * count + k][c] - t[v * count + k][c]);
        if (largest == 0.0f) {
          EXPECT_EQ(stored[v * count + k][c], 0.0f);
          continue;
        }
        worst = std::max(worst, double(error / largest));
      }
    }
  EXPECT_LE(worst, std::ldexp(1.0, -14));  // half of a step of at most 2^-13 of the largest
  EXPECT_GT(worst, std::ldexp(1.0, -17));  // and it does round: not floats kept as they were
  EXPECT_EQ(stored[count], glm::vec3(4.0f, -0.25f, 1024.0f));  // powers of two are exact
}

TEST(QuantizedTransfer, StoringTheStoredValuesChangesNothing) {
  const std::size_t count = 16;
  std::vector<glm::vec3> t = randomTransfer(300, count);
  // A largest that rounds down to a power of two: 2^-1 - a quarter step of the 2^0 range.
  t[2 * count] = glm::vec3(0.5f + std::ldexp(1.0f, -17), 0.5f, -0.5f - std::ldexp(1.0f, -17));
  const std::vector<glm::vec3> once = storedTransfer("t", t, count);
  EXPECT_EQ(storedTransfer("t", once, count), once);
  const QuantizedTransfer q = quantizeTransfer("t", t, count);
  for (const auto& steps : q.values)
    for (const int16_t s : steps) EXPECT_LE(std::abs(int(s)), kTransferSteps);
  for (const glm::vec3& s : q.scale)
    for (int c = 0; c < 3; ++c) {
      if (s[c] == 0.0f) continue;
      int e = 0;
      EXPECT_EQ(std::frexp(s[c] / kTransferNormalizer, &e), 0.5f);  // a power of two
    }
}

TEST(QuantizedTransfer, RefusesValuesNoScaleCanHold) {
  std::vector<glm::vec3> t(4, glm::vec3(1.0f));
  t[2].y = 3e37f;
  try {
    quantizeTransfer("big.ply", t, 4);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("big.ply"), std::string::npos) << e.what();
  }
}

// Every scale quantizeTransfer gives, over the range it accepts (1e30 down to the smallest
// float), is 32767 (127) times 2^e with e a byte the GLB holds, and comes back from it exactly; a
// channel whose largest is below 2^-127 steps is stored as zero.
TEST(QuantizedTransfer, ScalesAreExactPowersOfTwoWhoseExponentsFitAByte) {
  std::vector<glm::vec3> t;
  for (float largest = 1e30f; largest > 0.0f; largest *= 0.37f)
    for (int k = 0; k < 25; ++k) t.push_back(glm::vec3(largest * (float(k % 7 - 3) / 3.0f)));
  const std::size_t count = 25, n = t.size() / count;
  const QuantizedTransfer q = quantizeTransfer("t", t, count);
  std::size_t zeros = 0;
  for (std::size_t v = 0; v < n; ++v)
    for (const auto& [scales, normalizer] : {std::pair{&q.scale, kTransferNormalizer},
                                             std::pair{&q.scaleHigh, kHighTransferNormalizer}}) {
      const float scale = (*scales)[v].x;
      const int e = scaleExponent(scale, normalizer);
      EXPECT_TRUE(e == kZeroScaleExponent || (e >= kMinStepExponent && e <= kMaxStepExponent)) << e;
      EXPECT_EQ(scaleOfExponent("t", e, normalizer), scale) << e;
      zeros += scale == 0.0f;
    }
  EXPECT_GT(zeros, 0u);  // the smallest channels
  const float tiny = float(kTransferSteps) * std::ldexp(1.0f, -127);
  EXPECT_EQ(quantizeTransfer("t", std::vector<glm::vec3>(16, glm::vec3(tiny)), 16).scale[0].x,
            0.0f);
  EXPECT_GT(quantizeTransfer("t", std::vector<glm::vec3>(16, glm::vec3(2 * tiny)), 16).scale[0].x,
            0.0f);
  EXPECT_THROW(scaleOfExponent("t", kMaxStepExponent + 1, kTransferNormalizer), Error);
  EXPECT_THROW(scaleOfExponent("t", kMinStepExponent - 1, kTransferNormalizer), Error);
}

// A relightable bake of `order` on an icosphere written as PLY and GLB: the transfer comes back
// as storedTransfer made it from both, the GLB passes the validator. Returns the bytes the
// relightable fields add to the PLY (against the same bake without them) and the vertex count.
// A relightable bake of `order` on an icosphere, its transfer random.
BakedMesh relightableBake(int order) {
  BakedMesh baked;
  baked.mesh = makeIcosphere(1, 1.0f);
  const std::size_t n = baked.mesh.vertexCount(), count = std::size_t((order + 1) * (order + 1));
  baked.exitance.assign(n, glm::vec3(0.5f));
  baked.relightOrder = order;
  baked.relightTransfer = randomTransfer(n, count);
  baked.radianceGain.assign(n, glm::vec3(0.3f));
  baked.exitancePerRadiance.assign(n, glm::vec3(3.0f));
  baked.relightTransport = "hierarchical,0.01,gauss,halfspace,0.9,0.8,0.7,directional,2,64";
  return baked;
}

std::filesystem::path scratchDir() {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("sss-test-" + std::to_string(::getpid()) + "-qt");
  std::filesystem::create_directories(dir);
  return dir;
}

std::pair<std::size_t, std::size_t> relightableFileBytes(int order) {
  const std::filesystem::path dir = scratchDir();
  BakedMesh baked = relightableBake(order);
  const std::size_t n = baked.mesh.vertexCount(), count = std::size_t((order + 1) * (order + 1));
  const std::vector<glm::vec3> expected = storedTransfer("t", baked.relightTransfer, count);
  const std::string ply = (dir / "q.ply").string(), glb = (dir / "q.glb").string();
  writeBakedPly(ply, baked);
  writeBakedGlb(glb, baked);
  EXPECT_EQ(readBakedPly(ply).baked.relightTransfer, expected);
  EXPECT_EQ(readBakedGlb(glb).baked.relightTransfer, expected);
  test::expectValidGltf(glb);  // normalized SHORT (and BYTE) attributes, padded strides
  const auto plySize = std::filesystem::file_size(ply);
  baked.relightOrder = -1;
  baked.relightTransfer.clear();
  baked.radianceGain.clear();
  baked.exitancePerRadiance.clear();
  writeBakedPly(ply, baked);
  const std::size_t added = plySize - std::filesystem::file_size(ply);
  std::filesystem::remove_all(dir);
  return {added, n};
}

// Order 3: the PLY's transfer takes 6 bytes per coefficient instead of 12.
TEST(QuantizedTransfer, TheBakedFilesCarryItBitForBit) {
  const auto [added, n] = relightableFileBytes(3);
  // 16 x 3 shorts and 3 float scales per vertex, with the 6 floats of g and b, and the header's
  // lines; floats would take 16 x 3 x 4 bytes.
  const std::size_t count = 16, records = n * (count * 6 + 12 + 24);
  EXPECT_GE(added, records);
  EXPECT_LT(added, records + 4096);
  EXPECT_LT(added, n * (count * 12 + 24));
}

// The float transfer of a format 1 file (before the quantized form) still reads as it was written.
TEST(QuantizedTransfer, AFormatOneFilesFloatTransferStillReads) {
  const std::string seed =
      SSS_SOURCE_DIR "/tests/fuzz/corpus/baked_ply/icosahedron_relightable.ply";
  const BakedPlyContents c = readBakedPly(seed);
  ASSERT_EQ(c.baked.relightOrder, 1);
  ASSERT_EQ(c.baked.relightTransfer.size(), 4 * c.baked.mesh.vertexCount());
  float largest = 0.0f;
  for (const glm::vec3& t : c.baked.relightTransfer) largest = std::max(largest, std::abs(t.x));
  EXPECT_GT(largest, 0.0f);
  // Not quantized: some coefficient is not a multiple of its vertex's step.
  EXPECT_NE(storedTransfer(seed, c.baked.relightTransfer, 4), c.baked.relightTransfer);
}

}  // namespace
}  // namespace sss

namespace sss {
namespace {

// Bands 4 and up (orders above 3): 8 bits with a scale of their own, each coefficient within half
// a step of 2^-6 of the largest of those bands; bands 0-3 as before; exact when stored again.
TEST(QuantizedTransfer, HighBandsTakeEightBitsWithinHalfAStepOfTheirLargest) {
  const std::size_t count = 49, n = 400;  // order 6
  const std::vector<glm::vec3> t = randomTransfer(n, count);
  const QuantizedTransfer q = quantizeTransfer("t", t, count);
  ASSERT_EQ(q.scaleHigh.size(), n);
  EXPECT_TRUE(quantizeTransfer("t", t, 16).scaleHigh.empty());  // order 3: no high bands
  const std::vector<glm::vec3> stored = dequantizeTransfer(q, count);
  double worstLow = 0.0, worstHigh = 0.0;
  for (std::size_t v = 0; v < n; ++v)
    for (int c = 0; c < 3; ++c) {
      const float largestLow = largestMagnitude(t, count, v, c, 0, kShortTransferCoefficients);
      const float largestHigh = largestMagnitude(t, count, v, c, kShortTransferCoefficients, count);
      for (std::size_t k = 0; k < count; ++k) {
        const bool high = k >= kShortTransferCoefficients;
        const int limit = high ? kHighTransferSteps : kTransferSteps;
        EXPECT_LE(std::abs(int(q.values[v * count + k][c])), limit);
        const float largest = high ? largestHigh : largestLow;
        if (largest == 0.0f) continue;
        const double error = std::abs(stored[v * count + k][c] - t[v * count + k][c]) / largest;
        (high ? worstHigh : worstLow) = std::max(high ? worstHigh : worstLow, error);
      }
    }
  EXPECT_LE(worstLow, std::ldexp(1.0, -14));
  EXPECT_LE(worstHigh, 1.0 / 127.0);          // half of a step of at most 2 / 127 of the largest
  EXPECT_GT(worstHigh, std::ldexp(1.0, -9));  // and it is 8 bits, not 16
  EXPECT_EQ(storedTransfer("t", stored, count), stored);
}

// Order 6: the high bands as 8 bits (the GLB's as normalized BYTE, which the validator accepts):
// the PLY's transfer takes 6 bytes per coefficient of bands 0-3, 3 per higher one and 12 for the
// high scale.
TEST(QuantizedTransfer, OrderSixFilesCarryTheHighBandsInEightBits) {
  const auto [added, n] = relightableFileBytes(6);
  const std::size_t records = n * (16 * 6 + 33 * 3 + 12 + 12 + 24);
  EXPECT_GE(added, records);
  EXPECT_LT(added, records + 8192);  // the header's property lines
}

// The GLB's steps, decoded from the file as docs/relighting.md lays them out (not through our
// reader): entry i = 3 k + c of bands 0-3 is component i % 4 of the normalized SHORT VEC4
// _TRANSFER_LOW_<i / 4>, of bands 4-6 (i = 3 (k - 16) + c) of the BYTE _TRANSFER_HIGH_<i / 4>,
// tightly packed (8 and 4 bytes a vertex), the padding zero; times the scales of the exponents in
// _TRANSFER_EXPONENT(_HIGH) they give the stored transfer.
TEST(QuantizedTransfer, TheGlbPacksTheStepsFourToAnAttribute) {
  const std::filesystem::path dir = scratchDir();
  const BakedMesh baked = relightableBake(6);
  const std::size_t n = baked.mesh.vertexCount(), count = 49;
  const std::string path = (dir / "packed.glb").string();
  writeBakedGlb(path, baked);
  const test::GlbFile glb(path);
  const std::vector<glm::vec3> stored = storedTransfer("t", baked.relightTransfer, count);
  const auto& attributes = glb.json["meshes"][0]["primitives"][0]["attributes"];
  // A non-normalized BYTE VEC4 of exponents e (r, g, b, 0): the scale is normalizer 2^e.
  const auto scales = [&](const std::string& name, float normalizer) {
    const auto& accessor = glb.json["accessors"][attributes[name].get<int>()];
    const auto& view = glb.json["bufferViews"][accessor["bufferView"].get<int>()];
    EXPECT_EQ(accessor["type"], "VEC4");
    EXPECT_EQ(accessor["componentType"], 5120);
    EXPECT_FALSE(accessor.value("normalized", false));
    EXPECT_EQ(view["byteLength"], 4 * n);
    std::vector<glm::vec3> out(n);
    const char* data = glb.bin.data() + view["byteOffset"].get<std::size_t>();
    for (std::size_t v = 0; v < n; ++v) {
      EXPECT_EQ(data[4 * v + 3], 0);
      for (int c = 0; c < 3; ++c) out[v][c] = std::ldexp(normalizer, data[4 * v + c]);
    }
    return out;
  };
  const std::vector<glm::vec3> scale = scales("_TRANSFER_EXPONENT", kTransferNormalizer);
  const std::vector<glm::vec3> scaleHigh =
      scales("_TRANSFER_EXPONENT_HIGH", kHighTransferNormalizer);
  EXPECT_EQ(glb.sssExtras()["format"], 4);
  const auto decode = [&](const std::string& prefix, std::size_t first, std::size_t last,
                          int componentType, std::size_t size, float normalizer,
                          const std::vector<glm::vec3>& scales) {
    const std::size_t entries = 3 * (last - first), attributeCount = (entries + 3) / 4;
    EXPECT_FALSE(attributes.contains(prefix + std::to_string(attributeCount)));
    for (std::size_t j = 0; j < attributeCount; ++j) {
      const auto& accessor =
          glb.json["accessors"][attributes[prefix + std::to_string(j)].get<int>()];
      const auto& view = glb.json["bufferViews"][accessor["bufferView"].get<int>()];
      ASSERT_EQ(accessor["type"], "VEC4");
      ASSERT_EQ(accessor["componentType"], componentType);
      ASSERT_EQ(accessor["normalized"], true);
      ASSERT_EQ(accessor["count"], n);
      ASSERT_EQ(view["byteLength"], 4 * size * n);
      ASSERT_FALSE(view.contains("byteStride"));
      const char* data = glb.bin.data() + view["byteOffset"].get<std::size_t>();
      for (std::size_t v = 0; v < n; ++v)
        for (std::size_t i = 4 * j; i < 4 * j + 4; ++i) {
          const char* at = data + (4 * v + i % 4) * size;
          int16_t q = 0;
          if (size == 2)
            std::memcpy(&q, at, 2);
          else
            q = static_cast<int8_t>(*at);
          if (i >= entries) {
            EXPECT_EQ(q, 0);
            continue;
          }
          const std::size_t k = first + i / 3, c = i % 3;
          EXPECT_EQ(float(q) / normalizer * scales[v][c], stored[v * count + k][c]) << k;
        }
    }
  };
  decode("_TRANSFER_LOW_", 0, 16, 5122, 2, kTransferNormalizer, scale);
  decode("_TRANSFER_HIGH_", 16, 49, 5120, 1, kHighTransferNormalizer, scaleHigh);
  std::filesystem::remove_all(dir);
}

// The GLB's exponents and packed steps refused where the writer never puts them: an exponent out
// of range, a non-zero fourth exponent, a non-zero padding step, a step beyond its limit.
TEST(QuantizedTransfer, TheGlbRefusesExponentsAndStepsItsWriterNeverWrites) {
  const std::filesystem::path dir = scratchDir();
  const std::string good = (dir / "good.glb").string(), bad = (dir / "bad.glb").string();
  writeBakedGlb(good, relightableBake(4));  // 25 coefficients: 3 padding entries in each list
  const test::GlbFile glb(good);
  const std::string bytes = test::readFile(good);
  const auto& attributes = glb.json["meshes"][0]["primitives"][0]["attributes"];
  // The file offset of component `component` of attribute `name`'s first element.
  const auto at = [&](const std::string& name, std::size_t component, std::size_t size) {
    const auto& accessor = glb.json["accessors"][attributes[name].get<int>()];
    const auto& view = glb.json["bufferViews"][accessor["bufferView"].get<int>()];
    return bytes.size() - glb.bin.size() + view["byteOffset"].get<std::size_t>() + component * size;
  };
  const struct {
    std::size_t offset, size;
    int16_t value;
    const char* message;
  } cases[] = {
      {at("_TRANSFER_EXPONENT", 0, 1), 1, 101,
       "transfer scale exponent 101 is outside [-126, 100]"},
      {at("_TRANSFER_EXPONENT", 1, 1), 1, -127, "transfer scale exponent -127 is outside"},
      {at("_TRANSFER_EXPONENT_HIGH", 3, 1), 1, 1, "_TRANSFER_EXPONENT_HIGH has a non-zero fourth"},
      {at("_TRANSFER_HIGH_6", 3, 1), 1, 5, "_TRANSFER_HIGH_6 has a non-zero padding component"},
      {at("_TRANSFER_LOW_0", 1, 2), 2, kTransferSteps + 1,
       "_TRANSFER_LOW_0 has a step count beyond"},
  };
  for (const auto& c : cases) {
    std::string edited = bytes;
    std::memcpy(&edited[c.offset], &c.value, c.size);  // little-endian: the low byte first
    std::ofstream(bad, std::ios::binary) << edited;
    try {
      readBakedGlb(bad);
      ADD_FAILURE() << c.message;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(c.message), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("bad.glb"), std::string::npos) << e.what();
    }
  }
  std::filesystem::remove_all(dir);
}

// A GLB of format 3 (one normalized VEC3 per coefficient, as written before the packed form) and
// the PLY of the same bake, both from that build (tests/mesh/legacy/), read to the same transfer,
// and so does the format 4 GLB written from it.
TEST(QuantizedTransfer, AFormatThreeGlbStillReads) {
  const std::string legacy = SSS_SOURCE_DIR "/tests/mesh/legacy/icosahedron_relightable_order4";
  const BakedPlyContents glb = readBakedGlb(legacy + "_format3.glb");
  const BakedPlyContents ply = readBakedPly(legacy + "_format3.ply");
  ASSERT_EQ(glb.baked.relightOrder, 4);
  ASSERT_EQ(glb.baked.relightTransfer.size(), 25 * glb.baked.mesh.vertexCount());
  EXPECT_EQ(glb.baked.relightTransfer, ply.baked.relightTransfer);
  const std::filesystem::path dir = scratchDir();
  const std::string rewritten = (dir / "format4.glb").string();
  writeBakedGlb(rewritten, glb.baked);
  EXPECT_EQ(test::GlbFile(rewritten).sssExtras()["format"], 4);
  EXPECT_EQ(readBakedGlb(rewritten).baked.relightTransfer, glb.baked.relightTransfer);
  std::filesystem::remove_all(dir);
}

// A format 2 file of order 4 (16 bits for every band, written before the high bands had their
// own scale) still reads as written; the same bake in format 3 agrees with it within the high
// bands' step. A high scale in a format 2 file, or none in format 3, is an error.
TEST(QuantizedTransfer, AFormatTwoFileOfOrderFourStillReads) {
  const std::string corpus = SSS_SOURCE_DIR "/tests/fuzz/corpus/baked_ply/";
  const BakedPlyContents before =
      readBakedPly(corpus + "icosahedron_relightable_order4_format2.ply");
  const BakedPlyContents after = readBakedPly(corpus + "icosahedron_relightable_order4.ply");
  ASSERT_EQ(before.baked.relightOrder, 4);
  const std::vector<glm::vec3>& a = before.baked.relightTransfer;
  const std::vector<glm::vec3>& b = after.baked.relightTransfer;
  ASSERT_EQ(a.size(), b.size());
  const std::size_t count = 25;
  double worstHigh = 0.0;
  bool someHighDiffer = false;
  for (std::size_t v = 0; v < a.size() / count; ++v)
    for (int c = 0; c < 3; ++c) {
      const float largestHigh = largestMagnitude(a, count, v, c, 16, count);
      for (std::size_t k = 0; k < count; ++k) {
        const float d = std::abs(a[v * count + k][c] - b[v * count + k][c]);
        if (k < 16) {
          EXPECT_LE(d, 1e-4f * std::abs(a[v * count][c]) + 1e-12f);
        }
        if (k >= 16 && largestHigh > 0.0f) worstHigh = std::max(worstHigh, double(d / largestHigh));
        someHighDiffer = someHighDiffer || (k >= 16 && d > 0.0f);
      }
    }
  EXPECT_TRUE(someHighDiffer);  // the format 2 file's 16-bit high bands are read as such
  EXPECT_LE(worstHigh, std::ldexp(1.0, -6) + 1e-4);
  const std::string format3 = test::readFile(corpus + "icosahedron_relightable_order4.ply");
  const auto mutated = [&](const std::string& from, const std::string& to) {
    std::string text = format3;
    for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + 1))
      text.replace(at, from.size(), to);
    const std::string path = std::filesystem::temp_directory_path() /
                             ("sss-test-" + std::to_string(::getpid()) + "-order4.ply");
    std::ofstream(path, std::ios::binary) << text;
    return path;
  };
  const std::string asFormat2 = mutated("sss format=3", "sss format=2");
  EXPECT_THROW(readBakedPly(asFormat2), Error);
  const std::string noHighScale = mutated("transfer_scale_high_", "transfer_scale_hxyz_");
  try {
    readBakedPly(noHighScale);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("without transfer_scale_high"), std::string::npos)
        << e.what();
  }
  std::filesystem::remove(asFormat2);
  std::filesystem::remove(noHighScale);
}

}  // namespace
}  // namespace sss
