// Methods x tolerances x mesh resolutions for the whole bake on the sample dragons (marble,
// 150 mm long, forest, 64 visibility rays per vertex): one CSV row per configuration with the
// stage times and the relative RMS error of the exitance B against a reference: `exact` where
// it is affordable (N <= --exact-limit), else `auto` at the tightest tolerance (--reference-tol).
// Visibility runs once per mesh (it does not depend on the diffusion method); its time is part
// of every row's bake_s; gauss and incremental are left out above --slow-limit vertices.
// Usage: bake_sweep [--out F.csv] [--threads N] [--repeats R] [--exact-limit N]
//                   [--slow-limit N] [--reference-tol T] MESH...
// With --visibility-out F.csv, instead, the visibility sample count against its own noise: E and B
// (hierarchical at 1%) with 16..1024 rays per vertex against --reference-samples rays (default
// 4096, another seed), per mesh, beside the errors the pilot's noise model (bake.h) predicts.
// --env NAME picks data/cache/env/NAME.exr (default forest), --size-mm L the mesh's length (150);
// a MESH ending in .ply is a path, else a sample mesh name.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include <glm/common.hpp>

#include "bake/bake.h"
#include "core/relative_rms.h"
#include "core/timer.h"
#include "diffusion/diffusion.h"
#include "envmap/environment.h"
#include "lighting/visibility.h"
#include "material/diffusion_profile.h"
#include "material/material.h"
#include "material/profile_factory.h"
#include "mesh/load_mesh.h"
#include "mesh/triangle_mesh.h"

using sss::relativeRms;

int main(int argc, char** argv) {
  std::string out = "bake_sweep.csv", visibilityOut, envName = "forest";
  double sizeMm = 150.0;
  int referenceSamples = 4096;
  int threads = 2, repeats = 1;
  std::size_t exactLimit = 30000, slowLimit = 150000;
  double referenceTolerance = 0.001;
  std::vector<std::string> meshes;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--out" && i + 1 < argc)
      out = argv[++i];
    else if (a == "--visibility-out" && i + 1 < argc)
      visibilityOut = argv[++i];
    else if (a == "--env" && i + 1 < argc)
      envName = argv[++i];
    else if (a == "--size-mm" && i + 1 < argc)
      sizeMm = std::atof(argv[++i]);
    else if (a == "--reference-samples" && i + 1 < argc)
      referenceSamples = std::atoi(argv[++i]);
    else if (a == "--slow-limit" && i + 1 < argc)
      slowLimit = std::stoul(argv[++i]);
    else if (a == "--threads" && i + 1 < argc)
      threads = std::atoi(argv[++i]);
    else if (a == "--repeats" && i + 1 < argc)
      repeats = std::atoi(argv[++i]);
    else if (a == "--exact-limit" && i + 1 < argc)
      exactLimit = std::stoul(argv[++i]);
    else if (a == "--reference-tol" && i + 1 < argc)
      referenceTolerance = std::atof(argv[++i]);
    else
      meshes.push_back(a);
  }
  const std::string data = SSS_SOURCE_DIR "/data/cache";
  const sss::Material marble = sss::findMaterialPreset("marble");
  const auto profile = sss::makeProfile("dipole", marble);
  sss::Stopwatch clock;
  const sss::Cubemap env = sss::loadEnvironment(data + "/env/" + envName + ".exr");
  const double envSeconds = clock.seconds();

  std::ofstream visibilityCsv;
  if (!visibilityOut.empty()) {
    visibilityCsv.open(visibilityOut);
    visibilityCsv << "mesh,env,vertices,samples,visibility_s,rel_rms_error_E,rel_rms_error_B,"
                     "error_bound_E,predicted_E,predicted_B,predicted_B_vs_reference\n";
  }
  std::ofstream csv;
  if (visibilityOut.empty()) csv.open(out);
  csv << "mesh,vertices,method,method_run,tolerance,diffusion_s,visibility_s,load_s,bake_s,"
         "rel_rms_error,reference,estimated_error,gaussians\n";
  for (const std::string& name : meshes) {
    clock.restart();
    const bool isPath = name.size() > 4 && name.substr(name.size() - 4) == ".ply";
    sss::TriangleMesh mesh = sss::loadMesh(isPath ? name : data + "/meshes/" + name + ".ply");
    glm::vec3 lo = mesh.positions[0], hi = lo;
    for (const glm::vec3& p : mesh.positions) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    sss::scalePositions(mesh, sizeMm / std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z}));
    const std::vector<float> areas = sss::vertexAreas(mesh);
    const double loadSeconds = clock.seconds() + envSeconds;

    sss::VisibilityOptions vo;
    vo.samples = 64;
    vo.run.threads = threads;
    clock.restart();
    const auto e = sss::transmittedIrradianceWithVisibility(mesh.positions, mesh.normals,
                                                            mesh.triangles, env, 1.3f, vo);
    const double visibilitySeconds = clock.seconds();
    const sss::DiffusionInput input{mesh.positions, mesh.normals, areas, e};
    const std::size_t n = mesh.vertexCount();
    std::fprintf(stderr, "%s: %zu vertices, visibility %.2f s\n", name.c_str(), n,
                 visibilitySeconds);

    if (!visibilityOut.empty()) {
      sss::DiffusionOptions o;
      o.method = sss::DiffusionMethod::Hierarchical;
      o.run.threads = threads;
      o.run.quiet = true;
      sss::VisibilityOptions ro = vo;
      ro.samples = referenceSamples;
      ro.run.seed = 99;
      const auto eRef = sss::transmittedIrradianceWithVisibility(mesh.positions, mesh.normals,
                                                                 mesh.triangles, env, 1.3f, ro);
      const auto bRef = sss::diffuse({mesh.positions, mesh.normals, areas, eRef}, *profile, o);
      for (int samples : {16, 32, 64, 128, 256, 512, 1024}) {
        ro.samples = samples;
        ro.run.seed = 1;
        ro.pilot = sss::VisibilityPilotOptions{};
        sss::VisibilityNoiseModel model;
        ro.chooseSamples = [&](const sss::VisibilityPilot& pilot) {
          model = sss::visibilityNoiseModel(pilot, mesh.positions, areas, *profile);
          return samples;
        };
        sss::VisibilityReport report;
        clock.restart();
        const auto eS = sss::transmittedIrradianceWithVisibility(
            mesh.positions, mesh.normals, mesh.triangles, env, 1.3f, ro, &report);
        const double seconds = clock.seconds();
        const auto bS = sss::diffuse({mesh.positions, mesh.normals, areas, eS}, *profile, o);
        double eVar = 0.0, eSq = 0.0;
        for (std::size_t k = 0; k < report.pilot.vertices.size(); ++k) {
          const glm::vec3 v = report.pilot.fineVariance[k], e = report.pilot.irradiance[k];
          eVar += double(v.r + v.g + v.b) *
                  std::pow(double(report.pilot.fineRays) / samples, model.rate);
          eSq += double(e.r) * e.r + double(e.g) * e.g + double(e.b) * e.b;
        }
        // The reference has noise too: the measured error is sqrt(err_N^2 + err_ref^2).
        const double predicted = model.errorAt(samples);
        const double predictedVsRef = std::hypot(predicted, model.errorAt(referenceSamples));
        char line[320];
        std::snprintf(line, sizeof line, "%s,%s,%zu,%d,%.4f,%.5g,%.5g,%.5g,%.5g,%.5g,%.5g\n",
                      name.c_str(), envName.c_str(), mesh.vertexCount(), samples, seconds,
                      relativeRms(eS, eRef), relativeRms(bS.exitance, bRef.exitance),
                      report.relativeStdError, std::sqrt(eVar / eSq), predicted, predictedVsRef);
        visibilityCsv << line;
        visibilityCsv.flush();
        std::fprintf(stderr, "  %s", line);
      }
      continue;
    }

    auto run = [&](sss::DiffusionMethod method, double tolerance, double& seconds) {
      sss::DiffusionOptions o;
      o.method = method;
      o.tolerance = tolerance;
      o.run.threads = threads;
      o.run.quiet = true;
      std::vector<double> times;
      sss::DiffusionResult result;
      for (int r = 0; r < repeats; ++r) {
        clock.restart();
        result = sss::diffuse(input, *profile, o);
        times.push_back(clock.seconds());
      }
      std::sort(times.begin(), times.end());
      seconds = times[times.size() / 2];
      return result;
    };
    const bool exactAffordable = n <= exactLimit;
    double referenceSeconds = 0.0;
    const sss::DiffusionResult reference =
        exactAffordable ? run(sss::DiffusionMethod::Exact, 0.01, referenceSeconds)
                        : run(sss::DiffusionMethod::Auto, referenceTolerance, referenceSeconds);
    const std::string referenceName =
        exactAffordable ? "exact" : "auto@" + std::to_string(referenceTolerance);
    auto row = [&](const std::string& method, double tolerance, const sss::DiffusionResult& r,
                   double seconds) {
      char line[512];
      std::snprintf(line, sizeof line, "%s,%zu,%s,%s,%g,%.4f,%.4f,%.4f,%.4f,%.6g,%s,%.4g,%d\n",
                    name.c_str(), n, method.c_str(),
                    sss::kDiffusionMethodNames.name(r.report.method), tolerance, seconds,
                    visibilitySeconds, loadSeconds, loadSeconds + visibilitySeconds + seconds,
                    relativeRms(r.exitance, reference.exitance), referenceName.c_str(),
                    r.report.estimatedError, r.report.gaussians);
      csv << line;
      csv.flush();
      std::fprintf(stderr, "  %s", line);
    };
    if (exactAffordable) row("exact", 0.0, reference, referenceSeconds);
    for (const std::string method : {"gauss", "incremental", "hierarchical", "auto"}) {
      // gauss and incremental take minutes beyond ~150K vertices (see the chart): left out.
      if (n > slowLimit && (method == "gauss" || method == "incremental")) continue;
      for (double tolerance : {0.03, 0.01, 0.003}) {
        double seconds = 0.0;
        const auto r = run(sss::kDiffusionMethodNames.parse(method), tolerance, seconds);
        row(method, tolerance, r, seconds);
      }
    }
  }
  return 0;
}
