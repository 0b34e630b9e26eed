// The concavity study (docs/accuracy.md, "Concavities: the box with a pit and the bunny"): the
// light an object sends to itself (sss-bake --bounces, lib/transport/interreflection.h) against
// the forward light tracer (lib/pathtrace/light_tracer.h), which follows light that leaves the
// object and meets it again.
//
//   concavity_study OUT_DIR [--paths N] [--only NAME] [--cache DIR]
//
// Scenes, each in marble and in skim milk (a high-albedo and a low-density material):
//  - the closed 20 mm box with a pit 6 mm deep (tests/support/box_with_pit.h; its floor sees about
//    70 % of the sky) under uniform radiance 1 and under a sun of 1 degree angular radius 30
//    degrees from the pit's axis;
//  - the sample bunny (data/cache/meshes/bunny.ply: closed, 1,839 vertices) scaled to 50 mm along
//    its longest side, with concavities (between the ears, under the chin and the haunch) and thin
//    parts (the ears), under uniform radiance 1 and under forest.exr at full resolution (its
//    sky and sunlit canopy).
// The bake is sss-bake's own pipeline (lib/bake/bake.h) with its defaults at 1 % (escape energy,
// dipole, directional entry, normalized exit, far field auto) and 256 visibility rays, with
// --bounces 0 and --bounces auto.
// Metrics, on the radiance along the normal (all channels; the reference's noise removed):
//   rms_all      sqrt(max(0, sum (L - L_ref)^2 - sum se^2) / sum L_ref^2) over every vertex,
//   rms_concave  the same over the concave vertices (those that see < 80 % of the sky: E under
//                uniform light below 0.8 of a convex vertex's),
//   ratio_concave  sum L / sum L_ref over the concave vertices,
//   predicted    the bake's own predicted error (the JSON's estimated_error.total), and
//   measured_over_predicted  rms_all / predicted: 1 when the bake's "1 %" holds;
//   numerical, model_*  the predicted error's parts (estimated_error.numerical and .model);
//   ref_noise    the reference's own noise in rms_all's norm (what it subtracts);
//   *_calibrated  the first three with the calibrated exit model for B's part (sss-render
//                --exit-model calibrated).
// Writes OUT_DIR/concavity.csv, and each bake's per-vertex values beside the reference's to
// OUT_DIR/vertices/SCENE-BOUNCES.csv.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "bake/bake.h"
#include "core/error.h"
#include "envmap/environment.h"
#include "lighting/visibility.h"
#include "material/directional_albedo_weight.h"
#include "material/material.h"
#include "mesh/baked_mesh.h"
#include "mesh/triangle_mesh.h"
#include "optics/fresnel.h"
#include "pathtrace/light_tracer.h"
#include "study_support.h"
#include "support/box_with_pit.h"

namespace {

using namespace sss;
using namespace sss::study;

constexpr int kVisibilityRays = 256;

enum class Light { Uniform, Sun, Forest };
const char* lightName(Light l) {
  return l == Light::Uniform ? "uniform" : l == Light::Sun ? "sun" : "forest";
}

// A closed mesh in mm, the file the bake reads it from, and its concave vertices.
struct Shape {
  std::string name;
  TriangleMesh mesh;
  std::string meshPath;
  std::vector<char> concave;
};

struct Scene {
  std::string name;
  Material material;
  Light light;
};

// The concave vertices: E under uniform light below 0.8 of the unoccluded value.
std::vector<char> concaveVertices(const TriangleMesh& mesh, float eta) {
  VisibilityOptions options;
  options.samples = 1024;
  const Cubemap uniform(16, glm::vec3(1.0f));
  const std::vector<glm::vec3> e = transmittedIrradianceWithVisibility(
      mesh.positions, mesh.normals, mesh.triangles, uniform, eta, options);
  const double open = M_PI * (1.0 - diffuseFresnelReflectance(eta));
  std::vector<char> concave(e.size());
  for (std::size_t v = 0; v < e.size(); ++v) concave[v] = e[v].y < 0.8 * open;
  return concave;
}

struct Metrics {
  double rmsAll = 0.0, rmsConcave = 0.0, ratioConcave = 0.0;
};

Metrics compare(const std::vector<glm::vec3>& l, const LightTraceResult& ref,
                const std::vector<char>& concave) {
  double sum = 0.0, sumRef = 0.0;
  for (std::size_t v = 0; v < l.size(); ++v)
    if (concave[v])
      for (int c = 0; c < 3; ++c) {
        sum += l[v][c];
        sumRef += ref.radiance[v][c];
      }
  Metrics m;
  m.rmsAll = relativeRmsAgainst(l, ref.radiance, ref.radianceStdErr);
  m.rmsConcave = relativeRmsAgainst(l, ref.radiance, ref.radianceStdErr, &concave);
  m.ratioConcave = sumRef > 0 ? sum / sumRef : 0.0;
  return m;
}

// One row per vertex (position, normal, concave, the bake's radiance along the normal, B and E,
// the reference's radiance and its standard error), for locating an error on the mesh.
void writeVertices(const std::string& path, const TriangleMesh& mesh, const BakedMesh& baked,
                   const LightTraceResult& ref, const std::vector<char>& concave) {
  std::ofstream out(path);
  out << "x,y,z,nx,ny,nz,concave";
  for (const char* q : {"l", "b", "e", "l_ref", "se"})
    for (const char* c : {"r", "g", "b"}) out << ',' << q << '_' << c;
  out << '\n';
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    const glm::vec3 p = mesh.positions[v], n = mesh.normals[v];
    out << p.x << ',' << p.y << ',' << p.z << ',' << n.x << ',' << n.y << ',' << n.z << ','
        << int(concave[v]);
    for (const glm::vec3& q : {baked.radianceNormal[v], baked.exitance[v], baked.irradiance[v],
                               ref.radiance[v], ref.radianceStdErr[v]})
      out << ',' << q.x << ',' << q.y << ',' << q.z;
    out << '\n';
  }
}

Cubemap environmentOf(Light light) {
  switch (light) {
    case Light::Uniform:
      return Cubemap(16, glm::vec3(1.0f));
    case Light::Sun:
      return sunEnvironment(glm::normalize(glm::vec3(0.5f, 0.0f, 0.866f)), 1.0, 256);
    case Light::Forest:
      break;
  }
  return loadEnvironment(std::string(SSS_SOURCE_DIR) + "/data/cache/env/forest.exr", {});
}

void study(const Scene& s, const Shape& shape, uint64_t paths, const std::string& cache,
           const std::string& verticesDir, std::ofstream& csv) {
  const TriangleMesh& mesh = shape.mesh;
  BakeEnvironment env{environmentOf(s.light), {}};
  const HomogeneousMedium medium = homogeneousMediumOf(s.material);
  LightTraceOptions lo;
  lo.paths = paths;
  lo.run.seed = study::kReferenceSeed;
  const LightTraceResult ref = cachedReference(cache, s.name + "-" + std::to_string(paths), [&] {
    return lightTraceSubsurface(mesh.positions, mesh.normals, mesh.triangles,
                                DistantLight::environment(env.radiance), medium, lo);
  });
  std::printf("%s: reference %llu paths, %.1f s, %llu re-entries\n", s.name.c_str(),
              (unsigned long long)paths, ref.seconds, (unsigned long long)ref.reentries);
  for (int bounces : {0, kAutoBounces}) {
    const BakeOutput out =
        bakeAtDefaults(mesh, s.material, env, kVisibilityRays, shape.meshPath, bounces);
    const Metrics m = compare(out.baked.radianceNormal, ref, shape.concave);
    writeVertices(verticesDir + "/" + s.name + (bounces == 0 ? "-0" : "-auto") + ".csv", mesh,
                  out.baked, ref, shape.concave);
    // The same with the calibrated exit model (sss-render --exit-model calibrated) for B's part.
    const float eta = float(s.material.eta);
    const glm::vec3 calibrated =
        calibratedExitRadiance(DirectionalAlbedoWeight(s.material), 1.0f, eta);
    const float normalized = float(normalExitRadianceScale(eta));
    std::vector<glm::vec3> l = out.baked.radianceNormal;
    for (std::size_t v = 0; v < l.size(); ++v)
      l[v] += out.baked.exitance[v] * (calibrated - glm::vec3(normalized));
    const Metrics mc = compare(l, ref, shape.concave);
    const UnscatteredLightReport& u = out.report.unscattered;
    std::printf("  unscattered: %s (%s), share %.4f, paths %llu, noise %.4f, %.2f s\n",
                u.traced ? "traced" : "not traced", u.reason.c_str(), u.share,
                (unsigned long long)u.paths, u.relativeStdError, u.seconds);
    const FarFieldReport& far = out.report.farField;
    std::printf("  far field: %s (%s), sensitivity %.4f, paths %llu, noise %.4f, %.2f s\n",
                far.traced ? "traced" : "not traced", far.reason.c_str(), far.sensitivity,
                (unsigned long long)far.paths, far.relativeStdError, far.seconds);
    const InterreflectionReport& ir = out.report.interreflection;
    const BakeErrorReport& e = out.report.errors;
    const double predicted = e.total;
    char line[512];
    std::snprintf(line, sizeof line,
                  "%s,%s,%s,%s,%d,%.5f,%.5f,%.4f,%.5f,%.2f,%.3f,%llu,%.5f,%.5f,%.4f,%.5f,%.5f,%.5f,"
                  "%.5f,%.5f,%.5f,%.5f\n",
                  s.name.c_str(), s.material.name.c_str(), lightName(s.light),
                  bounces == 0 ? "0" : "auto", ir.bounces, m.rmsAll, m.rmsConcave, m.ratioConcave,
                  predicted, predicted > 0 ? m.rmsAll / predicted : 0.0, out.report.totalSeconds,
                  (unsigned long long)paths, mc.rmsAll, mc.rmsConcave, mc.ratioConcave, e.numerical,
                  e.model.exitModel, e.model.facets, e.model.facetLight, e.model.farField,
                  e.model.interreflection, relativeNoise(ref.radiance, ref.radianceStdErr));
    csv << line;
    csv.flush();
    std::printf(
        "  bounces %-4s (%d done): rms all %.4f, concave %.4f, concave ratio %.3f, predicted "
        "%.4f, %.2f s; calibrated exit: rms all %.4f, concave %.4f\n",
        bounces == 0 ? "0" : "auto", ir.bounces, m.rmsAll, m.rmsConcave, m.ratioConcave, predicted,
        out.report.totalSeconds, mc.rmsAll, mc.rmsConcave);
    std::fflush(stdout);
  }
}

int run(int argc, char** argv) {
  // 32M paths per reference: what the committed rows use (docs/accuracy.md, "The bake's predicted
  // error").
  const StudyArguments args = parseStudyArguments(argc, argv, 32000000);
  if (args.outDir.empty()) {
    std::fprintf(stderr,
                 "usage: concavity_study OUT_DIR [--paths N] [--only NAME] [--cache DIR]\n");
    return 2;
  }
  const std::string& outDir = args.outDir;
  const std::string &only = args.only, &cache = args.cache;
  const uint64_t paths = args.paths;
  std::filesystem::create_directories(outDir + "/vertices");
  std::vector<Shape> shapes;
  shapes.push_back({"pit", boxWithPit(), outDir + "/box_with_pit.ply", {}});
  TriangleMesh bunny =
      loadScaled(std::string(SSS_SOURCE_DIR) + "/data/cache/meshes/bunny.ply", 50.0);
  bunny.normals = computeVertexNormals(bunny);
  shapes.push_back({"bunny", std::move(bunny), outDir + "/bunny_50mm.ply", {}});
  for (Shape& shape : shapes) {
    shape.concave = concaveVertices(shape.mesh, 1.3f);
    std::size_t count = 0;
    for (char c : shape.concave) count += c;
    std::printf("%s: %zu vertices, %zu see < 80 %% of the sky\n", shape.name.c_str(),
                shape.mesh.positions.size(), count);
  }
  std::ofstream csv(outDir + "/concavity.csv");
  csv << "scene,material,light,bounces_asked,bounces_done,rms_all,rms_concave,ratio_concave,"
         "predicted,measured_over_predicted,bake_s,ref_paths,rms_all_calibrated,"
         "rms_concave_calibrated,ratio_concave_calibrated,numerical,model_exit,model_facets,"
         "model_facet_light,model_far_field,model_interreflection,ref_noise\n";
  for (const Shape& shape : shapes)
    for (const char* m : {"marble", "skimmilk"})
      for (Light light : {Light::Uniform, shape.name == "pit" ? Light::Sun : Light::Forest}) {
        const Scene s{shape.name + "-" + lightName(light) + "-" + m, findMaterialPreset(m), light};
        if (only.empty() || s.name.find(only) != std::string::npos)
          study(s, shape, paths, cache, outDir + "/vertices", csv);
      }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "concavity_study: error: %s\n", e.what());
    return 1;
  }
}
