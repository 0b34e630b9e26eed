// Where diffusion methods fail, pinned against the Monte Carlo reference (docs/accuracy.md,
// "Where methods still fail"). Each test states the measured behaviour; if a change to a profile,
// the diffusion sums or the path tracer moves it, the test says so. Numbers:
// tests/bench/results/accuracy (tests/bench/accuracy_study.sh).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/geometric.hpp>

#include "diffusion/diffusion.h"
#include "envmap/cubemap.h"
#include "lighting/visibility.h"
#include "material/diffusion_profile.h"
#include "material/directional_albedo_weight.h"
#include "material/material.h"
#include "material/profile_factory.h"
#include "mesh/primitives.h"
#include "optics/fresnel.h"
#include "pathtrace/light_tracer.h"
#include "pathtrace/subsurface_path_tracer.h"
#include "transport/finite_object_energy.h"

namespace sss {
namespace {

// Radiance 1 from directions with z > 0, 0 below: light from one side of a slab.
Cubemap upperHemisphere() {
  Cubemap c(16);
  forEachTexel(c.size(), [&](int f, int x, int y) {
    c.at(f, x, y) = glm::vec3(c.direction(f, x, y).z > 0.0f ? 1.0f : 0.0f);
  });
  return c;
}

// The bake's transmitted irradiance with the mesh's shadows, 64 rays per vertex.
std::vector<glm::vec3> irradiance(const TriangleMesh& mesh, const Cubemap& light,
                                  const Material& m) {
  VisibilityOptions vis;
  vis.samples = 64;
  return transmittedIrradianceWithVisibility(mesh.positions, mesh.normals, mesh.triangles, light,
                                             float(m.eta), vis);
}

std::size_t nearestVertex(const TriangleMesh& mesh, const glm::vec3& p) {
  std::size_t best = 0;
  for (std::size_t i = 1; i < mesh.positions.size(); ++i)
    if (glm::length(mesh.positions[i] - p) < glm::length(mesh.positions[best] - p)) best = i;
  return best;
}

std::vector<glm::vec3> diffuseExact(const TriangleMesh& mesh, const std::vector<glm::vec3>& e,
                                    const DiffusionProfile& profile) {
  const std::vector<float> areas = vertexAreas(mesh);
  DiffusionOptions options;
  options.method = DiffusionMethod::Exact;
  options.run.quiet = true;
  return diffuse({mesh.positions, mesh.normals, areas, e}, profile, options).exitance;
}

// The same sum with the escape energy model (lib/transport/finite_object_energy.h).
std::vector<glm::vec3> diffuseExactEscape(const TriangleMesh& mesh, const std::vector<glm::vec3>& e,
                                          const DiffusionProfile& profile, const Material& m) {
  const std::vector<float> areas = vertexAreas(mesh);
  EnergyOptions energyOptions;
  energyOptions.model = EnergyModel::Escape;
  energyOptions.noiseBudget = 0.003;
  const EnergyPlan plan = planFiniteObjectEnergy(mesh, areas, m, energyOptions);
  DiffusionOptions options;
  options.method = DiffusionMethod::Exact;
  options.run.quiet = true;
  const DiffusionResult r =
      diffuseWithEnergy({mesh.positions, mesh.normals, areas, e}, profile, options, plan, m);
  return r.exitance;
}

// Thin parts: a 1 mm marble slab (2.6 reduced mean free paths) lit from above only. The truth
// sends much of the light through to the unlit side; the profiles assume a half-space, so the
// diffusion sum returns that light on the lit side instead. Measured (Monte Carlo / dipole):
// top 1.67 / 2.46 (+47%), bottom 1.10 / 1.30 (+19%).
TEST(FailureModes, ThinSlabDiffusionOverestimatesTheLitSide) {
  const Material marble = findMaterialPreset("marble");
  const TriangleMesh slab = makeSlab(30.0f, 1.0f, 24);
  const Cubemap light = upperHemisphere();
  const uint32_t top = uint32_t(nearestVertex(slab, glm::vec3(0.0f, 0.0f, 0.5f)));
  const uint32_t bottom = uint32_t(nearestVertex(slab, glm::vec3(0.0f, 0.0f, -0.5f)));
  PathTraceOptions options;
  options.samples = 6000;
  options.vertices = {top, bottom};
  options.estimateRadiance = false;
  options.run.quiet = true;
  const PathTraceResult pt = pathTraceSubsurface(slab, light, marble, options);
  const std::vector<glm::vec3> e = irradiance(slab, light, marble);
  const auto dipole = makeProfile("dipole", marble);
  const std::vector<glm::vec3> b = diffuseExact(slab, e, *dipole);
  const double topRatio = b[top].y / pt.exitance[0].y;
  const double bottomRatio = b[bottom].y / pt.exitance[1].y;
  EXPECT_LT(pt.exitanceStdErr[1].y, 0.03 * pt.exitance[1].y);
  EXPECT_GT(pt.exitance[1].y, 0.5 * pt.exitance[0].y) << "the slab transmits";
  EXPECT_GT(topRatio, 1.3) << "lit side: dipole / Monte Carlo";
  EXPECT_LT(topRatio, 1.7);
  EXPECT_NEAR(bottomRatio, 1.19, 0.12) << "unlit side: dipole / Monte Carlo";
  // The escape energy model normalizes the profile by its sum over both faces (1.25 R_total) and
  // spreads the light the slab returns beyond a half-space widely, over both faces: measured
  // top 1.07, bottom 0.92.
  const std::vector<glm::vec3> escape = diffuseExactEscape(slab, e, *dipole, marble);
  const double escapeTop = escape[top].y / pt.exitance[0].y;
  const double escapeBottom = escape[bottom].y / pt.exitance[1].y;
  EXPECT_NEAR(escapeTop, 1.07, 0.08) << "lit side: escape model / Monte Carlo";
  EXPECT_NEAR(escapeBottom, 0.92, 0.08) << "unlit side: escape model / Monte Carlo";
  EXPECT_LT(std::abs(escapeTop - 1.0), 0.5 * (topRatio - 1.0));
}

// A thick half-space (eta 1.3, uniform light, sigma_t = 1 / mm) with reduced albedos kExitAlbedo
// in R, G, B: the backward tracer's exitance and radiance along the normal at the top centre,
// counting light scattered at least minScatteringOrder times.
const glm::dvec3 kExitAlbedo(0.99, 0.5, 0.05);

PathTraceResult halfSpaceExit(int minScatteringOrder) {
  const TriangleMesh box = makeBox(glm::vec3(120.0f, 120.0f, 60.0f), 2);
  const uint32_t top = uint32_t(nearestVertex(box, glm::vec3(0.0f, 0.0f, 30.0f)));
  const Cubemap uniform(8, glm::vec3(1.0f));
  HomogeneousMedium medium;
  medium.eta = 1.3;
  medium.sigmaS = kExitAlbedo;
  medium.sigmaA = 1.0 - kExitAlbedo;
  PathTraceOptions options;
  options.samples = 40000;
  options.vertices = {top};
  options.minScatteringOrder = minScatteringOrder;
  options.run.quiet = true;
  return pathTraceSubsurface(box.positions, box.normals, box.triangles, uniform, medium, options);
}

// Low albedo: the exit model L = B F_t / (pi (1 - 2 C_1)) assumes the diffuse angular shape of
// strongly scattering media. On a half-space (multiple scattering) the Monte Carlo radiance along
// the normal matches it within 1% at alpha' = 0.99 but is 6% below it at alpha' = 0.5 and 0.05:
// less scattered light leaves more grazing.
TEST(FailureModes, ExitModelHoldsAtHighAlbedoOnly) {
  const PathTraceResult pt = halfSpaceExit(2);  // the diffusion part the exit model describes
  const double scale = fresnelTransmittance(1.0f, 1.3f) * exitRadianceScale(1.3f);
  glm::dvec3 ratio;
  for (int c = 0; c < 3; ++c) ratio[c] = pt.radiance[0][c] / (pt.exitance[0][c] * scale);
  EXPECT_NEAR(ratio.x, 1.0, 0.03);
  EXPECT_NEAR(ratio.y, 0.94, 0.035);
  EXPECT_NEAR(ratio.z, 0.94, 0.05);
  EXPECT_LT(std::max(ratio.y, ratio.z), 0.975);
}

// The calibrated exit model (material/directional_albedo_weight.h) on the same half-space, for all
// the scattered light the bake's B holds: L = B F_t(1) w(1) / (pi (1 - 2 C_1)) with w from the
// half-space Monte Carlo table holds across albedo, where the normalized model (w = 1) is 5-12 %
// high at alpha' 0.5 and 0.05.
TEST(FailureModes, CalibratedExitModelHoldsAcrossAlbedo) {
  const PathTraceResult pt = halfSpaceExit(1);
  const glm::vec3 calibrated =
      calibratedExitRadiance(DirectionalAlbedoWeight(kExitAlbedo, 1.3), 1.0f, 1.3f);
  const double normalized = fresnelTransmittance(1.0f, 1.3f) * exitRadianceScale(1.3f);
  for (int c = 0; c < 3; ++c) {
    const double measured = pt.radiance[0][c] / pt.exitance[0][c];
    // Within 2 % plus three of the reference's standard errors (1.7 % at alpha' 0.05).
    const double se = pt.radianceStdErr[0][c] / pt.radiance[0][c];
    EXPECT_NEAR(measured / calibrated[c], 1.0, 0.02 + 3.0 * se) << "alpha' " << kExitAlbedo[c];
    if (c > 0) {
      EXPECT_LT(measured / normalized, 0.95) << "alpha' " << kExitAlbedo[c];
    }
  }
}

// Uniform light on a marble sphere: dipole exitance / Monte Carlo exitance, averaged over vertices.
double dipoleOverReference(int subdivisions, uint32_t vertices, int walks,
                           bool escapeEnergy = false) {
  const Material marble = findMaterialPreset("marble");
  const TriangleMesh sphere = makeIcosphere(subdivisions, 10.0f);
  const Cubemap uniform(8, glm::vec3(1.0f));
  PathTraceOptions options;
  options.samples = walks;
  options.estimateRadiance = false;
  options.run.quiet = true;
  for (uint32_t k = 0; k < vertices; ++k)
    options.vertices.push_back(uint32_t(k * sphere.positions.size() / vertices));
  const PathTraceResult pt = pathTraceSubsurface(sphere, uniform, marble, options);
  const std::vector<glm::vec3> e(sphere.positions.size(),
                                 glm::vec3(float(M_PI * (1.0 - diffuseFresnelReflectance(1.3f)))));
  const auto dipole = makeProfile("dipole", marble);
  const std::vector<glm::vec3> b = escapeEnergy ? diffuseExactEscape(sphere, e, *dipole, marble)
                                                : diffuseExact(sphere, e, *dipole);
  double ptSum = 0, bSum = 0;
  for (uint32_t k = 0; k < vertices; ++k) {
    ptSum += pt.exitance[k].y;
    bSum += b[options.vertices[k]].y;
    EXPECT_TRUE(std::isfinite(b[options.vertices[k]].y));
  }
  return bSum / ptSum;
}

// Small objects and very coarse meshes. A 10 mm marble sphere is about one diffusion length
// across: the light a half-space would absorb far away leaves the sphere instead, so the dipole
// (which assumes a half-space) with the half-space energy is 11% low under uniform light on a
// 642-vertex sphere. Coarsening
// the mesh to 42 vertices (edges 6 mm, 0.7 diffusion lengths) costs another 4%: the
// disc-integrated self term keeps B finite and close.
TEST(FailureModes, SmallObjectsAreUnderestimatedCoarseMeshesAddLittle) {
  const double fine = dipoleOverReference(3, 42, 300);
  const double coarse = dipoleOverReference(1, 42, 300);
  EXPECT_NEAR(fine, 0.89, 0.03);
  EXPECT_NEAR(coarse / fine, 0.955, 0.03);
  // The escape energy model measures what the sphere returns: 0.99 and 0.98 (its walks enter over
  // each vertex's facets, so the coarse mesh's cone-shaped vertices do not bias them).
  EXPECT_NEAR(dipoleOverReference(3, 42, 300, true), 1.0, 0.03);
  EXPECT_NEAR(dipoleOverReference(1, 42, 300, true), 1.0, 0.05);
}

// Sharp edges: a 20 mm marble cube lit from above. With the escape energy model the dipole's B is
// within 4% of the reference at the top face's centre and a side face's centre (radiance along
// the normal against the backward path tracer there: measured 1.03 and 0.99), and along a top
// edge: light entering near an edge is not lost. A vertex on the edge stands for the facets
// around it, half on the top face (the whole sky) and half on the side (half of it), so there the
// reference is the forward light tracer's barycentric tally of B over the edge's inner vertices
// (0.97; the backward tracer's point value at the edge, along its 45-degree normal, is another
// quantity: the bake's B over it reads 1.04 with E taken at that normal, and 0.94 with the
// facets' light, lighting/facet_light.h). Under the accuracy study's blurred forest, which lights
// the cube from every side, its error is in tests/bench/results/accuracy.
TEST(FailureModes, SharpEdgesHoldUnderLightFromAbove) {
  const Material marble = findMaterialPreset("marble");
  const TriangleMesh cube = makeBox(glm::vec3(20.0f), 8);
  const std::vector<uint32_t> vertices = {
      uint32_t(nearestVertex(cube, glm::vec3(0.0f, 0.0f, 10.0f))),
      uint32_t(nearestVertex(cube, glm::vec3(0.0f, 10.0f, 0.0f)))};
  const Cubemap light = upperHemisphere();
  PathTraceOptions options;
  options.samples = 4000;
  options.vertices = vertices;
  options.run.quiet = true;
  const PathTraceResult pt = pathTraceSubsurface(cube, light, marble, options);
  const std::vector<glm::vec3> e = irradiance(cube, light, marble);
  const auto dipole = makeProfile("dipole", marble);
  const std::vector<glm::vec3> b = diffuseExactEscape(cube, e, *dipole, marble);
  const double scale = fresnelTransmittance(1.0f, 1.3f) * exitRadianceScale(1.3f);
  const char* names[2] = {"top face", "side face"};
  for (int k = 0; k < 2; ++k) {
    EXPECT_LT(pt.radianceStdErr[k].y, 0.02 * pt.radiance[k].y) << names[k];
    EXPECT_NEAR(b[vertices[k]].y * scale / pt.radiance[k].y, 1.0, 0.06) << names[k];
  }
  LightTraceOptions lo;
  lo.paths = 500000;
  lo.tallyRadiance = false;
  const LightTraceResult ref =
      lightTraceSubsurface(cube.positions, cube.normals, cube.triangles,
                           DistantLight::environment(light), homogeneousMediumOf(marble), lo);
  double sum = 0.0, sumRef = 0.0, var = 0.0;
  int edge = 0;
  for (std::size_t v = 0; v < cube.positions.size(); ++v) {
    const glm::vec3 p = cube.positions[v];
    if (std::abs(p.y - 10.0f) > 1e-3f || std::abs(p.z - 10.0f) > 1e-3f || std::abs(p.x) > 9.0f)
      continue;
    ++edge;
    sum += b[v].y;
    sumRef += ref.exitance[v].y;
    var += double(ref.exitanceStdErr[v].y) * ref.exitanceStdErr[v].y;
  }
  ASSERT_EQ(edge, 7);
  EXPECT_LT(std::sqrt(var), 0.02 * sumRef);
  EXPECT_NEAR(sum / sumRef, 1.0, 0.06) << "top edge";
}

// Strong sun: the reference picks one environment direction per exit, so a small bright sun
// makes it noisy (27% per vertex with 4096 walks in the study's sun scene) and the comparison
// with diffusion there is limited by that noise. What must hold is that the reported standard
// errors are honest: two seeds differ by what they claim (mean squared z-score ~ 1).
TEST(FailureModes, StrongSunStandardErrorsAreHonest) {
  const Material marble = findMaterialPreset("marble");
  const TriangleMesh sphere = makeIcosphere(2, 10.0f);
  Cubemap sun(16, glm::vec3(0.2f));
  sun.at(int(CubeFace::PosY), 7, 7) = glm::vec3(5000.0f);  // ~0.003 sr, 99% of the energy
  PathTraceOptions options;
  options.samples = 128;
  options.estimateRadiance = false;
  options.run.quiet = true;
  for (uint32_t k = 0; k < 64; ++k) options.vertices.push_back(k * 162 / 64);
  const PathTraceResult a = pathTraceSubsurface(sphere, sun, marble, options);
  options.run.seed = 2;
  const PathTraceResult b = pathTraceSubsurface(sphere, sun, marble, options);
  double z2 = 0.0, relSe = 0.0;
  for (std::size_t k = 0; k < options.vertices.size(); ++k) {
    const double d = a.exitance[k].y - b.exitance[k].y;
    const double se2 = a.exitanceStdErr[k].y * a.exitanceStdErr[k].y +
                       b.exitanceStdErr[k].y * b.exitanceStdErr[k].y;
    z2 += d * d / se2 / double(options.vertices.size());
    relSe += a.exitanceStdErr[k].y / a.exitance[k].y / double(options.vertices.size());
  }
  EXPECT_GT(relSe, 0.1) << "a sun is noisy for the reference";
  EXPECT_GT(z2, 0.5);
  EXPECT_LT(z2, 2.0);
}

}  // namespace
}  // namespace sss
