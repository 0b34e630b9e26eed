#include "transport/interreflection.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>

#include <glm/geometric.hpp>

#include "core/barycentric.h"
#include "core/bounds.h"
#include "core/error.h"
#include "core/parallel.h"
#include "core/random.h"
#include "core/sampling.h"
#include "envmap/compact_lights.h"
#include "lighting/facet_light.h"
#include "material/diffusion_profile.h"
#include "optics/fresnel.h"
#include "raytrace/triangle_scene.h"
#include "transport/surface_hit.h"

namespace sss {

namespace {

// The sky the gather's hits mirror is looked up at this face size (texels of ~11 degrees, the
// flux of each kept: Cubemap::resized). A mirror direction finds a small bright source only by
// chance, and brings far more than the sky when it does, so at full resolution the bounces would
// spread a few vertices' fireflies (docs/tools/sss-bake.md, "Bounces and interreflection"). The
// compact lights are traced from the lights (mirrored_lights.h); what the texels still hold is
// the rest of the sky, and a source too wide or too dim to count as a compact light, whose
// reflected patch they blur by their width.
constexpr int kMirrorSkyFaceSize = 8;

// Mixed into the seed of the compact lights' mirror images (mirrored_lights.h).
constexpr uint64_t kMirroredLightSeed = 0x6d6972726f72ull;

// The paths for the compact lights' images: their noise relative to E goes as the lights' share
// of the flux over the square root of the paths, so perVertex at a share of 1 (a sun alone) and
// share^2 of it elsewhere, at least one per vertex (sunrise.exr, 59 %: 6; forest.exr, 12 %: 1).
uint64_t mirroredLightPaths(int perVertex, double fluxShare, std::size_t vertices) {
  const double share = std::clamp(fluxShare, 0.0, 1.0);
  return uint64_t(std::max(1.0, std::ceil(perVertex * share * share))) * vertices;
}

Cubemap mirrorSkyOf(const Cubemap& radiance) {
  return radiance.size() > kMirrorSkyFaceSize ? radiance.resized(kMirrorSkyFaceSize) : radiance;
}

// One vertex's gather rays as streams (TriangleScene::intersect): the first hits, then the
// mirror rays of those that met the front of a surface. Reused per thread.
struct GatherStreams {
  std::vector<OcclusionRay> rays, mirrorRays;
  std::vector<glm::vec3> entry;  // per ray: pi / N F_t w / pdf over the facets (the throughput)
  std::vector<SceneHit> hits, mirrorHits;
  std::vector<SurfaceHit> firsts;
  std::vector<uint32_t> sample;  // per ray: its index in the vertex's set (frontHits' bit)
};

// What every vertex's rays share.
struct GatherSetup {
  std::span<const glm::vec3> positions, normals;
  std::span<const glm::uvec3> triangles;
  const VertexFacets& facets;
  const DirectionalAlbedoWeight& weight;
  float eta, extent, perRay;
  std::span<const uint16_t> frontHits;  // InterreflectionOptions::frontHits
  std::size_t words;                    // frontHitWords per vertex
  // Whether vertex v's ray j may meet the front of a surface (no frontHits: every ray may).
  bool mayHit(uint32_t v, uint32_t j) const {
    return frontHits.empty() || (frontHits[v * words + j / 16] >> (j % 16) & 1u) != 0;
  }
};

// Appends vertex v's rays of one stratified set (Hammersley, `count` points rotated by (ra, rb))
// from the facets' cosine lobes, those the facets take light in (facet_light.h), as the
// environment's light is taken. visibilityOrder: the throughput rounded as the visibility's kept
// hits hold it (lighting/cosine_hits.h), so that a set traced here equals the one taken from them.
// `first`: the set's first ray's index among the vertex's rays (frontHits' bits).
void appendCosineRays(const GatherSetup& s, uint32_t v, uint32_t count, uint32_t first, float ra,
                      float rb, bool visibilityOrder, GatherStreams& g) {
  const glm::vec3 nv = s.normals[v], p = s.positions[v];
  const float offset = surfaceRayOffset(p, s.extent);
  for (uint32_t j = 0; j < count; ++j) {
    if (!s.mayHit(v, first + j)) continue;
    float u1, u2;
    hammersley(j, count, ra, rb, u1, u2);
    const glm::vec3 w = sampleFacetCosine(s.facets, v, nv, u1, u2);
    const FacetIntake intake = facetIntake(s.facets, v, nv, w, s.eta, &s.weight);
    if (!(intake.transmitted > 0.0f)) continue;
    g.rays.push_back({p + offset * nv, w, offset, std::numeric_limits<float>::infinity()});
    g.entry.push_back(visibilityOrder ? s.perRay * (intake.entryWeighted / intake.cosinePdf)
                                      : s.perRay / intake.cosinePdf * intake.entryWeighted);
    g.sample.push_back(first + j);
  }
}

// Appends vertex v's kept visibility hits as first hits (no tracing).
void appendTracedRays(const GatherSetup& s, const TriangleScene& scene, const CosineHits& traced,
                      uint32_t v, GatherStreams& g) {
  const glm::vec3 p = s.positions[v], nv = s.normals[v];
  const float offset = surfaceRayOffset(p, s.extent);
  for (uint32_t k = traced.offsets[v]; k < traced.offsets[v + 1]; ++k) {
    const CosineHit& c = traced.hits[k];
    g.rays.push_back(
        {p + offset * nv, c.direction, offset, std::numeric_limits<float>::infinity()});
    g.entry.push_back(s.perRay * c.weight);
    g.sample.push_back(c.sample);
    const SceneHit hit{c.t, scene.faceNormal(c.triangle), c.triangle, true};
    g.firsts.push_back(
        surfaceHitOf(hit, s.positions, s.normals, s.triangles, g.rays.back().origin, c.direction));
  }
}

// Traces the rays from index `from` on (their first hits), then the mirror rays of every valid
// first hit; returns how many first hits met the mesh.
uint64_t traceGatherRays(const GatherSetup& s, const TriangleScene& scene, std::size_t from,
                         GatherStreams& g) {
  scene.intersect(std::span(g.rays).subspan(from), g.hits);
  for (std::size_t k = from; k < g.rays.size(); ++k)
    g.firsts.push_back(surfaceHitOf(g.hits[k - from], s.positions, s.normals, s.triangles,
                                    g.rays[k].origin, g.rays[k].direction));
  g.mirrorRays.clear();
  uint64_t met = 0;
  for (std::size_t k = 0; k < g.rays.size(); ++k) {
    const SurfaceHit& first = g.firsts[k];
    met += first.hit;
    if (!first.valid) continue;
    const float o = surfaceRayOffset(first.point, s.extent);
    g.mirrorRays.push_back({first.point + o * first.faceNormal,
                            mirrorDirection(first, g.rays[k].direction), o,
                            std::numeric_limits<float>::infinity()});
  }
  scene.intersect(g.mirrorRays, g.mirrorHits);
  return met;
}

}  // namespace

InterreflectionGather::InterreflectionGather(std::span<const glm::vec3> positions,
                                             std::span<const glm::vec3> normals,
                                             std::span<const glm::uvec3> triangles,
                                             const Cubemap& radiance, float eta,
                                             const InterreflectionOptions& options) {
  const std::size_t n = positions.size();
  if (normals.size() != n || triangles.empty()) fail("", "interreflection: empty mesh");
  if (options.rays < 1 || options.visibilityCosineRays < 0)
    fail("", "interreflection: at least one ray per vertex");
  const CosineHits* traced = options.traced;
  if (traced && (traced->offsets.size() != n + 1 || !options.vertices.empty() ||
                 traced->perVertex != options.visibilityCosineRays))
    fail("", "interreflection: the traced rays must be the whole mesh's visibility set");
  std::optional<TriangleScene> own;
  const TriangleScene& scene = givenOrBuilt(options.scene, own, positions, triangles,
                                            TriangleSceneOptions::surfaceRays(options.run.threads));
  const float exitScale = float(exitRadianceScale(eta));
  const DirectionalAlbedoWeight diffuse;
  mirroredSetup_ = mirroredLightsSetup(options, eta, positions, normals, triangles);
  const Cubemap mirrorSky =
      mirrorSkyFor(radiance, &scene, options.mirroredLightsOf, positions, normals, triangles);
  const uint32_t visibilitySet = uint32_t(options.visibilityCosineRays);
  const uint32_t total = std::max(uint32_t(options.rays), visibilitySet);
  const uint32_t ownSet = total - visibilitySet;
  const VertexFacets facets = lightFacets(positions, normals, triangles);
  const std::size_t words = frontHitWords(int(total));
  if (!options.frontHits.empty() && options.frontHits.size() != n * words)
    fail("", "interreflection: the front hits must hold " + std::to_string(words) +
                 " words per vertex");
  const GatherSetup setup{positions,
                          normals,
                          triangles,
                          facets,
                          options.entry ? *options.entry : diffuse,
                          eta,
                          boundsOf(positions).longestSide(),
                          1.0f / float(total),
                          options.frontHits,
                          words};
  if (options.keepFrontHits) frontHits_.assign(n * words, 0);
  std::vector<uint32_t> vertices = options.vertices;
  if (vertices.empty()) {
    vertices.resize(n);
    for (std::size_t v = 0; v < n; ++v) vertices[v] = uint32_t(v);
  }
  std::vector<uint32_t> hitCount(n, 0);  // per vertex, counted as traced
  {
    std::vector<char> listed(n, 0);
    for (const uint32_t v : vertices) {
      if (v >= n) fail("", "interreflection: a traced vertex is not in the mesh");
      if (listed[v]) fail("", "interreflection: a vertex is listed twice");
      listed[v] = 1;
    }
  }
  // The hits of each parallelFor chunk of vertices, in the order traced (vertex after vertex),
  // laid out per vertex once all are traced: a few vectors, not one per vertex.
  constexpr std::size_t kGrain = 64;
  std::vector<std::vector<Hit>> chunkHits((vertices.size() + kGrain - 1) / kGrain);
  std::vector<std::vector<Mirror>> chunkMirrors(options.keepMirrors ? chunkHits.size() : 0);
  std::atomic<uint64_t> blocked{0};
  // The light leaving a hit towards where the ray came from: its exit radiance from B, and the
  // sky it mirrors (along `mirror`); where the mirror direction meets the object again (`second`,
  // the mirror ray's hit; null for a second hit itself), the light leaving that second hit instead
  // (its exit radiance and its mirrored sky: one specular bounce more, which keeps a white furnace
  // at 1 up to third-order mirror paths).
  const auto addHit = [&](std::size_t chunk, uint32_t v, const SurfaceHit& h,
                          const glm::vec3& mirror, const glm::vec3& throughput,
                          const SurfaceHit* second) {
    const float fr = fresnelDielectric(h.mu, eta);
    const bool open = !second || (!second->hit && glm::dot(mirror, h.faceNormal) > 0.0f);
    const glm::vec3 mirrorWeight = open ? throughput * fr : glm::vec3(0.0f);
    chunkHits[chunk].push_back(
        {h.vertices, h.barycentric, throughput * fresnelTransmittance(h.mu, eta) * exitScale,
         open ? mirrorWeight * mirrorSky.sample(mirror) : glm::vec3(0.0f), second == nullptr});
    if (options.keepMirrors) chunkMirrors[chunk].push_back({mirror, mirrorWeight});
    ++hitCount[v];
  };
  parallelFor(
      vertices.size(), options.run.threads, kGrain, [&](std::size_t begin, std::size_t end) {
        const std::size_t chunk = begin / kGrain;
        thread_local GatherStreams g;
        uint64_t count = 0;
        for (std::size_t i = begin; i < end; ++i) {
          const uint32_t v = vertices[i];
          // The same stream as the visibility's (visibility_vertex_estimator.cpp): its first two
          // numbers rotate the set traced here, its next two the visibility's cosine set.
          Pcg32 rng(options.run.seed, v);
          const float r0 = rng.uniform(), r1 = rng.uniform(), r2 = rng.uniform(),
                      r3 = rng.uniform();
          g.rays.clear();
          g.entry.clear();
          g.firsts.clear();
          g.sample.clear();
          if (traced)
            appendTracedRays(setup, scene, *traced, v, g);
          else
            appendCosineRays(setup, v, visibilitySet, 0, r2, r3, true, g);
          const std::size_t from = g.firsts.size();  // the rays from here on are traced below
          appendCosineRays(setup, v, ownSet, visibilitySet, r0, r1, false, g);
          count += traceGatherRays(setup, scene, from, g);
          std::size_t m = 0;
          for (std::size_t k = 0; k < g.rays.size(); ++k) {
            const SurfaceHit& first = g.firsts[k];
            if (!first.valid) continue;
            if (options.keepFrontHits)
              frontHits_[v * words + g.sample[k] / 16] |= uint16_t(1u << (g.sample[k] % 16));
            const OcclusionRay& mirrorRay = g.mirrorRays[m];
            const SurfaceHit second = surfaceHitOf(g.mirrorHits[m++], positions, normals, triangles,
                                                   mirrorRay.origin, mirrorRay.direction);
            addHit(chunk, v, first, mirrorRay.direction, g.entry[k], &second);
            if (second.valid)
              addHit(chunk, v, second, mirrorDirection(second, mirrorRay.direction),
                     g.entry[k] * fresnelDielectric(first.mu, eta), nullptr);
          }
        }
        blocked += count;
      });
  layOutPerVertex(vertices, kGrain, hitCount, std::move(chunkHits), std::move(chunkMirrors));
  rays_ = int(total);
  threads_ = options.run.threads;
  visibilityCosineRays_ = options.visibilityCosineRays;
  blockedFraction_ = double(blocked) / double(std::max<std::size_t>(vertices.size() * total, 1));
}

void InterreflectionGather::layOutPerVertex(std::span<const uint32_t> vertices, std::size_t grain,
                                            std::span<const uint32_t> hitCount,
                                            std::vector<std::vector<Hit>> chunkHits,
                                            std::vector<std::vector<Mirror>> chunkMirrors) {
  const std::size_t n = hitCount.size();
  offsets_.assign(n + 1, 0);
  for (std::size_t v = 0; v < n; ++v) offsets_[v + 1] = offsets_[v] + hitCount[v];
  hits_.resize(offsets_[n]);
  mirrors_.resize(chunkMirrors.empty() ? 0 : offsets_[n]);
  for (std::size_t c = 0; c < chunkHits.size(); ++c) {
    std::size_t k = 0;  // the chunk's hits laid out so far
    for (std::size_t i = c * grain; i < std::min(vertices.size(), (c + 1) * grain); ++i) {
      const uint32_t v = vertices[i];
      std::copy_n(chunkHits[c].begin() + k, hitCount[v], hits_.begin() + offsets_[v]);
      if (!chunkMirrors.empty())
        std::copy_n(chunkMirrors[c].begin() + k, hitCount[v], mirrors_.begin() + offsets_[v]);
      k += hitCount[v];
    }
    std::vector<Hit>().swap(chunkHits[c]);  // freed as it is laid out
    if (!chunkMirrors.empty()) std::vector<Mirror>().swap(chunkMirrors[c]);
  }
}

InterreflectionGather::MirroredLightsSetup InterreflectionGather::mirroredLightsSetup(
    const InterreflectionOptions& options, float eta, std::span<const glm::vec3> positions,
    std::span<const glm::vec3> normals, std::span<const glm::uvec3> triangles) {
  MirroredLightsSetup m;
  m.eta = eta;
  if (options.entry) m.entry = *options.entry;
  m.pathsPerVertex = options.traceMirroredLights ? std::max(options.mirroredLightPaths, 0) : 0;
  m.run = options.run;
  if (options.keepMirrors && m.pathsPerVertex > 0) {  // for setSky
    m.positions.assign(positions.begin(), positions.end());
    m.normals.assign(normals.begin(), normals.end());
    m.triangles.assign(triangles.begin(), triangles.end());
  }
  return m;
}

Cubemap InterreflectionGather::mirrorSkyFor(const Cubemap& radiance, const TriangleScene* scene,
                                            const InterreflectionGather* same,
                                            std::span<const glm::vec3> positions,
                                            std::span<const glm::vec3> normals,
                                            std::span<const glm::uvec3> triangles) {
  mirroredLights_ = {};
  const MirroredLightsSetup& m = mirroredSetup_;
  if (m.pathsPerVertex == 0) return mirrorSkyOf(radiance);
  const CompactLightSplit split = splitCompactLights(radiance);
  if (split.lights.empty()) return mirrorSkyOf(radiance);
  if (same) {
    if (same->mirroredLights_.irradiance.size() != positions.size())
      fail("", "interreflection: the gather to take the lights' images from traced none");
    mirroredLights_ = same->mirroredLights_;
    return mirrorSkyOf(split.rest);
  }
  std::optional<TriangleScene> own;
  const TriangleScene& rays = givenOrBuilt(scene, own, positions, triangles,
                                           TriangleSceneOptions::surfaceRays(m.run.threads));
  RunContext run = m.run;
  run.seed ^= kMirroredLightSeed;  // streams of their own, not the gather rays' per vertex
  mirroredLights_ = traceMirroredLights(
      {.positions = positions,
       .normals = normals,
       .triangles = triangles,
       .scene = rays,
       .lights = split.lights,
       .eta = m.eta,
       .entry = m.entry,
       .paths = mirroredLightPaths(m.pathsPerVertex, split.fluxShare, positions.size()),
       .run = run});
  return mirrorSkyOf(split.rest);
}

void InterreflectionGather::setSky(const Cubemap& radiance, const TriangleScene* scene) {
  if (mirrors_.size() != hits_.size())
    fail("", "interreflection: setSky needs a gather that kept its mirrors");
  const MirroredLightsSetup& m = mirroredSetup_;
  const Cubemap mirrorSky =
      mirrorSkyFor(radiance, scene, nullptr, m.positions, m.normals, m.triangles);
  for (std::size_t k = 0; k < hits_.size(); ++k) {
    const Mirror& m = mirrors_[k];
    hits_[k].reflection =
        m.weight != glm::vec3(0.0f) ? m.weight * mirrorSky.sample(m.direction) : glm::vec3(0.0f);
  }
}

std::vector<glm::vec3> InterreflectionGather::gather(std::span<const glm::vec3> exitance,
                                                     std::vector<glm::vec3>* variance,
                                                     bool mirrored) const {
  const std::size_t n = offsets_.size() - 1;
  if (exitance.size() != n) fail("", "interreflection: one exitance per vertex needed");
  std::vector<glm::vec3> e(n, glm::vec3(0.0f));
  if (variance) variance->assign(n, glm::vec3(0.0f));
  // Each vertex's sum alone, in its hits' order: the same for any thread count.
  parallelFor(n, threads_, 1024, [&](std::size_t begin, std::size_t end) {
    for (std::size_t v = begin; v < end; ++v) {
      glm::dvec3 ray(0.0), squares(0.0);  // the current ray's light; the sum of squares over rays
      for (uint32_t k = offsets_[v]; k < offsets_[v + 1]; ++k) {
        const Hit& h = hits_[k];
        const glm::vec3 b = h.barycentric.x * exitance[h.vertices.x] +
                            h.barycentric.y * exitance[h.vertices.y] +
                            h.barycentric.z * exitance[h.vertices.z];
        const glm::vec3 light = h.exitWeight * b + (mirrored ? h.reflection : glm::vec3(0.0f));
        e[v] += light;
        if (!h.sameRay) {
          squares += ray * ray;
          ray = glm::dvec3(0.0);
        }
        ray += glm::dvec3(light);
      }
      squares += ray * ray;
      // The compact lights' mirror images, traced from the lights: no ray of this vertex's.
      const glm::vec3 images = mirrored && !mirroredLights_.irradiance.empty()
                                   ? mirroredLights_.irradiance[v]
                                   : glm::vec3(0.0f);
      if (variance && rays_ > 1) {
        // Var(sum of N rays) = N var(one ray) = N (sum x^2 - (sum x)^2 / N) / (N - 1).
        const double count = double(rays_);
        const glm::dvec3 sum(e[v]);
        (*variance)[v] = glm::vec3(count * (squares - sum * sum / count) / (count - 1.0));
      }
      e[v] += images;
    }
  });
  return e;
}

namespace {

double squaredNorm(std::span<const glm::vec3> values) {
  double sum = 0.0;
  for (const glm::vec3& x : values) sum += glm::dot(glm::dvec3(x), glm::dvec3(x));
  return sum;
}

// The transport's energy ratio over the object per channel, k = sum B A / sum E A (what leaves per
// what enters): how a change of E at a vertex shows in B, the transport's smoothing left out.
glm::dvec3 energyRatio(std::span<const glm::vec3> exitance, std::span<const glm::vec3> irradiance,
                       std::span<const float> areas) {
  if (irradiance.size() != exitance.size() || areas.size() != exitance.size())
    fail("", "interreflection: one irradiance and area per vertex needed");
  glm::dvec3 leaving(0.0), entering(0.0);
  for (std::size_t v = 0; v < exitance.size(); ++v) {
    leaving += double(areas[v]) * glm::dvec3(exitance[v]);
    entering += double(areas[v]) * glm::dvec3(irradiance[v]);
  }
  glm::dvec3 k(0.0);
  for (int c = 0; c < 3; ++c) k[c] = entering[c] > 0.0 ? leaving[c] / entering[c] : 0.0;
  return k;
}

// The first bounce's light at the pilot's vertices as the transport would spread it
// (TransportSmoothing), with its rays' variance carried through the same weights.
struct PilotLight {
  std::vector<glm::dvec3> light, variance;  // per pilot vertex, in `vertices`' order
};

PilotLight smoothOverPilot(std::span<const uint32_t> vertices, std::span<const glm::vec3> added,
                           std::span<const glm::vec3> variance, std::span<const float> areas,
                           const TransportSmoothing& smoothing) {
  const std::size_t n = vertices.size();
  PilotLight p{std::vector<glm::dvec3>(n), std::vector<glm::dvec3>(n)};
  if (!smoothing.profile) {
    for (std::size_t i = 0; i < n; ++i) {
      p.light[i] = glm::dvec3(added[vertices[i]]);
      p.variance[i] = glm::dvec3(variance[vertices[i]]);
    }
    return p;
  }
  if (smoothing.positionsMm.size() != added.size())
    fail("", "interreflection: one position per vertex needed for the transport's smoothing");
  // Each pilot vertex stands for its share of the whole surface.
  double total = 0.0, pilot = 0.0;
  for (const float a : areas) total += a;
  for (const uint32_t v : vertices) pilot += areas[v];
  const double scale = pilot > 0.0 ? total / pilot : 0.0;
  const DiffusionProfile& profile = *smoothing.profile;
  const double reach = profile.radiusContaining(0.999);
  parallelFor(n, smoothing.threads, 16, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      const glm::vec3 x = smoothing.positionsMm[vertices[i]];
      glm::dvec3 sum(0.0), sumVariance(0.0), weights(0.0);
      for (std::size_t j = 0; j < n; ++j) {
        const uint32_t u = vertices[j];
        const double share = scale * areas[u];
        const double r = glm::length(smoothing.positionsMm[u] - x);
        if (j != i && r > reach) continue;
        // The vertex's own share integrates the profile's peak (as the diffusion sum's self term).
        const glm::dvec3 w =
            j == i ? profile.integrateDisc(std::sqrt(share / M_PI)) : profile.evaluate(r) * share;
        sum += w * glm::dvec3(added[u]);
        sumVariance += w * w * glm::dvec3(variance[u]);
        weights += w;
      }
      for (int c = 0; c < 3; ++c) {
        if (!(weights[c] > 0.0)) continue;
        p.light[i][c] = sum[c] / weights[c];
        p.variance[i][c] = sumVariance[c] / (weights[c] * weights[c]);
      }
    }
  });
  return p;
}

}  // namespace

MissingInterreflection estimateMissingInterreflection(const InterreflectionGather& gather,
                                                      std::span<const uint32_t> vertices,
                                                      std::span<const glm::vec3> exitance,
                                                      std::span<const glm::vec3> irradiance,
                                                      std::span<const float> areas,
                                                      const TransportSmoothing& smoothing) {
  const glm::dvec3 k = energyRatio(exitance, irradiance, areas);
  std::vector<glm::vec3> variance;
  const std::vector<glm::vec3> added = gather.gather(exitance, &variance);
  const PilotLight light = smoothOverPilot(vertices, added, variance, areas, smoothing);
  // The squares' sum less the rays' noise in it (a sun the mirror direction finds by chance
  // would otherwise count as light). The gain is the light's, before the smoothing.
  double sumAdded = 0.0, sumB = 0.0, squaredAdded = 0.0, noise = 0.0, squaredB = 0.0;
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const uint32_t v = vertices[i];
    const glm::dvec3 dB = k * light.light[i], b(exitance[v]), unsmoothed = k * glm::dvec3(added[v]);
    sumAdded += unsmoothed.x + unsmoothed.y + unsmoothed.z;
    sumB += b.x + b.y + b.z;
    squaredAdded += glm::dot(dB, dB);
    noise += glm::dot(k * k, light.variance[i]);
    squaredB += glm::dot(b, b);
  }
  MissingInterreflection m;
  if (!(sumB > 0.0 && squaredB > 0.0)) return m;
  m.gain = sumAdded / sumB;
  m.firstBounce = std::sqrt(std::max(0.0, squaredAdded - noise) / squaredB);
  m.relativeRms = m.firstBounce / (1.0 - std::min(m.gain, 0.9));
  return m;
}

double predictGatherNoise(const InterreflectionGather& gather, const InterreflectionGather& replica,
                          std::span<const uint32_t> vertices, std::span<const glm::vec3> exitance,
                          std::span<const glm::vec3> irradiance, std::span<const float> areas,
                          double effectiveVertices) {
  const glm::dvec3 k = energyRatio(exitance, irradiance, areas);
  const double squaredB = squaredNorm(exitance);
  if (!(squaredB > 0.0) || vertices.empty()) return 0.0;
  const std::vector<glm::vec3> a = gather.gather(exitance), b = replica.gather(exitance);
  double noise = 0.0;  // sum over the replica's vertices of k^2 Var(E_ir)
  const std::span<const glm::vec3> images = gather.mirroredLightVariance();
  for (const uint32_t v : vertices) {
    const glm::dvec3 d = k * (glm::dvec3(a[v]) - glm::dvec3(b[v]));
    noise += 0.5 * glm::dot(d, d);
    // The compact lights' images, which the replica shares: their paths' own variance.
    if (!images.empty()) noise += glm::dot(k * k, glm::dvec3(images[v]));
  }
  noise *= double(exitance.size()) / double(vertices.size());
  return std::sqrt(noise / std::max(effectiveVertices, 1.0) / squaredB);
}

namespace {

// Per vertex and channel the ratio last / previous of two increments, capped at kMaxTailRatio; 0
// where the previous one is 0.
constexpr double kMaxTailRatio = 0.95;

glm::dvec3 ratioOf(const glm::vec3& previous, const glm::vec3& last) {
  glm::dvec3 r(0.0);
  for (int c = 0; c < 3; ++c)
    if (previous[c] > 0.0f) r[c] = std::clamp(double(last[c]) / previous[c], 0.0, kMaxTailRatio);
  return r;
}

}  // namespace

GeometricTail bounceTail(std::span<const glm::vec3> earlier, std::span<const glm::vec3> previous,
                         std::span<const glm::vec3> last, std::span<const glm::vec3> lastLight) {
  const std::size_t n = last.size();
  if (previous.size() != n || lastLight.size() != n || (!earlier.empty() && earlier.size() != n))
    fail("", "interreflection: the tail needs its increments and light per vertex");
  GeometricTail t{std::vector<glm::vec3>(n), std::vector<glm::vec3>(n), 0.0};
  double squares = 0.0;  // of the tail's change between the two ratios (or of the tail)
  for (std::size_t v = 0; v < n; ++v) {
    const glm::dvec3 rho = ratioOf(previous[v], last[v]);
    const glm::dvec3 tail = glm::dvec3(last[v]) * rho / (1.0 - rho);
    t.exitance[v] = glm::vec3(tail);
    t.irradiance[v] = glm::vec3(glm::dvec3(lastLight[v]) * rho / (1.0 - rho));
    glm::dvec3 d = tail;
    if (!earlier.empty()) {
      const glm::dvec3 before = ratioOf(earlier[v], previous[v]);
      d -= glm::dvec3(last[v]) * before / (1.0 - before);
    }
    squares += glm::dot(d, d);
  }
  t.squaredError = squares;
  return t;
}

namespace {

void addTo(std::vector<glm::vec3>& sum, std::span<const glm::vec3> x) {
  for (std::size_t v = 0; v < sum.size(); ++v) sum[v] += x[v];
}

}  // namespace

BounceResult iterateInterreflection(const InterreflectionGather& gather,
                                    std::span<const glm::vec3> direct,
                                    std::vector<glm::vec3> initial,
                                    const BounceTransport& increment, int maxBounces,
                                    double tolerance, BounceTail tail) {
  constexpr int kAutoBounceLimit = 64;
  const std::size_t n = direct.size();
  if (initial.size() != n) fail("", "interreflection: one initial exitance per vertex needed");
  BounceResult r;
  r.irradiance.assign(direct.begin(), direct.end());
  r.exitance = std::move(initial);
  std::vector<glm::vec3> added = r.exitance;  // what the last bounce added to B (B_0 at first)
  std::vector<glm::vec3> previous, earlier, light;  // dB_(k-1), dB_(k-2); dE_k
  const double directSquares = squaredNorm(direct);
  double lastLight = 0.0;  // |dE_k|^2 of the last bounce
  const int limit = maxBounces > 0 ? maxBounces : kAutoBounceLimit;
  const bool geometric = tail == BounceTail::Geometric;
  std::optional<GeometricTail> extrapolated;
  for (int bounce = 0; bounce < limit; ++bounce) {
    light = gather.gather(added, nullptr, bounce == 0);
    lastLight = squaredNorm(light);
    const double share = std::sqrt(lastLight / std::max(directSquares, 1e-300));
    const double looseness = std::max(1.0, std::ldexp(1.0, -(bounce + 2)) / share);
    earlier = std::exchange(previous, std::exchange(added, increment(light, looseness)));
    if (added.size() != n) fail("", "interreflection: one exitance per vertex needed");
    const double before = squaredNorm(r.exitance);  // |B_(k-1)|^2
    addTo(r.irradiance, light);
    addTo(r.exitance, added);
    r.change = before > 0.0 ? std::sqrt(squaredNorm(added) / before) : 0.0;
    r.bounces = bounce + 1;
    // The tail needs two increments of the bounces' own light (dB_0 is the direct light's B).
    if (geometric && r.bounces >= 2)
      extrapolated =
          bounceTail(r.bounces >= 3 ? earlier : std::vector<glm::vec3>{}, previous, added, light);
    if (maxBounces > 0) continue;
    if (extrapolated &&
        extrapolated->squaredError < tolerance * tolerance * squaredNorm(r.exitance))
      break;
    if (r.change < tolerance) break;
  }
  if (extrapolated) {
    addTo(r.irradiance, extrapolated->irradiance);
    addTo(r.exitance, extrapolated->exitance);
    const double b = squaredNorm(r.exitance);
    r.remaining = b > 0.0 ? std::sqrt(extrapolated->squaredError / b) : 0.0;
    r.tail = true;
  } else if (r.bounces > 0 && lastLight > 0.0) {
    const double ratio = std::sqrt(squaredNorm(gather.gather(added, nullptr, false)) / lastLight);
    const double rho = std::min(ratio, 0.95);
    r.remaining = r.change * rho / (1.0 - rho);
  }
  return r;
}

}  // namespace sss
