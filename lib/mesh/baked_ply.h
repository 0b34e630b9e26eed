// The baked-mesh file: a binary little-endian PLY with per-vertex irradiance E and exitance B,
// an 8-bit sRGB preview, and the material and units as header comments, so that sss-render needs
// no repeat of them. A standard PLY: general readers (MeshLab, Blender) skip the unknown float
// properties and show red/green/blue as vertex colours; OpenMesh's reader is tested on it.
//
//   ply
//   format binary_little_endian 1.0
//   comment sss format=1
//   comment sss material=marble
//   comment sss sigma_a=0.0021,0.0041,0.0071      (per mm, r,g,b)
//   comment sss sigma_s_prime=2.19,2.62,3        (per mm)
//   comment sss eta=1.3
//   comment sss mm_per_unit=1000
//   comment sss preview_scale=0.8                (preview sRGB = encode(scale * exitance))
//   comment sss checked=1                        (the mesh passed sss-bake's cleanup: readers
//                                                 do not repeat its warnings)
//   comment sss unscattered=1                    (the bake traced light that crosses the object
//                                                 unscattered, transport/unscattered_light.h: in
//                                                 radiance_normal; sss-render draws it)
//   comment <each extraComments line>
//   (numbers: the shortest decimal that reads back to the same double; the material lines only
//   when materialName is set, preview_scale only with exitance)
//   element vertex N
//   property float x, y, z, nx, ny, nz
//   property float irradiance_r, irradiance_g, irradiance_b   (when irradiance is given)
//   property float exitance_r, exitance_g, exitance_b         (when exitance is given)
//   property uchar red, green, blue                           (with exitance)
//   property float radiance_normal_r, radiance_normal_g, radiance_normal_b
//                  (when given: the radiance leaving along the vertex normal, under the exit
//                  model of the bake, so that a bake compares with a reference in radiance)
//   property float far_exitance_r, far_exitance_g, far_exitance_b
//                  (when the bake traced its far field, transport/far_field.h: the part of B that
//                  light paths carried from afar; only with exit_slope)
//   property float exit_slope_r, exit_slope_g, exit_slope_b
//                  (the slope k of the exit lobe, optics/exit_lobe.h, which all of B leaves with:
//                  sss-render draws B through it; measured by the far field's exits or the escape
//                  walks'; absent: the normalized model. Files written before read their
//                  far_exit_slope_r/g/b here)
//   property float transfer0_r, transfer0_g, transfer0_b, ... transfer<K-1>_b
//   property float radiance_gain_r, radiance_gain_g, radiance_gain_b
//   property float exitance_per_radiance_r, exitance_per_radiance_g, exitance_per_radiance_b
//   property float escape_probability_r, escape_probability_g, escape_probability_b
//                  (a relightable bake, sss-bake --relightable, with "comment sss
//                  relight_order=N", K = (N + 1)^2, and "comment sss relight_transport=..."
//                  (bake/relight.h): under an environment with real SH coefficients L_k
//                  (irradiance/spherical_harmonics.h, index l (l + 1) + m) the radiance along the
//                  normal is radiance_gain (sum_k transfer<k> L_k) per channel, and B is that
//                  times exitance_per_radiance; escape_probability only with the escape energy
//                  model; docs/relighting.md)
//   element face M
//   property list uchar int vertex_indices
//   end_header
//
// One property per line in the file. OpenMesh's writer cannot write header comments, hence our
// own writer.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "mesh/load_mesh.h"
#include "mesh/triangle_mesh.h"

namespace sss {

// The highest relight order a baked file may declare (the readers' bound;
// irradiance/spherical_harmonics.h's kMaxOrder).
inline constexpr int kMaxStoredRelightOrder = 16;

struct BakedMesh {
  TriangleMesh mesh;
  std::vector<glm::vec3> irradiance;      // E per vertex (empty: not written/not present)
  std::vector<glm::vec3> exitance;        // B per vertex (empty: not written/not present)
  std::vector<glm::vec3> radianceNormal;  // L along the normal per vertex (idem)
  // The traced far field's part of B (empty: not traced) and the exit lobe's slope k (empty: the
  // normalized model), per vertex; a far field only with slopes.
  std::vector<glm::vec3> farExitance, exitSlope;
  std::string materialName;     // no spaces or '='
  glm::dvec3 sigmaA{0.0};       // absorption, per mm
  glm::dvec3 sigmaSPrime{0.0};  // reduced scattering, per mm
  double eta = 1.0;             // relative index of refraction
  double mmPerUnit = 1.0;       // millimetres per mesh unit
  // Preview colour = sRGB(previewScale * exitance). <= 0 on write: auto-exposed so that the
  // 99th percentile of max(exitance) maps to 1; the scale used is stored in the header.
  double previewScale = 0.0;
  std::vector<std::string> extraComments;  // written as "comment <line>"; single lines
  // The mesh went through loadMesh's validation and cleanup, whose warnings were shown then
  // (sss-bake): recorded in the file, so that reading it back does not repeat them.
  bool meshChecked = false;
  // The bake found light that crosses the object unscattered and traced it (radiance_normal holds
  // it along the normals; sss-render draws it, view-dependent, by default).
  bool unscatteredTraced = false;
  // A relightable bake (relightOrder >= 0): per vertex (relightOrder + 1)^2 SH transfer
  // coefficients of the radiance along the normal, per channel, at [vertex * K + k], and B / L.
  int relightOrder = -1;
  std::vector<glm::vec3> relightTransfer;
  std::vector<glm::vec3> radianceGain, exitancePerRadiance;
  std::vector<glm::vec3> escapeProbability;  // may be empty
  // Which of the bounces' gather rays met the front of a surface: the same number of 16-bit
  // words per vertex, a multiple of 4 (transport/interreflection.h, frontHits); may be empty.
  std::vector<uint16_t> gatherFrontHits;
  std::string relightTransport;  // bake/relight.h's key; one word
  int relightCount() const {
    return relightOrder < 0 ? 0 : (relightOrder + 1) * (relightOrder + 1);
  }
  // gatherFrontHits' words per vertex (0 without them or without vertices).
  std::size_t gatherFrontHitWords() const {
    return mesh.positions.empty() ? 0 : gatherFrontHits.size() / mesh.positions.size();
  }
};

// What every baked-mesh writer checks first (one value per vertex or none, finite values, indices
// in range, at least one triangle, normals present). Throws Error naming `path`.
void checkBakedMesh(const std::string& path, const BakedMesh& baked);

// The preview exposure: baked.previewScale when > 0, else the scale that maps the 99th
// percentile of max(r, g, b) of the exitance to 1 (1 when that is 0). 0 without exitance.
double previewScaleFor(const BakedMesh& baked);

// Throws Error naming `path` when `values` is neither empty nor one per vertex (n), or holds a
// non-finite value.
void checkVertexValues(const std::string& path, const std::vector<glm::vec3>& values, std::size_t n,
                       const char* what);

// Writes `baked` (exitance and irradiance must have one value per vertex, or be empty: zeros
// are not invented, the properties are left out) through AtomicOutput. Throws Error.
void writeBakedPly(const std::string& path, const BakedMesh& baked);

// What readBakedPly found.
struct BakedPlyContents {
  BakedMesh baked;
  bool hasIrradiance = false;      // irradiance_r/g/b present
  bool hasExitance = false;        // exitance_r/g/b present
  bool hasRadianceNormal = false;  // radiance_normal_r/g/b present
  bool hasFarField = false;        // far_exitance_r/g/b present
  bool hasExitSlope = false;       // exit_slope_r/g/b (or far_exit_slope_r/g/b) present
  bool hasRelight = false;         // relight_order, transfer*_r/g/b, exitance_per_radiance_r/g/b
  bool hasMaterial = false;        // "sss material/sigma_a/sigma_s_prime/eta" comments present
  bool hasUnits = false;           // "sss mm_per_unit" comment present
  MeshReport report;               // cleanup of the mesh part; no warnings when baked.meshChecked
};

// Reads a baked PLY back bit-exactly. Any other mesh file (plain PLY, OBJ, ...) loads too, with
// the has* flags false, so the caller can say e.g. "missing exitance_r/g/b: run sss-bake".
// The mesh goes through the same validation and cleanup as loadMesh (per-vertex values follow
// their vertices); a file that sss-bake wrote comes back unchanged.
BakedPlyContents readBakedPly(const std::string& path);

// Per-vertex values as a reader found them, in the file's vertex order (empty: absent).
struct BakedVertexValues {
  std::vector<glm::vec3> irradiance, exitance, radianceNormal, farExitance, exitSlope;
  std::vector<glm::vec3> relightTransfer;  // [vertex * K + k]
  std::vector<glm::vec3> radianceGain, exitancePerRadiance, escapeProbability;
  std::vector<uint16_t> gatherFrontHits;  // [vertex * words + w]
};

// The end of every baked-mesh reader: `raw` through cleanMesh into contents.baked.mesh, the
// per-vertex values (those the has* flags say are present) following their vertices, and no
// cleanup warnings when contents.baked.meshChecked (sss-bake showed them).
void cleanBakedMesh(const std::string& path, RawMesh raw, const BakedVertexValues& values,
                    BakedPlyContents& contents);

}  // namespace sss
