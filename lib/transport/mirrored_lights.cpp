#include "transport/mirrored_lights.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "core/bounds.h"
#include "core/error.h"
#include "core/luminance.h"
#include "core/parallel.h"
#include "core/random.h"
#include "core/sampling.h"
#include "mesh/triangle_mesh.h"
#include "optics/fresnel.h"
#include "raytrace/triangle_scene.h"
#include "transport/surface_hit.h"

namespace sss {

namespace {

// Which light a path goes to: by the lights' luminance at normal incidence (cumulative, last 1).
std::vector<double> lightChoice(std::span<const DirectionalLight> lights) {
  std::vector<double> cdf(lights.size());
  double sum = 0.0;
  for (std::size_t l = 0; l < lights.size(); ++l) {
    sum += std::max(0.0, double(luminance(lights[l].irradiance)));
    cdf[l] = sum;
  }
  for (double& c : cdf) c = sum > 0.0 ? c / sum : 1.0;
  if (!cdf.empty()) cdf.back() = 1.0;
  return cdf;
}

struct Deposit {
  uint32_t vertex;
  glm::vec3 irradiance;
};

// The object as the paths see it: its bounding sphere and the hat functions' areas.
struct PathSetup {
  const MirroredLightsInput& in;
  std::vector<double> choice;
  std::vector<float> vertexAreas;  // a third of each vertex's triangles' area, mm^2
  glm::vec3 center{0.0f};
  double radius = 0.0;
  float extent = 0.0f;
};

PathSetup pathSetup(const MirroredLightsInput& in) {
  PathSetup s{in, lightChoice(in.lights), vertexAreas(in.positions, in.triangles)};
  const Bounds3 bounds = boundsOf(in.positions);
  s.center = bounds.center();
  for (const glm::vec3& p : in.positions)
    s.radius = std::max(s.radius, double(glm::length(p - s.center)));
  s.radius = s.radius * 1.001 + 4.0 * in.scene.epsilon();
  s.extent = bounds.longestSide();
  return s;
}

// Path i: from the light to its first hit, then up to two mirror bounces, each landing on the
// front of the object deposited.
void tracePath(const PathSetup& s, uint64_t index, std::vector<Deposit>& deposits) {
  const MirroredLightsInput& in = s.in;
  Pcg32 rng(in.run.seed, index);
  const double u = rng.uniformDouble();
  const std::size_t l = std::min<std::size_t>(
      std::lower_bound(s.choice.begin(), s.choice.end(), u) - s.choice.begin(),
      s.choice.size() - 1);
  const DirectionalLight& light = in.lights[l];
  const double chosen = s.choice[l] - (l > 0 ? s.choice[l - 1] : 0.0);
  if (!(chosen > 0.0)) return;
  // Within the light's cone (solid angle 2 pi (1 - cos)), uniform: its irradiance is spread evenly.
  const double cosRadius = std::clamp(1.0 - light.solidAngle / (2.0 * M_PI), -1.0, 1.0);
  const glm::vec3 towards = sampleUniformCone(glm::normalize(light.direction), cosRadius,
                                              rng.uniformDouble(), rng.uniformDouble());
  glm::vec3 b1, b2;
  orthonormalBasis(towards, b1, b2);
  const double r = s.radius * std::sqrt(rng.uniformDouble()),
               phi = 2.0 * M_PI * rng.uniformDouble();
  const glm::vec3 start = s.center + float(s.radius * 1.01) * towards +
                          float(r * std::cos(phi)) * b1 + float(r * std::sin(phi)) * b2;
  glm::vec3 power =
      light.irradiance * float(M_PI * s.radius * s.radius / (chosen * double(in.paths)));
  glm::vec3 direction = -towards;
  SurfaceHit at = surfaceHitOf(in.scene.intersect(start, direction), in.positions, in.normals,
                               in.triangles, start, direction);
  for (int reflection = 0; reflection < 2 && at.valid; ++reflection) {
    power *= fresnelDielectric(at.mu, in.eta);
    const glm::vec3 mirror = mirrorDirection(at, direction);
    const float offset = surfaceRayOffset(at.point, s.extent);
    const glm::vec3 origin = at.point + offset * at.faceNormal;
    at = surfaceHitOf(in.scene.intersect(origin, mirror, offset), in.positions, in.normals,
                      in.triangles, origin, mirror);
    direction = mirror;
    const float muFace = -glm::dot(direction, at.faceNormal);
    if (!at.valid || !(muFace > 0.0f)) return;
    const glm::vec3 taken = power * fresnelTransmittance(muFace, in.eta) * in.entry.at(muFace);
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = at.vertices[k];
      if (s.vertexAreas[v] > 0.0f)
        deposits.push_back({v, taken * (at.barycentric[k] / s.vertexAreas[v])});
    }
  }
}

}  // namespace

MirroredLights traceMirroredLights(const MirroredLightsInput& in) {
  const std::size_t n = in.positions.size();
  if (in.normals.size() != n) fail("", "mirrored lights: one normal per vertex needed");
  MirroredLights out{std::vector<glm::vec3>(n, glm::vec3(0.0f)),
                     std::vector<glm::vec3>(n, glm::vec3(0.0f))};
  if (in.lights.empty() || in.paths == 0 || n == 0 || in.triangles.empty()) return out;
  const PathSetup setup = pathSetup(in);
  // Each chunk's deposits in path order, added chunk after chunk: the same sum for any thread
  // count. A block of paths at a time, so that the deposits held stay bounded on a large mesh.
  constexpr std::size_t kGrain = 4096, kBlock = std::size_t(1) << 22;
  std::vector<std::vector<Deposit>> chunkDeposits(kBlock / kGrain);
  for (uint64_t first = 0; first < in.paths; first += kBlock) {
    const std::size_t count = std::size_t(std::min<uint64_t>(kBlock, in.paths - first));
    parallelFor(count, in.run.threads, kGrain, [&](std::size_t begin, std::size_t end) {
      std::vector<Deposit>& deposits = chunkDeposits[begin / kGrain];
      for (std::size_t i = begin; i < end; ++i) tracePath(setup, first + i, deposits);
    });
    for (std::vector<Deposit>& deposits : chunkDeposits) {
      for (const Deposit& d : deposits) {
        out.irradiance[d.vertex] += d.irradiance;
        out.variance[d.vertex] += d.irradiance * d.irradiance;
      }
      deposits.clear();
    }
  }
  const float perPath = 1.0f / float(in.paths);
  for (std::size_t v = 0; v < n; ++v)
    out.variance[v] = glm::max(out.variance[v] - out.irradiance[v] * out.irradiance[v] * perPath,
                               glm::vec3(0.0f));
  return out;
}

}  // namespace sss
