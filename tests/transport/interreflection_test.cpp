// Interreflection: the white furnace. A closed, non-absorbing object under uniform radiance 1
// sends radiance 1 in every direction from every vertex, concavities included; without the light
// it sends itself, a pit is dark.
#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <memory>
#include <span>
#include <vector>

#include "core/error.h"
#include "core/relative_rms.h"
#include "envmap/compact_lights.h"
#include "envmap/cubemap.h"
#include "lighting/visibility.h"
#include "material/diffusion_profile.h"
#include "material/material.h"
#include "material/profile_factory.h"
#include "mesh/primitives.h"
#include "mesh/triangle_mesh.h"
#include "optics/fresnel.h"
#include "raytrace/triangle_scene.h"
#include "support/box_with_pit.h"
#include "support/joined_meshes.h"
#include "support/small_sun.h"
#include "transport/interreflection.h"

namespace sss {
namespace {

// The furnace for one gather's rays: `rays` its own count, `reused` how many of the visibility's
// cosine rays per vertex it takes (0: none, all traced for it).
void expectWhiteFurnace(int rays, int reused) {
  const TriangleMesh mesh = boxWithPit();
  const Cubemap white(8, glm::vec3(1.0f));
  const float eta = 1.3f;
  const double full = M_PI * (1.0 - diffuseFresnelReflectance(eta));  // E under a full sky
  VisibilityOptions vis;
  vis.samples = reused > 0 ? 2 * reused : 256;
  vis.keepCosineHitsUpTo = reused;
  VisibilityReport visibility;
  const std::vector<glm::vec3> direct = transmittedIrradianceWithVisibility(
      mesh.positions, mesh.normals, mesh.triangles, white, eta, vis, &visibility);
  ASSERT_EQ(visibility.cosineHits.perVertex, reused);
  InterreflectionOptions options;
  options.rays = rays;
  options.visibilityCosineRays = reused;
  if (reused > 0) options.traced = &visibility.cosineHits;
  const InterreflectionGather gather(mesh.positions, mesh.normals, mesh.triangles, white, eta,
                                     options);
  if (reused > 0) {
    // The same set traced by the gather itself (as a relight, which has no visibility pass, does):
    // the same light, bit for bit.
    InterreflectionOptions alone = options;
    alone.traced = nullptr;
    const InterreflectionGather again(mesh.positions, mesh.normals, mesh.triangles, white, eta,
                                      alone);
    const std::vector<glm::vec3> b(mesh.positions.size(), glm::vec3(0.3f, 0.5f, 0.7f));
    EXPECT_EQ(gather.gather(b), again.gather(b));
  }
  EXPECT_EQ(gather.rays(), std::max(rays, reused));
  EXPECT_GT(gather.blockedFraction(), 0.02);
  // A non-absorbing object under uniform light returns all it receives where it receives it: the
  // transport of any normalized model maps a uniform E to B = E.
  const auto identity = [](std::span<const glm::vec3> e, double = 1.0) {
    return std::vector<glm::vec3>(e.begin(), e.end());
  };
  const BounceResult r =
      iterateInterreflection(gather, direct, identity(direct), identity, 0, 1e-5);
  EXPECT_GT(r.bounces, 2);
  EXPECT_LT(r.change, 1e-5);
  // Radiance along the normal: the exit model of B plus the reflected sky, F_r(1) * 1.
  const double exitScale = normalExitRadianceScale(eta);
  const double reflected = fresnelDielectric(1.0f, eta);
  double pitDirect = 0.0, pitAfter = 0.0;
  int pit = 0;
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    const double l = r.exitance[v].g * exitScale + reflected;
    ASSERT_NEAR(l, 1.0, 0.06) << "vertex " << v;
    if (direct[v].g / full < 0.8) {  // sees less than ~80 % of the sky
      ++pit;
      pitDirect += direct[v].g / full;
      pitAfter += r.exitance[v].g * exitScale + reflected;
    }
  }
  ASSERT_GT(pit, 10);
  EXPECT_LT(pitDirect / pit, 0.75);        // without interreflection: dark
  EXPECT_NEAR(pitAfter / pit, 1.0, 0.01);  // with it: the furnace's radiance 1
}

TEST(Interreflection, WhiteFurnaceSendsRadianceOneFromEveryVertex) {
  expectWhiteFurnace(256, 0);
}

// One ray set, both uses: the gather takes the visibility's cosine rays that met the mesh, all of
// its rays or some (then it traces the rest itself), and the furnace holds as with its own.
TEST(Interreflection, WhiteFurnaceHoldsWithTheVisibilitysRays) {
  expectWhiteFurnace(64, 128);
  expectWhiteFurnace(256, 128);
}

// Two touching spheres (5,124 vertices, each sphere sees the other): the gather's light and its
// variance are the same, bit for bit, for any thread count (each vertex sums its own hits).
TEST(Interreflection, GatherIsTheSameForAnyThreadCount) {
  const TriangleMesh sphere = makeIcosphere(4, 10.0f);
  const TriangleMesh pair = joinedMeshes(sphere, sphere, glm::vec3(20.5f, 0.0f, 0.0f));
  const Cubemap sky(8, glm::vec3(1.0f));
  std::vector<glm::vec3> b(pair.positions.size());
  for (std::size_t v = 0; v < b.size(); ++v)
    b[v] = glm::vec3(0.2f + 0.6f * float(v % 7) / 7.0f, 0.5f, 0.3f + float(v % 3) / 3.0f);
  std::vector<std::vector<glm::vec3>> light, variance;
  for (int threads : {1, 3}) {
    InterreflectionOptions options;
    options.rays = 32;
    options.run.threads = threads;
    const InterreflectionGather gather(pair.positions, pair.normals, pair.triangles, sky, 1.3f,
                                       options);
    ASSERT_GT(gather.blockedFraction(), 0.01);
    variance.emplace_back();
    light.push_back(gather.gather(b, &variance.back()));
  }
  EXPECT_EQ(light[0], light[1]);
  EXPECT_EQ(variance[0], variance[1]);
}

// A relightable bake stores which of its gather's rays met the front of a surface (frontHits); a
// gather given them traces those rays only, and gathers the same light, bit for bit, its variance
// and a swapped sky included.
TEST(Interreflection, StoredFrontHitsGatherTheSameLight) {
  const TriangleMesh mesh = boxWithPit();
  const Cubemap sky(8, glm::vec3(0.6f, 0.8f, 1.0f));
  const float eta = 1.3f;
  VisibilityOptions vis;
  vis.samples = 96;
  vis.keepCosineHitsUpTo = 48;
  VisibilityReport visibility;
  transmittedIrradianceWithVisibility(mesh.positions, mesh.normals, mesh.triangles, sky, eta, vis,
                                      &visibility);
  InterreflectionOptions options;
  options.rays = 64;  // 48 of them the visibility's, 16 its own
  options.visibilityCosineRays = 48;
  options.traced = &visibility.cosineHits;
  options.keepFrontHits = true;
  const InterreflectionGather bake(mesh.positions, mesh.normals, mesh.triangles, sky, eta, options);
  const std::size_t words = frontHitWords(64);
  ASSERT_EQ(words, 4u);
  ASSERT_EQ(bake.frontHits().size(), mesh.positions.size() * words);
  // Some rays met the pit's walls, far from all (most vertices see the open sky).
  std::size_t rays = 0;
  for (const uint16_t word : bake.frontHits()) rays += std::size_t(std::popcount(word));
  EXPECT_GT(double(rays), 0.01 * 64.0 * double(mesh.positions.size()));
  EXPECT_LT(double(rays), 0.5 * 64.0 * double(mesh.positions.size()));
  InterreflectionOptions relight = options;
  relight.traced = nullptr;
  relight.keepFrontHits = false;
  relight.keepMirrors = true;
  relight.frontHits = bake.frontHits();
  InterreflectionGather stored(mesh.positions, mesh.normals, mesh.triangles, sky, eta, relight);
  relight.frontHits = {};
  InterreflectionGather traced(mesh.positions, mesh.normals, mesh.triangles, sky, eta, relight);
  const std::vector<glm::vec3> b(mesh.positions.size(), glm::vec3(0.3f, 0.5f, 0.7f));
  std::vector<glm::vec3> storedVariance, tracedVariance;
  EXPECT_EQ(stored.gather(b, &storedVariance), bake.gather(b));
  EXPECT_EQ(traced.gather(b, &tracedVariance), bake.gather(b));
  EXPECT_EQ(storedVariance, tracedVariance);
  const Cubemap other(8, glm::vec3(2.0f, 0.5f, 0.1f));
  stored.setSky(other);
  traced.setSky(other);
  EXPECT_EQ(stored.gather(b), traced.gather(b));
  // The bits are read: without any, nothing is traced and nothing gathered; a short mask throws.
  const std::vector<uint16_t> none(mesh.positions.size() * words, 0);
  relight.frontHits = none;
  const InterreflectionGather empty(mesh.positions, mesh.normals, mesh.triangles, sky, eta,
                                    relight);
  for (const glm::vec3& e : empty.gather(b)) EXPECT_EQ(e, glm::vec3(0.0f));
  relight.frontHits = std::span(none).first(none.size() - 1);
  EXPECT_THROW(
      InterreflectionGather(mesh.positions, mesh.normals, mesh.triangles, sky, eta, relight),
      Error);
}

// One BVH for the bake's stages: the visibility and the gather given the caller's scene of the
// mesh see what they see with their own, bit for bit; a scene of another mesh is refused.
TEST(Interreflection, AGivenRaySceneGathersWhatAnOwnOneDoes) {
  const TriangleMesh mesh = boxWithPit();
  const Cubemap sky(8, glm::vec3(0.6f, 0.8f, 1.0f));
  const float eta = 1.3f;
  const TriangleScene shared(mesh.positions, mesh.triangles, TriangleSceneOptions::surfaceRays(1));
  VisibilityOptions vis;
  vis.samples = 96;
  vis.keepCosineHitsUpTo = 48;
  VisibilityReport own, given;
  const std::vector<glm::vec3> eOwn = transmittedIrradianceWithVisibility(
      mesh.positions, mesh.normals, mesh.triangles, sky, eta, vis, &own);
  vis.scene = &shared;
  const std::vector<glm::vec3> eGiven = transmittedIrradianceWithVisibility(
      mesh.positions, mesh.normals, mesh.triangles, sky, eta, vis, &given);
  EXPECT_EQ(eOwn, eGiven);
  ASSERT_EQ(own.cosineHits.hits.size(), given.cosineHits.hits.size());
  InterreflectionOptions options;
  options.rays = 64;  // 48 of them the visibility's, 16 traced here
  options.visibilityCosineRays = 48;
  options.traced = &own.cosineHits;
  const InterreflectionGather alone(mesh.positions, mesh.normals, mesh.triangles, sky, eta,
                                    options);
  options.scene = &shared;
  const InterreflectionGather sharing(mesh.positions, mesh.normals, mesh.triangles, sky, eta,
                                      options);
  const std::vector<glm::vec3> b(mesh.positions.size(), glm::vec3(0.3f, 0.5f, 0.7f));
  EXPECT_EQ(alone.gather(b), sharing.gather(b));
  EXPECT_GT(alone.blockedFraction(), 0.02);
  const TriangleMesh other = makeIcosphere(2, 10.0f);
  const TriangleScene otherScene(other.positions, other.triangles,
                                 TriangleSceneOptions::surfaceRays(1));
  options.scene = &otherScene;
  EXPECT_THROW(
      InterreflectionGather(mesh.positions, mesh.normals, mesh.triangles, sky, eta, options),
      Error);
}

// Without bounces, a pilot gather estimates the share of B the bounces would add. With a local
// transport (B = albedo E: no smoothing, which the estimate leaves out), what it approximates is
// the later bounces' geometric series: it must agree with the bounces themselves.
TEST(Interreflection, PilotEstimateOfTheMissingLightMatchesTheBounces) {
  const TriangleMesh mesh = boxWithPit();
  const Cubemap white(8, glm::vec3(1.0f));
  const float eta = 1.3f;
  VisibilityOptions vis;
  vis.samples = 64;
  const std::vector<glm::vec3> direct = transmittedIrradianceWithVisibility(
      mesh.positions, mesh.normals, mesh.triangles, white, eta, vis);
  const glm::vec3 albedo(0.9f, 0.6f, 0.2f);
  const auto local = [&](std::span<const glm::vec3> e, double = 1.0) {
    std::vector<glm::vec3> b(e.begin(), e.end());
    for (glm::vec3& x : b) x *= albedo;
    return b;
  };
  InterreflectionOptions options;
  options.rays = 64;
  const InterreflectionGather all(mesh.positions, mesh.normals, mesh.triangles, white, eta,
                                  options);
  const BounceResult bounced = iterateInterreflection(all, direct, local(direct), local, 0, 1e-5);
  const std::vector<glm::vec3> b0 = local(direct);
  const double actual = relativeRms(bounced.exitance, b0);
  ASSERT_GT(actual, 0.02);  // the pit matters
  // A pilot of every 4th vertex, as the bake's of ~1,000 on a larger mesh.
  options.vertices.clear();
  for (uint32_t v = 1; v < mesh.positions.size(); v += 4) options.vertices.push_back(v);
  const InterreflectionGather pilot(mesh.positions, mesh.normals, mesh.triangles, white, eta,
                                    options);
  const MissingInterreflection estimate =
      estimateMissingInterreflection(pilot, options.vertices, b0, direct, vertexAreas(mesh));
  EXPECT_GT(estimate.gain, 0.0);
  EXPECT_NEAR(estimate.relativeRms / actual, 1.0, 0.25) << estimate.relativeRms << " " << actual;
  // Untraced vertices gather nothing.
  const std::vector<glm::vec3> added = pilot.gather(b0);
  EXPECT_EQ(added[0], glm::vec3(0.0f));
}

// With a diffusion transport, B_v = sum_u R_d(r_vu) E_u A_u (Li & Guo Eq. 7; the vertex's own
// area integrates the profile), the first bounce's light, concentrated in the pit, is spread over
// a diffusion length, which in skim milk is the pit's size: the estimate follows that spreading
// with the profile over the pilot's vertices, where the light's own RMS overestimates.
TEST(Interreflection, PilotEstimateFollowsTheTransportsSpreading) {
  const TriangleMesh mesh = boxWithPit();
  const Cubemap white(8, glm::vec3(1.0f));
  const Material skim = findMaterialPreset("skimmilk");
  const float eta = float(skim.eta);
  const std::unique_ptr<DiffusionProfile> profile = makeProfile("dipole", skim);
  VisibilityOptions vis;
  vis.samples = 64;
  const std::vector<glm::vec3> direct = transmittedIrradianceWithVisibility(
      mesh.positions, mesh.normals, mesh.triangles, white, eta, vis);
  const std::vector<float> areas = vertexAreas(mesh);
  const std::size_t n = mesh.positions.size();
  std::vector<std::vector<glm::dvec3>> weights(n, std::vector<glm::dvec3>(n));
  for (std::size_t v = 0; v < n; ++v)
    for (std::size_t u = 0; u < n; ++u)
      weights[v][u] = u == v
                          ? profile->integrateDisc(std::sqrt(areas[v] / M_PI))
                          : profile->evaluate(glm::length(mesh.positions[u] - mesh.positions[v])) *
                                double(areas[u]);
  const auto diffusion = [&](std::span<const glm::vec3> e, double = 1.0) {
    std::vector<glm::vec3> b(n);
    for (std::size_t v = 0; v < n; ++v) {
      glm::dvec3 sum(0.0);
      for (std::size_t u = 0; u < n; ++u) sum += weights[v][u] * glm::dvec3(e[u]);
      b[v] = glm::vec3(sum);
    }
    return b;
  };
  InterreflectionOptions options;
  options.rays = 64;
  const InterreflectionGather all(mesh.positions, mesh.normals, mesh.triangles, white, eta,
                                  options);
  const std::vector<glm::vec3> b0 = diffusion(direct);
  // The first bounce alone: what the spreading changes (the later ones, a series of the mean
  // gain, are the local transport's test's).
  const BounceResult one = iterateInterreflection(all, direct, b0, diffusion, 1, 1e-5);
  const double actual = relativeRms(one.exitance, b0);
  ASSERT_GT(actual, 0.02);
  options.vertices.clear();
  for (uint32_t v = 1; v < n; v += 4) options.vertices.push_back(v);
  const InterreflectionGather pilot(mesh.positions, mesh.normals, mesh.triangles, white, eta,
                                    options);
  const double unspread =
      estimateMissingInterreflection(pilot, options.vertices, b0, direct, areas).firstBounce;
  const double spread = estimateMissingInterreflection(pilot, options.vertices, b0, direct, areas,
                                                       {mesh.positions, profile.get(), 0})
                            .firstBounce;
  EXPECT_GT(unspread / actual, 1.2) << unspread << " " << actual;
  EXPECT_NEAR(spread / actual, 1.0, 0.1) << spread << " " << actual;
}

TEST(Interreflection, ConvexObjectsSendThemselvesNothing) {
  const TriangleMesh sphere = makeIcosphere(2, 10.0f);
  const Cubemap white(8, glm::vec3(1.0f));
  const InterreflectionGather gather(sphere.positions, sphere.normals, sphere.triangles, white,
                                     1.3f, {});
  EXPECT_EQ(gather.blockedFraction(), 0.0);
  const std::vector<glm::vec3> b(sphere.positions.size(), glm::vec3(1.0f));
  for (const glm::vec3& e : gather.gather(b)) EXPECT_EQ(e, glm::vec3(0.0f));
  const std::vector<glm::vec3> e(sphere.positions.size(), glm::vec3(2.0f));
  const std::vector<uint32_t> all = {0, 5, 9};
  EXPECT_EQ(estimateMissingInterreflection(gather, all, b, e, vertexAreas(sphere)).relativeRms,
            0.0);
}

// The pit box under a sky with a bright side (its +Y face) and its direct light: the scene of the
// bounces' own tests (the mirrored sky counts, and the pit gets light from its walls).
struct PitUnderSky {
  TriangleMesh mesh = boxWithPit();
  Cubemap sky{8, glm::vec3(0.3f, 0.4f, 0.5f)};
  float eta = 1.4f;
  std::vector<glm::vec3> direct;
  PitUnderSky() {
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 8; ++x) sky.at(int(CubeFace::PosY), x, y) = glm::vec3(4.0f, 3.0f, 2.0f);
    VisibilityOptions vis;
    vis.samples = 64;
    direct = transmittedIrradianceWithVisibility(mesh.positions, mesh.normals, mesh.triangles, sky,
                                                 eta, vis);
  }
};

// The bounces sum only what each adds, through the transport's linear part; iterating the whole
// transport, constant terms included (a traced far field), B_k = T(E_direct + gather(B_(k-1))),
// must give the same B and E. A transport that smooths (each vertex mixes with the next) and has a
// constant term, on the pit box under a sky with a bright direction (the mirrored sky counts).
TEST(Interreflection, SummingTheIncrementsEqualsIteratingTheWholeTransport) {
  const PitUnderSky scene;
  const auto& [mesh, sky, eta, direct] = scene;
  const std::size_t n = direct.size();
  const glm::vec3 albedo(0.8f, 0.5f, 0.3f), far(0.01f, 0.02f, 0.03f);
  const auto linear = [&](std::span<const glm::vec3> e, double = 1.0) {
    std::vector<glm::vec3> b(n);
    for (std::size_t v = 0; v < n; ++v) b[v] = albedo * (0.6f * e[v] + 0.4f * e[(v + 1) % n]);
    return b;
  };
  const auto whole = [&](std::span<const glm::vec3> e) {
    std::vector<glm::vec3> b = linear(e);
    for (glm::vec3& x : b) x += far;
    return b;
  };
  InterreflectionOptions options;
  options.rays = 32;
  const InterreflectionGather gather(mesh.positions, mesh.normals, mesh.triangles, sky, eta,
                                     options);
  const int bounces = 5;
  const std::vector<glm::vec3> b0 = whole(direct);
  const BounceResult r = iterateInterreflection(gather, direct, b0, linear, bounces, 0);
  std::vector<glm::vec3> e(direct.begin(), direct.end()), b = b0;
  for (int k = 0; k < bounces; ++k) {
    const std::vector<glm::vec3> light = gather.gather(b);
    for (std::size_t v = 0; v < n; ++v) e[v] = direct[v] + light[v];
    b = whole(e);
  }
  EXPECT_EQ(r.bounces, bounces);
  double moved = 0.0;
  for (std::size_t v = 0; v < n; ++v)
    for (int c = 0; c < 3; ++c) {
      ASSERT_NEAR(r.exitance[v][c], b[v][c], 1e-5 * b[v][c]) << "vertex " << v;
      ASSERT_NEAR(r.irradiance[v][c], e[v][c], 1e-5 * e[v][c]) << "vertex " << v;
      moved = std::max(moved, double(b[v][c] / b0[v][c]));
    }
  EXPECT_GT(moved, 1.2);  // the bounces matter in the pit
}

// A relight session (bake/relight.h) traces the gather's rays once and swaps the sky they mirror
// per environment: the gather must then be what one built under that sky is, bit for bit, and
// differ from the first sky's (the mirrored sky counts in the pit).
// A floor and a wall meeting at a right angle (40 mm squares, 1 mm cells), open, under a sun at
// 45 degrees in the plane across the corner: the sun mirrored by the floor lights the wall with
// E F_r(cos 45) cos 45, and the wall's image the floor; transmitted, times F_t(cos 45).
TriangleMesh floorAndWall() {
  TriangleMesh floor = makeGridPlane(40, 40.0f);
  TriangleMesh wall = floor;
  for (glm::vec3& p : wall.positions) p = glm::vec3(0.0f, p.y, p.x + 20.0f);
  for (glm::vec3& n : wall.normals) n = glm::vec3(1.0f, 0.0f, 0.0f);
  for (glm::uvec3& t : wall.triangles) std::swap(t.y, t.z);  // facing +x
  return joinedMeshes(std::move(floor), wall, glm::vec3(0.0f));
}

TEST(Interreflection, TracedMirrorImageOfASunMatchesTheCornersClosedForm) {
  TriangleMesh mesh = floorAndWall();
  for (std::size_t v = 0; v < mesh.positions.size() / 2; ++v) mesh.positions[v].x += 20.0f;
  const glm::vec3 sun = glm::normalize(glm::vec3(1.0f, 0.0f, 1.0f));
  const Cubemap sky = smallSun(sun);
  const CompactLightSplit split = splitCompactLights(sky);
  ASSERT_EQ(split.lights.size(), 1u);
  const float eta = 1.3f, mu = float(M_SQRT1_2);
  const double expected = split.lights[0].irradiance.g * fresnelDielectric(mu, eta) * mu *
                          fresnelTransmittance(mu, eta);
  // The vertices away from the edges, where the sun's images are uniform.
  std::vector<uint32_t> wall, floor;
  const std::size_t half = mesh.positions.size() / 2;
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    const glm::vec3 p = mesh.positions[v];
    const float along = v < half ? p.x : p.z;
    if (along > 8.0f && along < 32.0f && std::abs(p.y) < 12.0f)
      (v < half ? floor : wall).push_back(uint32_t(v));
  }
  InterreflectionOptions options;
  options.rays = 1;
  options.mirroredLightPaths = 256;
  const InterreflectionGather traced(mesh.positions, mesh.normals, mesh.triangles, sky, eta,
                                     options);
  const std::vector<glm::vec3> dark(mesh.positions.size(), glm::vec3(0.0f));
  const std::vector<glm::vec3> images = traced.gather(dark);
  InterreflectionOptions oneThread = options;
  oneThread.run.threads = 1;
  EXPECT_EQ(InterreflectionGather(mesh.positions, mesh.normals, mesh.triangles, sky, eta, oneThread)
                .gather(dark),
            images);  // the paths' deposits in path order, whatever the thread count
  for (const auto* side : {&wall, &floor}) {
    double sum = 0.0, squares = 0.0;
    for (const uint32_t v : *side) {
      const double e = images[v].g / expected;
      sum += e;
      squares += (e - 1.0) * (e - 1.0);
    }
    const double n = double(side->size());
    EXPECT_NEAR(sum / n, 1.0, 0.02);
    EXPECT_LT(std::sqrt(squares / n), 0.15);  // per vertex: the paths' noise
  }
  // The gather's own mirrored sky finds the same light, by chance and blurred: many rays at a few
  // wall vertices. Its 11-degree texels hold the sun's flux, which the lookup's interpolation
  // does not keep where the sun is on a face's edge, as here: 6.6 % high with 8,192 or 65,536 rays.
  InterreflectionOptions looked = options;
  looked.traceMirroredLights = false;
  looked.rays = 8192;
  for (std::size_t k = 0; k < wall.size(); k += wall.size() / 16)
    looked.vertices.push_back(wall[k]);
  const InterreflectionGather lookedUp(mesh.positions, mesh.normals, mesh.triangles, sky, eta,
                                       looked);
  const std::vector<glm::vec3> blurred = lookedUp.gather(dark);
  double sum = 0.0;
  for (const uint32_t v : looked.vertices) sum += blurred[v].g / expected;
  EXPECT_NEAR(sum / double(looked.vertices.size()), 1.0, 0.1);
}

TEST(Interreflection, SwappedSkyGathersAsAGatherBuiltUnderIt) {
  const PitUnderSky scene;
  const auto& [mesh, sky, eta, direct] = scene;
  Cubemap other(16, glm::vec3(0.1f, 0.2f, 0.1f));
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) other.at(int(CubeFace::NegX), x, y) = glm::vec3(9.0f, 1.0f, 5.0f);
  InterreflectionOptions options;
  options.rays = 16;
  options.keepMirrors = true;
  InterreflectionGather swapped(mesh.positions, mesh.normals, mesh.triangles, sky, eta, options);
  const std::vector<glm::vec3> first = swapped.gather(direct);
  swapped.setSky(other);
  const InterreflectionGather fresh(mesh.positions, mesh.normals, mesh.triangles, other, eta,
                                    options);
  EXPECT_EQ(swapped.gather(direct), fresh.gather(direct));
  EXPECT_GT(relativeRms(first, fresh.gather(direct)), 0.01);
  options.keepMirrors = false;
  InterreflectionGather kept(mesh.positions, mesh.normals, mesh.triangles, sky, eta, options);
  EXPECT_EQ(kept.gather(direct), first);  // keeping the mirrors changes nothing
  EXPECT_THROW(kept.setSky(other), Error);
}

// With bounces, the JSON's interreflection error is the gather's noise, measured from a replica of
// its rays with another seed at some vertices: it must match the spread of B over seeds. A local
// transport (no smoothing: one effective vertex), the pit box under a sky with a bright direction.
// visibilityRays: how many of the 16 rays per vertex are the visibility's cosine set (the bake's
// gather: one ray set, both uses), regenerated from the seed as a relight does.
void expectGatherNoiseAsPredicted(int visibilityRays) {
  const PitUnderSky scene;
  const auto& [mesh, sky, eta, direct] = scene;
  const std::size_t n = direct.size();
  const glm::vec3 albedo(0.9f, 0.7f, 0.5f);
  const auto local = [&](std::span<const glm::vec3> e, double = 1.0) {
    std::vector<glm::vec3> b(e.begin(), e.end());
    for (glm::vec3& x : b) x *= albedo;
    return b;
  };
  const std::vector<float> areas = vertexAreas(mesh);
  std::vector<uint32_t> half;
  for (uint32_t v = 0; v < n; v += 2) half.push_back(v);
  constexpr int kSeeds = 12;
  std::vector<std::vector<glm::vec3>> baked;
  double predicted = 0.0;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    InterreflectionOptions options;
    options.rays = 16;
    options.visibilityCosineRays = visibilityRays;
    options.run.seed = uint64_t(seed);
    const InterreflectionGather gather(mesh.positions, mesh.normals, mesh.triangles, sky, eta,
                                       options);
    options.run.seed += 1000;
    options.vertices = half;
    const InterreflectionGather replica(mesh.positions, mesh.normals, mesh.triangles, sky, eta,
                                        options);
    const BounceResult r = iterateInterreflection(gather, direct, local(direct), local, 0, 1e-4);
    predicted += predictGatherNoise(gather, replica, half, r.exitance, r.irradiance, areas, 1.0);
    baked.push_back(r.exitance);
  }
  predicted /= kSeeds;
  // The spread over seeds: sum over vertices of the sample variance, against sum |B|^2.
  double variance = 0.0, squares = 0.0;
  for (std::size_t v = 0; v < n; ++v) {
    glm::dvec3 mean(0.0);
    for (const auto& b : baked) mean += glm::dvec3(b[v]) / double(kSeeds);
    for (const auto& b : baked) {
      const glm::dvec3 d = glm::dvec3(b[v]) - mean;
      variance += glm::dot(d, d) / (kSeeds - 1);
    }
    squares += glm::dot(mean, mean);
  }
  const double measured = std::sqrt(variance / squares);
  ASSERT_GT(measured, 1e-3);  // the pit's rays do leave noise
  EXPECT_NEAR(predicted / measured, 1.0, 0.25) << predicted << " " << measured;
}

TEST(Interreflection, PredictedGatherNoiseMatchesTheSpreadOverSeeds) {
  expectGatherNoiseAsPredicted(0);
  expectGatherNoiseAsPredicted(8);
}

// The pit under the sky with a toy transport that smooths E over neighbouring indices and absorbs
// per channel, its gather of 64 rays and the direct light's B.
struct SmoothedPit {
  static std::vector<glm::vec3> smooth(std::span<const glm::vec3> e, double = 1.0) {
    std::vector<glm::vec3> b(e.size());
    for (std::size_t v = 0; v < e.size(); ++v)
      b[v] = glm::vec3(0.95f, 0.9f, 0.8f) * (0.5f * e[v] + 0.5f * e[(v + 1) % e.size()]);
    return b;
  }
  static InterreflectionGather gatherOf(const PitUnderSky& scene) {
    InterreflectionOptions options;
    options.rays = 64;
    return {scene.mesh.positions,
            scene.mesh.normals,
            scene.mesh.triangles,
            scene.sky,
            scene.eta,
            options};
  }
  PitUnderSky scene;
  InterreflectionGather gather = gatherOf(scene);
  std::vector<glm::vec3> direct = scene.direct;
  BounceTransport smoothing = [](std::span<const glm::vec3> e, double l) { return smooth(e, l); };
  std::vector<glm::vec3> b0 = smooth(direct);
};

// A bake with fewer bounces than convergence needs reports what the rest would add (one more
// gather estimates the series' ratio): it must match the difference to the converged B.
TEST(Interreflection, RemainingBouncesAreEstimatedFromOneMoreGather) {
  const SmoothedPit pit;
  const auto& [scene, gather, direct, smoothing, b0] = pit;
  const BounceResult converged = iterateInterreflection(gather, direct, b0, smoothing, 0, 1e-7);
  EXPECT_LT(converged.remaining, 1e-6);
  for (int bounces : {1, 2, 3}) {
    const BounceResult r = iterateInterreflection(gather, direct, b0, smoothing, bounces, 0.0);
    const double actual = relativeRms(converged.exitance, r.exitance);
    ASSERT_GT(actual, 1e-4) << bounces;
    EXPECT_NEAR(r.remaining / actual, 1.0, 0.3) << bounces << ": " << r.remaining << " " << actual;
  }
}

// Auto with the geometric tail (per vertex and channel ratios): fewer bounces than the plain
// series needs for the same convergence target, within that target of the converged B, and the
// error it reports holds. The same bounces without the tail miss by more.
TEST(Interreflection, GeometricTailEndsTheSeriesEarly) {
  const SmoothedPit pit;
  const auto& [scene, gather, direct, smoothing, b0] = pit;
  const BounceResult converged = iterateInterreflection(gather, direct, b0, smoothing, 0, 1e-9);
  constexpr double kTarget = 1e-3;
  const BounceResult plain = iterateInterreflection(gather, direct, b0, smoothing, 0, kTarget);
  const BounceResult tailed =
      iterateInterreflection(gather, direct, b0, smoothing, 0, kTarget, BounceTail::Geometric);
  ASSERT_TRUE(tailed.tail);
  EXPECT_LT(tailed.bounces, plain.bounces) << tailed.bounces << " " << plain.bounces;
  const double error = relativeRms(tailed.exitance, converged.exitance);
  EXPECT_LT(error, kTarget);
  EXPECT_LT(error, 2.0 * tailed.remaining + 1e-5) << error << " " << tailed.remaining;
  const BounceResult cut = iterateInterreflection(gather, direct, b0, smoothing, tailed.bounces, 0);
  EXPECT_GT(relativeRms(cut.exitance, converged.exitance), 5.0 * error);
  // The tail's light is in E as well: E and B stay one transport apart.
  const std::vector<glm::vec3> again = smoothing(tailed.irradiance, 1.0);
  EXPECT_LT(relativeRms(again, tailed.exitance), 2e-5);
}

}  // namespace
}  // namespace sss
