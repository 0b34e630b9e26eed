#include "mesh/baked_ply.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>

#include "core/atomic_output.h"
#include "core/error.h"
#include "core/file_extension.h"
#include "core/format.h"
#include "core/srgb.h"
#include "mesh/ply_format.h"
#include "mesh/quantized_transfer.h"
#include "optics/exit_lobe.h"

namespace sss {

namespace {

static_assert(std::endian::native == std::endian::little,
              "the baked PLY writer copies floats as little-endian bytes");

// 2: a relightable bake's transfer quantized (quantized_transfer.h); 3: from order 4, its bands
// from 4 in 8 bits with a scale of their own. Other bakes are written as 1, which they still are;
// relightable bakes of orders 0-3 as 2.
constexpr int kPlyFormatVersion = 3;
constexpr int kQuantizedTransferVersion = 2;
constexpr int kHighBandsVersion = 3;

std::string triple(const glm::dvec3& v) {
  return shortestDecimal(v.x) + "," + shortestDecimal(v.y) + "," + shortestDecimal(v.z);
}

bool parseTriple(std::string_view text, glm::dvec3& v) {
  for (int i = 0; i < 3; ++i) {
    const std::size_t comma = i < 2 ? text.find(',') : text.size();
    if (comma == std::string_view::npos || !parseDecimal(text.substr(0, comma), v[i])) return false;
    text.remove_prefix(i < 2 ? comma + 1 : comma);
  }
  return true;
}

// sRGB transfer function of a linear value, clamped to [0, 1], quantized to 8 bits.
unsigned char srgb8(float linear) {
  return static_cast<unsigned char>(std::lround(linearToSrgb(linear) * 255.0f));
}

}  // namespace

double previewScaleFor(const BakedMesh& baked) {
  const std::vector<glm::vec3>& exitance = baked.exitance;
  if (exitance.empty()) return 0.0;
  if (baked.previewScale > 0.0) return baked.previewScale;
  std::vector<float> peak(exitance.size());
  for (std::size_t i = 0; i < exitance.size(); ++i) {
    peak[i] = std::max({exitance[i].x, exitance[i].y, exitance[i].z});
  }
  const std::size_t k = peak.size() * 99 / 100;
  std::nth_element(peak.begin(), peak.begin() + k, peak.end());
  return peak[k] > 0.0f ? 1.0 / peak[k] : 1.0;
}

void checkVertexValues(const std::string& path, const std::vector<glm::vec3>& values, std::size_t n,
                       const char* what) {
  if (!values.empty() && values.size() != n) {
    fail(path, std::string(what) + " has " + std::to_string(values.size()) + " values for " +
                   std::to_string(n) + " vertices");
  }
  for (std::size_t i = 0; i < values.size(); ++i) {
    const glm::vec3& v = values[i];
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) {
      fail(path, std::string(what) + " of vertex " + std::to_string(i) + " is not finite");
    }
  }
}

namespace {

// The far field's part of B and the exit lobe's slopes: one per vertex, finite, a far field only
// with slopes (its exits measured them), slopes where the exit lobe is defined (a slope below -1
// would make the interior radiance negative along the normal).
void checkExitLobe(const std::string& path, const BakedMesh& baked, std::size_t n) {
  checkVertexValues(path, baked.farExitance, n, "far_exitance");
  checkVertexValues(path, baked.exitSlope, n, "exit_slope");
  if (!baked.farExitance.empty() && baked.exitSlope.empty())
    fail(path, "has far_exitance without exit_slope");
  for (std::size_t i = 0; i < baked.exitSlope.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const double k = baked.exitSlope[i][c];
      if (k < ExitLobe::kMinSlope || k > ExitLobe::kMaxSlope)
        fail(path, "exit_slope of vertex " + std::to_string(i) + " is outside [" +
                       shortestDecimal(ExitLobe::kMinSlope) + ", " +
                       shortestDecimal(ExitLobe::kMaxSlope) + "]");
    }
}

// A relightable bake's values: an order in range, K transfer coefficients and one ratio per vertex,
// finite; none without an order.
void checkRelight(const std::string& path, const BakedMesh& baked, std::size_t n) {
  if (baked.relightOrder < 0) {
    if (!baked.relightTransfer.empty() || !baked.exitancePerRadiance.empty() ||
        !baked.radianceGain.empty() || !baked.escapeProbability.empty() ||
        !baked.gatherFrontHits.empty())
      fail(path, "has relight transfer values without relight_order");
    return;
  }
  const std::size_t words = n == 0 ? 0 : baked.gatherFrontHits.size() / n;
  if (baked.gatherFrontHits.size() != n * words || words % 4 != 0)
    fail(path, "gather_hits: not whole groups of four 16-bit words per vertex");
  if (baked.relightOrder > kMaxStoredRelightOrder)
    fail(path, "relight_order " + std::to_string(baked.relightOrder) + " is above " +
                   std::to_string(kMaxStoredRelightOrder));
  checkVertexValues(path, baked.relightTransfer, n * baked.relightCount(), "transfer");
  if (baked.relightTransfer.size() != n * baked.relightCount())
    fail(path, "relight_order " + std::to_string(baked.relightOrder) + " without its transfer");
  checkVertexValues(path, baked.radianceGain, n, "radiance_gain");
  checkVertexValues(path, baked.exitancePerRadiance, n, "exitance_per_radiance");
  checkVertexValues(path, baked.escapeProbability, n, "escape_probability");
  if (baked.exitancePerRadiance.size() != n || baked.radianceGain.size() != n)
    fail(path, "relight transfer without radiance_gain and exitance_per_radiance");
  if (baked.relightTransport.empty() ||
      baked.relightTransport.find_first_of(" \t\r\n") != std::string::npos)
    fail(path, "relight transfer without a one-word relight_transport");
}

}  // namespace

void checkBakedMesh(const std::string& path, const BakedMesh& baked) {
  const TriangleMesh& mesh = baked.mesh;
  const std::size_t nv = mesh.positions.size();
  if (mesh.normals.size() != nv) fail(path, "mesh normals missing");
  if (mesh.triangles.empty()) fail(path, "mesh has no triangles");
  for (const glm::uvec3& t : mesh.triangles) {
    if (t.x >= nv || t.y >= nv || t.z >= nv) fail(path, "triangle index out of range");
  }
  checkVertexValues(path, mesh.positions, nv, "position");
  checkVertexValues(path, baked.irradiance, nv, "irradiance");
  checkVertexValues(path, baked.exitance, nv, "exitance");
  checkVertexValues(path, baked.radianceNormal, nv, "radiance_normal");
  checkExitLobe(path, baked, nv);
  checkRelight(path, baked, nv);
}

namespace {

template <class T>
void put(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.append(bytes, sizeof(T));
}

// The names that go into the header as text: one word, one line each.
void checkHeaderText(const std::string& path, const BakedMesh& baked) {
  if (baked.materialName.find_first_of(" \t\r\n=") != std::string::npos) {
    fail(path, "material name '" + baked.materialName + "' contains a space or '='");
  }
  for (const std::string& c : baked.extraComments) {
    if (c.find_first_of("\r\n") != std::string::npos) fail(path, "comment spans several lines");
  }
}

// Which optional per-vertex values the file carries.
struct BakedFields {
  explicit BakedFields(const BakedMesh& baked)
      : irradiance(!baked.irradiance.empty()),
        exitance(!baked.exitance.empty()),
        radianceNormal(!baked.radianceNormal.empty()),
        farField(!baked.farExitance.empty()),
        exitSlope(!baked.exitSlope.empty()),
        relightCount(baked.relightCount()),
        escape(!baked.escapeProbability.empty()),
        frontHitWords(baked.gatherFrontHitWords()) {}
  bool irradiance, exitance, radianceNormal, farField, exitSlope;
  int relightCount;
  bool escape;
  std::size_t frontHitWords;
  // Bytes of one vertex record: position and normal, then the optional fields in order.
  std::size_t vertexBytes() const {
    return 24 + (irradiance ? 12 : 0) + (exitance ? 15 : 0) + (radianceNormal ? 12 : 0) +
           (farField ? 12 : 0) + (exitSlope ? 12 : 0) +
           (relightCount > 0 ? 12 + transferBytes() + 24 : 0) + (escape ? 12 : 0) +
           2 * frontHitWords;
  }
  std::size_t transferBytes() const {
    const std::size_t count = std::size_t(relightCount);
    const std::size_t low = std::min(count, kShortTransferCoefficients);
    return 6 * low + (hasHighBands(count) ? 12 + 3 * (count - low) : 0);
  }
};

// The "comment sss" lines: format version, material, scale and flags, then the caller's.
void appendComments(std::string& out, const BakedMesh& baked, const BakedFields& fields,
                    double scale) {
  const int version = baked.relightOrder < 0                            ? 1
                      : hasHighBands(std::size_t(baked.relightCount())) ? kHighBandsVersion
                                                                        : kQuantizedTransferVersion;
  out += "comment sss format=" + std::to_string(version) + "\n";
  if (!baked.materialName.empty()) {
    out += "comment sss material=" + baked.materialName + "\n";
    out += "comment sss sigma_a=" + triple(baked.sigmaA) + "\n";
    out += "comment sss sigma_s_prime=" + triple(baked.sigmaSPrime) + "\n";
    out += "comment sss eta=" + shortestDecimal(baked.eta) + "\n";
  }
  out += "comment sss mm_per_unit=" + shortestDecimal(baked.mmPerUnit) + "\n";
  if (fields.exitance) out += "comment sss preview_scale=" + shortestDecimal(scale) + "\n";
  if (baked.meshChecked) out += "comment sss checked=1\n";
  if (baked.unscatteredTraced) out += "comment sss unscattered=1\n";
  if (baked.relightOrder >= 0)
    out += "comment sss relight_order=" + std::to_string(baked.relightOrder) +
           "\ncomment sss relight_transport=" + baked.relightTransport + "\n";
  for (const std::string& c : baked.extraComments) out += "comment " + c + "\n";
}

// The vertex element's properties, in the order appendVertex writes them.
void appendVertexProperties(std::string& out, std::size_t vertices, const BakedFields& fields) {
  out += "element vertex " + std::to_string(vertices) + "\n";
  for (const char* p : {"x", "y", "z", "nx", "ny", "nz"})
    out += std::string("property float ") + p + "\n";
  if (fields.irradiance)
    out +=
        "property float irradiance_r\nproperty float irradiance_g\nproperty float irradiance_b\n";
  if (fields.exitance) {
    out += "property float exitance_r\nproperty float exitance_g\nproperty float exitance_b\n";
    out += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  }
  if (fields.radianceNormal)
    out +=
        "property float radiance_normal_r\nproperty float radiance_normal_g\n"
        "property float radiance_normal_b\n";
  if (fields.farField)
    out +=
        "property float far_exitance_r\nproperty float far_exitance_g\n"
        "property float far_exitance_b\n";
  if (fields.exitSlope)
    out +=
        "property float exit_slope_r\nproperty float exit_slope_g\nproperty float exit_slope_b\n";
  if (fields.relightCount > 0)
    out +=
        "property float transfer_scale_r\nproperty float transfer_scale_g\n"
        "property float transfer_scale_b\n";
  if (hasHighBands(std::size_t(fields.relightCount)))
    out +=
        "property float transfer_scale_high_r\nproperty float transfer_scale_high_g\n"
        "property float transfer_scale_high_b\n";
  for (int k = 0; k < fields.relightCount; ++k)
    for (const char* c : {"_r", "_g", "_b"}) {
      const bool high = std::size_t(k) >= kShortTransferCoefficients;
      out += std::string(high ? "property char transfer" : "property short transfer") +
             std::to_string(k) + c + "\n";
    }
  for (const char* name : {"radiance_gain", "exitance_per_radiance", "escape_probability"}) {
    if (fields.relightCount == 0 || (std::string(name) == "escape_probability" && !fields.escape))
      continue;
    for (const char* c : {"_r", "_g", "_b"})
      out += std::string("property float ") + name + c + "\n";
  }
  for (std::size_t w = 0; w < fields.frontHitWords; ++w)
    out += "property ushort gather_hits_" + std::to_string(w) + "\n";
}

// Vertex i's record: floats, the exitance's 8-bit sRGB preview colour at `scale` and the
// quantized transfer.
void appendVertex(std::string& out, const BakedMesh& baked, const BakedFields& fields, double scale,
                  const QuantizedTransfer& transfer, std::size_t i) {
  for (int k = 0; k < 3; ++k) put(out, baked.mesh.positions[i][k]);
  for (int k = 0; k < 3; ++k) put(out, baked.mesh.normals[i][k]);
  if (fields.irradiance) {
    for (int k = 0; k < 3; ++k) put(out, baked.irradiance[i][k]);
  }
  if (fields.exitance) {
    for (int k = 0; k < 3; ++k) put(out, baked.exitance[i][k]);
    for (int k = 0; k < 3; ++k) {
      put(out, srgb8(static_cast<float>(scale * baked.exitance[i][k])));
    }
  }
  if (fields.radianceNormal) {
    for (int k = 0; k < 3; ++k) put(out, baked.radianceNormal[i][k]);
  }
  if (fields.farField) {
    for (int k = 0; k < 3; ++k) put(out, baked.farExitance[i][k]);
  }
  if (fields.exitSlope) {
    for (int k = 0; k < 3; ++k) put(out, baked.exitSlope[i][k]);
  }
  const std::size_t count = static_cast<std::size_t>(fields.relightCount);
  if (count > 0)
    for (int k = 0; k < 3; ++k) put(out, transfer.scale[i][k]);
  if (!transfer.scaleHigh.empty())
    for (int k = 0; k < 3; ++k) put(out, transfer.scaleHigh[i][k]);
  for (std::size_t t = 0; t < count; ++t)
    for (int k = 0; k < 3; ++k) {
      const std::int16_t q = transfer.values[i * count + t][k];
      if (t < kShortTransferCoefficients)
        put(out, q);
      else
        put(out, static_cast<std::int8_t>(q));  // |q| <= 127
    }
  if (count > 0) {
    for (int k = 0; k < 3; ++k) put(out, baked.radianceGain[i][k]);
    for (int k = 0; k < 3; ++k) put(out, baked.exitancePerRadiance[i][k]);
  }
  if (fields.escape)
    for (int k = 0; k < 3; ++k) put(out, baked.escapeProbability[i][k]);
  for (std::size_t w = 0; w < fields.frontHitWords; ++w)
    put(out, baked.gatherFrontHits[i * fields.frontHitWords + w]);
}

// Triangles as PLY lists: a count of 3, then three int32 indices.
void appendFaces(std::string& out, const std::vector<glm::uvec3>& triangles) {
  for (const glm::uvec3& t : triangles) {
    put(out, static_cast<unsigned char>(3));
    for (int k = 0; k < 3; ++k) put(out, static_cast<std::int32_t>(t[k]));
  }
}

// The whole file at once, through a temporary renamed into place: a reader never sees half.
void writeAtomically(const std::string& path, const std::string& bytes) {
  AtomicOutput output(path);
  {
    std::ofstream file(output.tempPath(), std::ios::binary);
    if (!file) fail(path, "cannot create output file");
    file.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    file.close();
    if (!file) fail(path, "write failed (disk full?)");
  }
  output.commit();
}

}  // namespace

void writeBakedPly(const std::string& path, const BakedMesh& baked) {
  checkBakedMesh(path, baked);
  checkHeaderText(path, baked);
  const TriangleMesh& mesh = baked.mesh;
  const std::size_t nv = mesh.positions.size();
  const BakedFields fields(baked);
  const double scale = previewScaleFor(baked);

  std::string out = "ply\nformat binary_little_endian 1.0\n";
  appendComments(out, baked, fields, scale);
  appendVertexProperties(out, nv, fields);
  out += "element face " + std::to_string(mesh.triangles.size()) + "\n";
  out += "property list uchar int vertex_indices\nend_header\n";

  const QuantizedTransfer transfer =
      quantizeTransfer(path, baked.relightTransfer, std::size_t(fields.relightCount));
  out.reserve(out.size() + nv * fields.vertexBytes() + mesh.triangles.size() * 13);
  for (std::size_t i = 0; i < nv; ++i) appendVertex(out, baked, fields, scale, transfer, i);
  appendFaces(out, mesh.triangles);
  writeAtomically(path, out);
}

namespace {

using Keys = std::map<std::string, std::string>;

// The known "sss key=value" comments; every other comment goes to `extra` verbatim.
Keys sssKeys(const std::vector<std::string>& comments, std::vector<std::string>& extra) {
  Keys keys;
  for (const std::string& c : comments) {
    const std::size_t eq = c.find('=');
    if (c.rfind("sss ", 0) == 0 && eq != std::string::npos && c.find(' ', 4) == std::string::npos) {
      const std::string key = c.substr(4, eq - 4);
      static const char* const known[] = {
          "format",      "material",      "sigma_a",          "sigma_s_prime",
          "eta",         "mm_per_unit",   "preview_scale",    "checked",
          "unscattered", "relight_order", "relight_transport"};
      if (std::find(std::begin(known), std::end(known), key) != std::end(known)) {
        keys[key] = c.substr(eq + 1);
        continue;
      }
    }
    extra.push_back(c);
  }
  return keys;
}

// The format version, material, units and preview scale of those comments into result.
void readKeys(const std::string& path, Keys& keys, BakedPlyContents& result) {
  BakedMesh& baked = result.baked;
  auto bad = [&](const std::string& key) {
    fail(path, "bad 'comment sss " + key + "=" + keys[key] + "'");
  };
  if (keys.count("format")) {
    double version = 0;
    if (!parseDecimal(keys["format"], version)) bad("format");
    if (version > kPlyFormatVersion) {
      fail(path, "baked PLY format " + keys["format"] + " is newer than this program reads (" +
                     std::to_string(kPlyFormatVersion) + ")");
    }
  }
  const int materialKeys = int(keys.count("material")) + int(keys.count("sigma_a")) +
                           int(keys.count("sigma_s_prime")) + int(keys.count("eta"));
  if (materialKeys > 0 && materialKeys < 4) {
    fail(path, "incomplete material comments (need sss material, sigma_a, sigma_s_prime, eta)");
  }
  if (materialKeys == 4) {
    result.hasMaterial = true;
    baked.materialName = keys["material"];
    if (!parseTriple(keys["sigma_a"], baked.sigmaA)) bad("sigma_a");
    if (!parseTriple(keys["sigma_s_prime"], baked.sigmaSPrime)) bad("sigma_s_prime");
    if (!parseDecimal(keys["eta"], baked.eta)) bad("eta");
  }
  if (keys.count("mm_per_unit")) {
    result.hasUnits = true;
    if (!parseDecimal(keys["mm_per_unit"], baked.mmPerUnit) || baked.mmPerUnit <= 0) {
      bad("mm_per_unit");
    }
  }
  if (keys.count("preview_scale") && !parseDecimal(keys["preview_scale"], baked.previewScale)) {
    bad("preview_scale");
  }
  if (keys.count("checked")) {
    if (keys["checked"] != "1") bad("checked");
    baked.meshChecked = true;
  }
  if (keys.count("unscattered")) {
    if (keys["unscattered"] != "1") bad("unscattered");
    baked.unscatteredTraced = true;
  }
  if (keys.count("relight_order")) {
    double order = -1;
    if (!parseDecimal(keys["relight_order"], order) || order != std::floor(order) || order < 0 ||
        order > kMaxStoredRelightOrder)
      bad("relight_order");
    baked.relightOrder = static_cast<int>(order);
    result.hasRelight = true;
    baked.relightTransport = keys["relight_transport"];
  } else if (keys.count("relight_transport")) {
    bad("relight_transport");
  }
}

// Per-vertex values base_r/g/b: all three channels (present = true) or none (empty).
std::vector<glm::vec3> readChannels(const std::string& path, const ply::PlyMesh& ply,
                                    const std::string& base, bool& present) {
  const std::vector<float>* c[3];
  int found = 0;
  const char* suffix[3] = {"_r", "_g", "_b"};
  for (int k = 0; k < 3; ++k) {
    auto it = ply.vertexScalars.find(base + suffix[k]);
    c[k] = it == ply.vertexScalars.end() ? nullptr : &it->second;
    found += c[k] != nullptr;
  }
  std::vector<glm::vec3> values;
  if (found == 0) return values;
  if (found < 3) fail(path, "has only some of " + base + "_r/g/b");
  present = true;
  values.resize(c[0]->size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    values[i] = {(*c[0])[i], (*c[1])[i], (*c[2])[i]};
  }
  return values;
}

// A stored transfer coefficient: an integer of at most `limit` (transferStepLimit).
std::array<int16_t, 3> transferSteps(const std::string& path, const std::string& name,
                                     const glm::vec3& q, int limit) {
  std::array<int16_t, 3> out{};
  for (int c = 0; c < 3; ++c) {
    if (!(std::abs(q[c]) <= float(limit)) || q[c] != std::floor(q[c]))
      fail(path, name + " is not a step count of at most " + std::to_string(limit));
    out[c] = int16_t(q[c]);
  }
  return out;
}

// gather_hits_0, gather_hits_1, ... (16-bit words; whole groups of four) of n vertices, at
// [vertex * words + w]; empty where there are none.
std::vector<uint16_t> readFrontHits(const std::string& path, const ply::PlyMesh& ply,
                                    std::size_t n) {
  std::vector<const std::vector<float>*> columns;
  for (;;) {
    auto it = ply.vertexScalars.find("gather_hits_" + std::to_string(columns.size()));
    if (it == ply.vertexScalars.end()) break;
    columns.push_back(&it->second);
  }
  if (columns.size() % 4 != 0)
    fail(path, "gather_hits: " + std::to_string(columns.size()) +
                   " words per vertex, not whole groups of four");
  std::vector<uint16_t> words(n * columns.size());
  for (std::size_t w = 0; w < columns.size(); ++w)
    for (std::size_t i = 0; i < n; ++i) {
      const float x = (*columns[w])[i];
      if (!(x >= 0.0f && x <= 65535.0f) || x != std::floor(x))
        fail(path, "gather_hits_" + std::to_string(w) + " is not a 16-bit word");
      words[i * columns.size() + w] = uint16_t(x);
    }
  return words;
}

// A relightable bake's transfer_scale, transfer0.. and exitance_per_radiance, all of them with
// relight_order.
void readRelight(const std::string& path, const ply::PlyMesh& ply, int formatVersion,
                 BakedPlyContents& result, BakedVertexValues& values) {
  bool ratio = false, gain = false, escape = false;
  values.exitancePerRadiance = readChannels(path, ply, "exitance_per_radiance", ratio);
  values.radianceGain = readChannels(path, ply, "radiance_gain", gain);
  values.escapeProbability = readChannels(path, ply, "escape_probability", escape);
  if (!result.hasRelight) {
    const bool transfer =
        ply.vertexScalars.count("transfer0_r") || ply.vertexScalars.count("transfer0_g") ||
        ply.vertexScalars.count("transfer0_b") || ply.vertexScalars.count("gather_hits_0");
    if (ratio || gain || escape || transfer)
      fail(path, "has relight transfer values without relight_order");
    return;
  }
  if (!ratio || !gain)
    fail(path, "relight_order without radiance_gain_r/g/b and exitance_per_radiance_r/g/b");
  const int count = result.baked.relightCount();
  const std::size_t n = values.exitancePerRadiance.size();
  // Quantized (quantized_transfer.h) with transfer_scale; floats in format 1.
  bool scaled = false;
  QuantizedTransfer quantized;
  quantized.scale = readChannels(path, ply, "transfer_scale", scaled);
  if (scaled != (formatVersion >= kQuantizedTransferVersion))
    fail(path, scaled
                   ? "transfer_scale_r/g/b in a format " + std::to_string(formatVersion) + " file"
                   : "relight_order without transfer_scale_r/g/b");
  checkTransferScales(path, quantized.scale);
  bool high = false;
  quantized.scaleHigh = readChannels(path, ply, "transfer_scale_high", high);
  if (high != (formatVersion >= kHighBandsVersion && hasHighBands(std::size_t(count))))
    fail(path, high ? "transfer_scale_high_r/g/b in a format " + std::to_string(formatVersion) +
                          " file of order " + std::to_string(result.baked.relightOrder)
                    : "relight_order above 3 without transfer_scale_high_r/g/b");
  checkTransferScales(path, quantized.scaleHigh);
  std::vector<glm::vec3> floats(scaled ? 0 : n * count);
  quantized.values.resize(scaled ? n * count : 0);
  for (int k = 0; k < count; ++k) {
    bool present = false;
    const std::string name = "transfer" + std::to_string(k);
    const std::vector<glm::vec3> channel = readChannels(path, ply, name, present);
    if (!present) fail(path, "relight_order without " + name + "_r/g/b");
    for (std::size_t i = 0; i < n; ++i) {
      if (scaled)
        quantized.values[i * count + k] =
            transferSteps(path, name, channel[i], transferStepLimit(std::size_t(k), high));
      else
        floats[i * count + k] = channel[i];
    }
  }
  values.relightTransfer =
      scaled ? dequantizeTransfer(quantized, std::size_t(count)) : std::move(floats);
  values.gatherFrontHits = readFrontHits(path, ply, n);
}

}  // namespace

BakedPlyContents readBakedPly(const std::string& path) {
  BakedPlyContents result;
  if (lowerExtension(path) != "ply") {
    MeshParts parts;
    result.baked.mesh = loadMesh(path, &result.report, &parts);
    if (parts.mmPerUnit > 0.0) {  // glTF: metres
      result.hasUnits = true;
      result.baked.mmPerUnit = parts.mmPerUnit;
    }
    return result;
  }
  ply::PlyMesh ply = ply::readPly(path);
  BakedMesh& baked = result.baked;
  Keys keys = sssKeys(ply.comments, baked.extraComments);
  readKeys(path, keys, result);
  BakedVertexValues values;
  values.irradiance = readChannels(path, ply, "irradiance", result.hasIrradiance);
  values.exitance = readChannels(path, ply, "exitance", result.hasExitance);
  values.radianceNormal = readChannels(path, ply, "radiance_normal", result.hasRadianceNormal);
  values.farExitance = readChannels(path, ply, "far_exitance", result.hasFarField);
  values.exitSlope = readChannels(path, ply, "exit_slope", result.hasExitSlope);
  if (!result.hasExitSlope)  // the name before the escape walks measured a lobe too
    values.exitSlope = readChannels(path, ply, "far_exit_slope", result.hasExitSlope);
  if (result.hasFarField && !result.hasExitSlope) fail(path, "has far_exitance without exit_slope");
  double version = 1.0;  // checked by readKeys
  if (keys.count("format")) parseDecimal(keys["format"], version);
  readRelight(path, ply, int(version), result, values);

  cleanBakedMesh(path, ply::takeMesh(ply, result.report), values, result);
  return result;
}

void cleanBakedMesh(const std::string& path, RawMesh raw, const BakedVertexValues& values,
                    BakedPlyContents& contents) {
  BakedMesh& baked = contents.baked;
  std::vector<unsigned> origin;
  baked.mesh = cleanMesh(path, std::move(raw), &contents.report, &origin);
  const std::size_t frontHitWords =
      values.gatherFrontHits.size() / std::max<std::size_t>(values.radianceGain.size(), 1);
  for (unsigned o : origin) {
    if (contents.hasIrradiance) baked.irradiance.push_back(values.irradiance[o]);
    if (contents.hasExitance) baked.exitance.push_back(values.exitance[o]);
    if (contents.hasRadianceNormal) baked.radianceNormal.push_back(values.radianceNormal[o]);
    if (contents.hasFarField) baked.farExitance.push_back(values.farExitance[o]);
    if (contents.hasExitSlope) baked.exitSlope.push_back(values.exitSlope[o]);
    if (contents.hasRelight) {
      const std::size_t count = baked.relightCount();
      const auto first = values.relightTransfer.begin() + std::ptrdiff_t(o * count);
      baked.relightTransfer.insert(baked.relightTransfer.end(), first,
                                   first + std::ptrdiff_t(count));
      baked.radianceGain.push_back(values.radianceGain[o]);
      baked.exitancePerRadiance.push_back(values.exitancePerRadiance[o]);
      if (!values.escapeProbability.empty())
        baked.escapeProbability.push_back(values.escapeProbability[o]);
      const auto hits = values.gatherFrontHits.begin() + std::ptrdiff_t(o * frontHitWords);
      baked.gatherFrontHits.insert(baked.gatherFrontHits.end(), hits,
                                   hits + std::ptrdiff_t(frontHitWords));
    }
  }
  checkVertexValues(path, baked.irradiance, origin.size(), "irradiance");
  checkVertexValues(path, baked.exitance, origin.size(), "exitance");
  checkVertexValues(path, baked.radianceNormal, origin.size(), "radiance_normal");
  checkExitLobe(path, baked, origin.size());
  checkRelight(path, baked, origin.size());
  if (baked.meshChecked) contents.report.warnings.clear();  // sss-bake showed them
}

}  // namespace sss
