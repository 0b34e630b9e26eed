// The relightable bake's light per vertex (lighting/visibility_transfer.h): the SH transfer against
// closed forms on a convex mesh and against a brute-force Monte Carlo of the shadowed integral on
// a floor beside a wall; the directional lights' irradiance against the geometry of the shadow.
#include <cmath>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "core/random.h"
#include "core/sampling.h"
#include "floor_and_wall.h"
#include "irradiance/spherical_harmonics.h"
#include "irradiance/transmitted_cosine.h"
#include "lighting/visibility_transfer.h"
#include "material/directional_albedo_weight.h"
#include "mesh/primitives.h"
#include "optics/fresnel.h"
#include "raytrace/triangle_scene.h"

namespace sss {
namespace {

constexpr float kEta = 1.3f;

// An environment of order 1 (exactly representable): L(w) = 1 + 0.6 w.z - 0.3 w.x, per channel
// scaled, as SH coefficients and as a function.
glm::vec3 smoothSky(const glm::vec3& w) {
  return (1.0f + 0.6f * w.z - 0.3f * w.x) * glm::vec3(1.0f, 0.8f, 0.5f);
}

SphericalHarmonics smoothSkySh(int order) {
  SphericalHarmonics sh(order);
  const float y00 = 0.282094792f, y1 = 0.488602512f;
  // c_00 = 1 / Y_00 * (1 / 4 pi) * 4 pi... : L = a Y_00 + b Y_10 + c Y_11 with Y_10 = y1 z,
  // Y_11 = y1 x.
  sh[SphericalHarmonics::index(0, 0)] = glm::vec3(1.0f / y00) * glm::vec3(1.0f, 0.8f, 0.5f);
  sh[SphericalHarmonics::index(1, 0)] = glm::vec3(0.6f / y1) * glm::vec3(1.0f, 0.8f, 0.5f);
  sh[SphericalHarmonics::index(1, 1)] = glm::vec3(-0.3f / y1) * glm::vec3(1.0f, 0.8f, 0.5f);
  return sh;
}

glm::vec3 transferred(std::span<const glm::vec3> transfer, const SphericalHarmonics& light) {
  glm::vec3 e(0.0f);
  for (int k = 0; k < light.coefficientCount(); ++k) e += transfer[k] * light[k];
  return e;
}

TEST(VisibilityTransfer, ConvexSphereIsTheClosedFormUnderUniformLight) {
  const TriangleMesh sphere = makeIcosphere(2, 10.0f);
  const VisibilityTransfer t = visibilityTransfer(sphere.positions, sphere.normals,
                                                  sphere.triangles, kEta, {.order = 3, .rays = 16});
  EXPECT_EQ(t.count, 16);
  EXPECT_EQ(t.blockedFraction, 0.0);
  // Uniform radiance 1: L_00 = 2 sqrt(pi), E = kHat_0 = 2 pi int F_t mu dmu.
  SphericalHarmonics uniform(3);
  uniform[0] = glm::vec3(2.0f * std::sqrt(float(M_PI)));
  const double expected = TransmittedCosineKernel(kEta).zonalCoefficient(0);
  for (std::size_t v = 0; v < sphere.positions.size(); v += 7)
    EXPECT_NEAR(transferred(t.at(v), uniform).x, expected, 1e-4 * expected) << v;
}

TEST(VisibilityTransfer, ConvexSphereMatchesTheIrradianceOfAnOrderOneSky) {
  const TriangleMesh sphere = makeIcosphere(2, 10.0f);
  const VisibilityTransfer t = visibilityTransfer(sphere.positions, sphere.normals,
                                                  sphere.triangles, kEta, {.order = 2, .rays = 8});
  const SphericalHarmonics sky = smoothSkySh(2);
  const SphericalHarmonics irradiance = sky.convolved(TransmittedCosineKernel(kEta));
  for (std::size_t v = 0; v < sphere.positions.size(); v += 5) {
    // A facet per vertex of a smooth sphere: the transfer is kHat_l Y_lm(n).
    const glm::vec3 want = irradiance.evaluate(sphere.normals[v]);
    const glm::vec3 got = transferred(t.at(v), sky);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 2e-3 * want[c] + 1e-5) << v;
  }
}

// Brute force: E = int L(w) V(w) F_t(mu) w(mu) mu dw over the vertex normal's hemisphere, by
// uniform directions (another sampling than the transfer's cosine lobes).
glm::vec3 bruteForce(const TriangleScene& scene, const glm::vec3& p, const glm::vec3& n,
                     const DirectionalAlbedoWeight& entry, uint64_t stream) {
  Pcg32 rng(7, stream);
  const int samples = 40000;
  glm::dvec3 sum(0.0);
  for (int i = 0; i < samples; ++i) {
    const double mu = rng.uniformDouble();
    const glm::vec3 w = directionAbout(n, mu, 2.0 * M_PI * rng.uniformDouble());
    if (scene.occluded(p + 1e-3f * n, w, 1e-3f)) continue;
    sum += glm::dvec3(smoothSky(w) * entry.at(float(mu)) *
                      (fresnelTransmittance(float(mu), kEta) * float(mu)));
  }
  return glm::vec3(sum * (2.0 * M_PI / samples));
}

TEST(VisibilityTransfer, ShadowedFloorMatchesABruteForceIntegral) {
  const TriangleMesh mesh = floorAndWall(8);
  const DirectionalAlbedoWeight entry(glm::dvec3(0.99, 0.9, 0.6), kEta);
  const VisibilityTransfer t =
      visibilityTransfer(mesh.positions, mesh.normals, mesh.triangles, kEta,
                         {.order = 2, .rays = 4096, .entry = &entry, .run = {.seed = 3}});
  EXPECT_GT(t.blockedFraction, 0.05);
  const TriangleScene scene(mesh.positions, mesh.triangles);
  const SphericalHarmonics sky = smoothSkySh(2);
  int checked = 0;
  for (std::size_t v = 0; v < 81; ++v) {  // the floor's vertices
    const glm::vec3 p = mesh.positions[v];
    if (p.x > -2.0f || std::abs(p.y) > 3.0f || p.x < -4.5f) continue;  // near the wall
    const glm::vec3 want = bruteForce(scene, p, mesh.normals[v], entry, v);
    const glm::vec3 got = transferred(t.at(v), sky);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], want[c], 0.02 * want[c]) << v << " " << c;
    ++checked;
  }
  EXPECT_GE(checked, 4);
}

TEST(VisibilityTransfer, DirectionalLightIsShadowedByTheWall) {
  const TriangleMesh mesh = floorAndWall(8);
  // Light from over the wall: +Z tilted towards -X at 45 degrees; the wall (x = -5, 10 high)
  // shadows the floor up to x = +5.
  const DirectionalLight sun{glm::normalize(glm::vec3(-1.0f, 0.0f, 1.0f)), glm::vec3(2.0f), 1e-3};
  const std::vector<glm::vec3> e =
      directionalIrradiance(mesh.positions, mesh.normals, mesh.triangles, kEta, nullptr,
                            std::span<const DirectionalLight>(&sun, 1), {});
  const float mu = std::sqrt(0.5f);
  const float lit = 2.0f * fresnelTransmittance(mu, kEta) * mu;
  // The wall's face (normal +X) turns away from this light; the floor is all in its shadow.
  for (std::size_t v = 0; v < 81; ++v) {
    const glm::vec3 p = mesh.positions[v];  // not on an edge, nor at the wall's foot
    if (p.x < 4.9f && p.x > -4.9f && std::abs(p.y) < 4.9f) {
      EXPECT_EQ(e[v].x, 0.0f) << v;
    }
  }
  const DirectionalLight low{glm::normalize(glm::vec3(1.0f, 0.0f, 1.0f)), glm::vec3(2.0f), 1e-3};
  const std::vector<glm::vec3> f =
      directionalIrradiance(mesh.positions, mesh.normals, mesh.triangles, kEta, nullptr,
                            std::span<const DirectionalLight>(&low, 1), {});
  for (std::size_t v = 0; v < 81; ++v) EXPECT_NEAR(f[v].x, lit, 1e-5f) << v;  // all lit
  for (std::size_t v = 81; v < mesh.positions.size(); ++v) {                  // the wall faces it
    const float wallMu = std::sqrt(0.5f);
    EXPECT_NEAR(f[v].x, 2.0f * fresnelTransmittance(wallMu, kEta) * wallMu, 1e-5f) << v;
  }
}

}  // namespace
}  // namespace sss
