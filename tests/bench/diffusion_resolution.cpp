// Resolution limit of the diffusion sums: a 20 mm marble sphere (and skin1) under a smooth
// directional light at icosphere levels 1-5, every method against the level-6 solution
// (40962 vertices, gauss at tolerance 0.001) on the shared vertices. Writes CSV to stdout:
// material,level,vertices,spacing_mm,spacing_over_mfp,method,error
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/geometric.hpp>
#include <vector>

#include "core/relative_rms.h"
#include "diffusion/diffusion.h"
#include "material/dipole_profile.h"
#include "material/material.h"
#include "mesh/primitives.h"
#include "mesh/triangle_mesh.h"

using namespace sss;

namespace {

struct Level {
  TriangleMesh mesh;
  std::vector<float> areas;
  std::vector<glm::vec3> irradiance;
};

Level makeLevel(int subdivisions) {
  Level l{makeIcosphere(subdivisions, 10), {}, {}};
  l.areas = vertexAreas(l.mesh);
  const glm::vec3 light = glm::normalize(glm::vec3(1, 2, 0.5));
  for (const auto& n : l.mesh.normals) {
    const float c = std::max(0.0f, glm::dot(n, light));
    l.irradiance.emplace_back(c * c * c + 0.05f, 0.5f * c + 0.02f, c + 0.1f);
  }
  return l;
}

std::vector<glm::vec3> run(const Level& l, const DiffusionProfile& profile, DiffusionMethod method,
                           double tolerance) {
  DiffusionOptions options;
  options.method = method, options.tolerance = tolerance, options.run.quiet = true;
  return diffuse({l.mesh.positions, l.mesh.normals, l.areas, l.irradiance}, profile, options)
      .exitance;
}

}  // namespace

int main() {
  std::printf("material,level,vertices,spacing_mm,spacing_over_mfp,method,error\n");
  for (const char* name : {"marble", "skin1"}) {
    const Material material = findMaterialPreset(name);
    const DipoleProfile profile(material);
    // The smallest transport mean free path 1 / sigma_t' over the channels.
    const glm::dvec3 mfp = material.meanFreePath();
    const double minMfp = std::min({mfp.x, mfp.y, mfp.z});
    const Level fine = makeLevel(6);
    const std::vector<glm::vec3> reference = run(fine, profile, DiffusionMethod::Gauss, 0.001);
    for (int level = 1; level <= 5; ++level) {
      const Level l = makeLevel(level);
      const double spacing =
          std::sqrt(surfaceArea(l.mesh) / l.mesh.vertexCount() * 2 / std::sqrt(3.0));
      for (DiffusionMethod method : {DiffusionMethod::Exact, DiffusionMethod::Gauss,
                                     DiffusionMethod::Hierarchical, DiffusionMethod::Incremental}) {
        if (method == DiffusionMethod::Exact && l.mesh.vertexCount() > 3000) continue;
        const std::vector<glm::vec3> b = run(l, profile, method, 0.01);
        std::printf("%s,%d,%zu,%.4g,%.4g,%s,%.5g\n", name, level, b.size(), spacing,
                    spacing / minMfp, kDiffusionMethodNames.name(method),
                    relativeRms(b, std::span(reference).first(b.size())));
        std::fflush(stdout);
      }
    }
  }
}
