// The material-interface study (docs/accuracy.md, "Several materials"): a sphere whose upper half
// is one material and lower half another, under uniform light, baked with sss-bake's defaults
// (--material-map, bake/material_parts.h) against a Monte Carlo of the two media itself.
//
//   material_interface_study OUT_DIR [--walks N]
//
// The reference knows nothing of the bake: backward random walks in the exact sphere (radius R,
// the interface the plane z = 0, both media of eta 1.3 so the interface does not refract), free
// flights by delta tracking against the larger sigma_t of the two (Woodcock; a tentative
// collision is real with probability sigma_t(x) / sigma_max, so the medium may change anywhere
// along a flight), isotropic scattering with sigma_s = sigma_s' (g = 0), analog absorption, exact
// Fresnel at the sphere (reflection with probability F_r, total internal reflection included).
// It tallies the radiance leaving along the normal directly: a walk starts at the surface point
// along -n with weight F_t(1), and each escape adds the environment's radiance (1). Under uniform
// light the sphere is symmetric about z, so the reference is taken at one point per ring of the
// UV sphere (polar angle theta), the bake as the mean over that ring's vertices.
//
// OUT_DIR/material_interface.csv: per scene, per ring: theta, the reference's radiance along the
// normal and its standard error per channel, the bake's (mixed), and the two one-material bakes'
// (the object all of the upper or all of the lower material).
// OUT_DIR/material_interface_summary.csv, per scene, relative RMS over the sphere's area (the
// reference's noise removed): bake_rms, the mixed bake against the reference;
// homogeneous_model_rms, the one-material bakes against the one-material objects' references
// (the models' own error, which the mix inherits); interface_measured, the mixed bake's error
// beyond that (against the same difference of references): what the border adds;
// interface_predicted and predicted_total, the bake's JSON (estimated_error.model.
// material_interface, estimated_error.total).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "bake/bake.h"
#include "bake/bake_report.h"
#include "bake/bake_settings.h"
#include "bake/material_map.h"
#include "core/parallel.h"
#include "core/random.h"
#include "core/sampling.h"
#include "core/timer.h"
#include "material/material.h"
#include "optics/fresnel.h"
#include "support/uv_sphere.h"

namespace sss {
namespace {

constexpr int kSegments = 64, kRings = 32;  // the equator (z = 0) is ring kRings / 2
constexpr double kEta = 1.3;

struct Scene {
  std::string name;
  std::string upper, lower;  // material presets
  double radiusMm;
};

const Scene kScenes[] = {{"skin1_ketchup_r10", "skin1", "ketchup", 10.0},
                         {"marble_skin1_r5", "marble", "skin1", 5.0},
                         {"skimmilk_ketchup_r10", "skimmilk", "ketchup", 10.0}};

// One channel of the two media, per mm.
struct TwoMedia {
  double sigmaT[2], albedo[2];  // [0]: z > 0, [1]: z <= 0
  double majorant;
};

TwoMedia twoMedia(const Material& upper, const Material& lower, int c) {
  TwoMedia m{};
  const Material* both[2] = {&upper, &lower};
  for (int k = 0; k < 2; ++k) {
    m.sigmaT[k] = both[k]->sigmaA[c] + both[k]->sigmaSPrime[c];
    m.albedo[k] = both[k]->sigmaSPrime[c] / m.sigmaT[k];
  }
  m.majorant = std::max(m.sigmaT[0], m.sigmaT[1]);
  return m;
}

glm::dvec3 uniformSphere(Pcg32& rng) {
  const double z = 1.0 - 2.0 * rng.uniformDouble(), phi = 2.0 * M_PI * rng.uniformDouble();
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

// 1 when the walk from x (inside the sphere of radius R) along d escapes, else 0.
double walk(glm::dvec3 x, glm::dvec3 d, double R, const TwoMedia& m, Pcg32& rng) {
  for (int event = 0; event < 10000000; ++event) {
    const double b = glm::dot(x, d), c = glm::dot(x, x) - R * R;
    const double toBoundary = -b + std::sqrt(std::max(0.0, b * b - c));
    const double flight = -std::log(1.0 - rng.uniformDouble()) / m.majorant;
    if (flight >= toBoundary) {
      x += toBoundary * d;
      const glm::dvec3 n = x / R;
      const double cosOut = glm::dot(d, n);
      if (rng.uniformDouble() >= fresnelDielectric(float(cosOut), float(1.0 / kEta))) return 1.0;
      d -= 2.0 * cosOut * n;
      x = n * (R * (1.0 - 1e-12));
      continue;
    }
    x += flight * d;
    const int k = x.z > 0.0 ? 0 : 1;
    if (rng.uniformDouble() * m.majorant >= m.sigmaT[k]) continue;  // a null collision
    if (rng.uniformDouble() >= m.albedo[k]) return 0.0;
    d = uniformSphere(rng);
  }
  return 0.0;
}

struct RingReference {
  glm::dvec3 radiance{0.0}, stdError{0.0};
};

RingReference referenceAt(double theta, double R, const Material& upper, const Material& lower,
                          int walks, std::uint64_t stream) {
  const glm::dvec3 n(std::sin(theta), 0.0, std::cos(theta));
  const double entry = fresnelTransmittance(1.0f, float(kEta));
  RingReference out;
  for (int c = 0; c < 3; ++c) {
    const TwoMedia m = twoMedia(upper, lower, c);
    Pcg32 rng(1, stream * 3 + std::uint64_t(c));
    double sum = 0.0;
    for (int w = 0; w < walks; ++w) sum += walk(n * (R * (1.0 - 1e-12)), -n, R, m, rng);
    const double p = sum / walks;
    out.radiance[c] = entry * p;
    out.stdError[c] = entry * std::sqrt(p * (1.0 - p) / walks);
  }
  return out;
}

// Two primitives of one UV sphere: rings above the equator "Upper", below "Lower".
void writeHalvesGlb(const std::string& path, double radiusMm) {
  test::GltfBuilder b;
  const float r = float(radiusMm / 1000.0);
  std::vector<test::GltfBuilder::Primitive> halves = {
      test::uvSpherePrimitive(b, kSegments, kRings, r, 0, kRings / 2),
      test::uvSpherePrimitive(b, kSegments, kRings, r, kRings / 2, kRings)};
  halves[0].material = b.material("Upper");
  halves[1].material = b.material("Lower");
  b.scene({b.node({{"name", "sphere"}, {"mesh", b.mesh(halves, "sphere")}})});
  std::ofstream(path, std::ios::binary) << b.glb();
}

// Per ring: the mean radiance along the normal of the bake's vertices whose polar angle is the
// ring's (the poles are one vertex each after welding).
std::vector<glm::dvec3> ringMeans(const BakedMesh& baked) {
  std::vector<glm::dvec3> sum(kRings + 1, glm::dvec3(0.0));
  std::vector<int> count(kRings + 1, 0);
  for (std::size_t i = 0; i < baked.mesh.vertexCount(); ++i) {
    const glm::dvec3 p = glm::normalize(glm::dvec3(baked.mesh.positions[i]));
    const int ring = int(std::lround(std::acos(std::clamp(p.z, -1.0, 1.0)) / M_PI * kRings));
    sum[ring] += glm::dvec3(baked.radianceNormal[i]);
    ++count[ring];
  }
  for (int r = 0; r <= kRings; ++r) sum[r] /= std::max(count[r], 1);
  return sum;
}

BakeOutput bakeSphere(const std::string& glb, const std::string& fallback, const std::string& map) {
  BakeSettings s;
  s.meshPath = glb;
  s.material = findMaterialPreset(fallback);
  if (!map.empty()) s.materialMap = parseMaterialMap(map);
  s.run.quiet = true;
  const BakeEnvironment white{Cubemap(16, glm::vec3(1.0f)), {}};
  return bake(s, white);
}

// Relative RMS over the sphere's area (each ring weighted by its sin theta), all channels, of
// (a - ref) - (b - refB): with b and refB empty, a's error; else what a's error has beyond b's
// (the mixed bake's beyond the one-material bakes' own model error). The reference's noise
// removed.
double ringRms(const std::vector<glm::dvec3>& a, const std::vector<RingReference>& ref,
               const std::vector<glm::dvec3>& b = {}, const std::vector<RingReference>& refB = {}) {
  double err = 0.0, norm = 0.0;
  for (std::size_t r = 0; r < ref.size(); ++r) {
    const double w = std::max(std::sin(M_PI * double(r) / kRings), 0.5 * M_PI / kRings);
    for (int c = 0; c < 3; ++c) {
      double d = a[r][c] - ref[r].radiance[c], noise = std::pow(ref[r].stdError[c], 2);
      if (!b.empty()) {
        d -= b[r][c] - refB[r].radiance[c];
        noise += std::pow(refB[r].stdError[c], 2);
      }
      err += w * (d * d - noise);
      norm += w * std::pow(ref[r].radiance[c], 2);
    }
  }
  return std::sqrt(std::max(0.0, err) / norm);
}

// Per ring: the upper half's value from `upper`, the lower's from `lower`, the equator's mean.
template <typename T>
std::vector<T> byHalf(const std::vector<T>& upper, const std::vector<T>& lower) {
  std::vector<T> out = upper;
  for (int r = kRings / 2 + 1; r <= kRings; ++r) out[r] = lower[r];
  return out;
}

std::vector<RingReference> reference(double R, const Material& upper, const Material& lower,
                                     int walks) {
  std::vector<RingReference> ref(kRings + 1);
  parallelFor(ref.size(), defaultThreadCount(), 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t r = begin; r < end; ++r)
      ref[r] = referenceAt(M_PI * double(r) / kRings, R, upper, lower, walks, r);
  });
  return ref;
}

}  // namespace
}  // namespace sss

int main(int argc, char** argv) {
  using namespace sss;
  if (argc < 2) {
    std::fprintf(stderr, "usage: material_interface_study OUT_DIR [--walks N]\n");
    return 2;
  }
  const std::string outDir = argv[1];
  int walks = 200000;
  for (int i = 2; i + 1 < argc; ++i)
    if (std::string(argv[i]) == "--walks") walks = std::atoi(argv[++i]);
  std::filesystem::create_directories(outDir);
  std::ofstream rows(outDir + "/material_interface.csv");
  rows << "scene,ring,theta_deg,ref_r,ref_g,ref_b,ref_se_r,ref_se_g,ref_se_b,bake_r,bake_g,bake_b,"
          "upper_only_r,upper_only_g,upper_only_b,lower_only_r,lower_only_g,lower_only_b\n";
  std::ofstream summary(outDir + "/material_interface_summary.csv");
  summary << "scene,upper,lower,radius_mm,walks,bake_rms,homogeneous_model_rms,"
             "interface_measured,interface_predicted,predicted_total,bake_s,reference_s\n";
  const std::string glb = outDir + "/halves.glb";
  for (const Scene& scene : kScenes) {
    writeHalvesGlb(glb, scene.radiusMm);
    const Material upper = findMaterialPreset(scene.upper), lower = findMaterialPreset(scene.lower);
    const BakeOutput mixed = bakeSphere(glb, scene.lower, "Upper=" + scene.upper);
    const std::vector<glm::dvec3> bake = ringMeans(mixed.baked);
    const std::vector<glm::dvec3> upperOnly = ringMeans(bakeSphere(glb, scene.upper, "").baked);
    const std::vector<glm::dvec3> lowerOnly = ringMeans(bakeSphere(glb, scene.lower, "").baked);
    Stopwatch refClock;
    const std::vector<RingReference> ref = reference(scene.radiusMm, upper, lower, walks);
    const double refSeconds = refClock.seconds();
    // The one-material objects' references: the bakes' own model error, which the mix inherits.
    const std::vector<RingReference> homogeneous =
        byHalf(reference(scene.radiusMm, upper, upper, walks),
               reference(scene.radiusMm, lower, lower, walks));
    std::vector<glm::dvec3> oneMaterial = byHalf(upperOnly, lowerOnly);
    oneMaterial[kRings / 2] = bake[kRings / 2];  // the border's blend, as the mixed bake has it
    for (int r = 0; r <= kRings; ++r) {
      char line[600];
      const RingReference& f = ref[r];
      std::snprintf(line, sizeof line,
                    "%s,%d,%.2f,%.6g,%.6g,%.6g,%.3g,%.3g,%.3g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,"
                    "%.6g,%.6g\n",
                    scene.name.c_str(), r, 180.0 * r / kRings, f.radiance.x, f.radiance.y,
                    f.radiance.z, f.stdError.x, f.stdError.y, f.stdError.z, bake[r].x, bake[r].y,
                    bake[r].z, upperOnly[r].x, upperOnly[r].y, upperOnly[r].z, lowerOnly[r].x,
                    lowerOnly[r].y, lowerOnly[r].z);
      rows << line;
    }
    const BakeErrorReport& e = mixed.report.errors;
    char line[400];
    std::snprintf(line, sizeof line, "%s,%s,%s,%g,%d,%.4f,%.4f,%.4f,%.4f,%.4f,%.2f,%.1f\n",
                  scene.name.c_str(), scene.upper.c_str(), scene.lower.c_str(), scene.radiusMm,
                  walks, ringRms(bake, ref), ringRms(oneMaterial, homogeneous),
                  ringRms(bake, ref, oneMaterial, homogeneous), e.model.materialInterface, e.total,
                  mixed.report.totalSeconds, refSeconds);
    summary << line;
    std::printf("%s", line);
    std::fflush(stdout);
  }
  std::filesystem::remove(glb);
  return 0;
}
