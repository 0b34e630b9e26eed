// What the studies share (sun_study.cpp, concavity_study.cpp, accuracy_study.cpp): a sun-only
// environment, a sample mesh scaled to a size in mm, and a cache for the light tracer's
// references, so that a model change is re-measured in seconds.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include <glm/geometric.hpp>

#include "bake/bake.h"
#include "bake/bake_settings.h"
#include "core/relative_rms.h"
#include "envmap/cubemap.h"
#include "mesh/load_mesh.h"
#include "mesh/triangle_mesh.h"
#include "pathtrace/light_tracer.h"

namespace sss::study {

// A black environment with a sun of angular radius `radiusDeg` (texel centres within it).
inline Cubemap sunEnvironment(const glm::vec3& towardsSun, double radiusDeg, int faceSize) {
  Cubemap env(faceSize, glm::vec3(0.0f));
  const float cosRadius = float(std::cos(radiusDeg * M_PI / 180.0));
  forEachTexel(faceSize, [&](int f, int x, int y) {
    if (glm::dot(env.direction(f, x, y), towardsSun) >= cosRadius)
      env.at(f, x, y) = glm::vec3(1000.0f);
  });
  return env;
}

// A mesh file scaled so that its longest bounding-box side is `longestMm` (sample meshes come in
// arbitrary units).
inline TriangleMesh loadScaled(const std::string& path, double longestMm) {
  TriangleMesh mesh = loadMesh(path);
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (const auto& p : mesh.positions) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const glm::vec3 ext = hi - lo;
  scalePositions(mesh, longestMm / std::max({ext.x, ext.y, ext.z}));
  return mesh;
}

// The mesh as an ASCII PLY with its normals, for the studies that run sss-bake's own pipeline
// (lib/bake/bake.h reads the mesh from a file).
inline void writeAsciiPly(const std::string& path, const TriangleMesh& mesh) {
  std::ofstream out(path);
  out << "ply\nformat ascii 1.0\nelement vertex " << mesh.positions.size()
      << "\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty "
         "float ny\nproperty float nz\nelement face "
      << mesh.triangles.size() << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    const glm::vec3 p = mesh.positions[v], n = mesh.normals[v];
    out << p.x << ' ' << p.y << ' ' << p.z << ' ' << n.x << ' ' << n.y << ' ' << n.z << '\n';
  }
  for (const glm::uvec3& t : mesh.triangles) out << "3 " << t.x << ' ' << t.y << ' ' << t.z << '\n';
}

// sss-bake's own pipeline (lib/bake/bake.h) at its defaults (1 %) with `samples` visibility rays
// and `bounces` on a mesh in mm: bake() reads the mesh from a file, written to `path` and removed
// after.
inline BakeOutput bakeAtDefaults(const TriangleMesh& mesh, const Material& material,
                                 const BakeEnvironment& env, int samples, const std::string& path,
                                 int bounces = 0, uint64_t seed = 1) {
  writeAsciiPly(path, mesh);
  BakeSettings settings;
  settings.meshPath = path;
  settings.material = material;
  settings.mmPerUnit = 1.0;
  settings.samples = samples;
  settings.bounces = bounces;
  settings.run.seed = seed;
  settings.run.quiet = true;
  BakeOutput out = bake(settings, env);
  std::filesystem::remove(path);
  return out;
}

// Relative RMS of a against ref, the reference's noise (se) removed (core/relative_rms.h,
// relativeRmsNoiseRemoved); over the vertices `only` marks, if given.
inline double relativeRmsAgainst(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& ref,
                                 const std::vector<glm::vec3>& se,
                                 const std::vector<char>* only = nullptr) {
  return only ? relativeRmsNoiseRemoved(a, ref, se, *only) : relativeRmsNoiseRemoved(a, ref, se);
}

// The reference's own noise in relativeRmsAgainst's norm, sqrt(sum se^2 / sum ref^2): what that
// metric subtracts, so that an error well below it is not resolved (model_error_fit.py).
inline double relativeNoise(const std::vector<glm::vec3>& ref, const std::vector<glm::vec3>& se) {
  return relativeRmsSums(ref, ref, se).relativeNoise();
}

// The spread between two bakes of different seeds in relativeRmsAgainst's norm,
// sqrt(sum (a - b)^2 / 2 / sum ref^2): each one's own noise, measured (what a bake's `numerical`
// error estimates).
inline double seedSpread(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b,
                         const std::vector<glm::vec3>& ref) {
  RelativeRmsSums sums;
  for (std::size_t v = 0; v < ref.size(); ++v)
    sums.add(glm::dvec3(a[v]) - glm::dvec3(b[v]), glm::dvec3(ref[v]));
  sums.error /= 2.0;
  return sums.ratio();
}

// The references' seed, apart from the bake's (1): the bake's traced stages (far field, unscattered
// light) trace the same light with the same medium walks, so a reference with their seed repeats
// their paths and shares their noise, and the measured error reads too low (docs/conventions.md,
// "Determinism and random numbers").
inline constexpr uint64_t kReferenceSeed = 0x7265666572656e63ULL;

// The reference's per-vertex arrays, kept in `cache` (if not empty) as raw floats.
inline LightTraceResult cachedReference(const std::string& cache, const std::string& key,
                                        const std::function<LightTraceResult()>& trace) {
  const std::string path = cache.empty() ? "" : cache + "/" + key + ".bin";
  LightTraceResult r;
  if (!path.empty()) {
    std::ifstream in(path, std::ios::binary);
    uint64_t n = 0;
    if (in.read(reinterpret_cast<char*>(&n), sizeof n)) {
      for (auto* v : {&r.exitance, &r.exitanceStdErr, &r.radiance, &r.radianceStdErr}) {
        v->resize(n);
        in.read(reinterpret_cast<char*>(v->data()), std::streamsize(n * sizeof(glm::vec3)));
      }
      in.read(reinterpret_cast<char*>(&r.seconds), sizeof r.seconds);
      in.read(reinterpret_cast<char*>(&r.meanScatteringEvents), sizeof r.meanScatteringEvents);
      in.read(reinterpret_cast<char*>(&r.reentries), sizeof r.reentries);
      if (in) return r;
    }
  }
  r = trace();
  if (!path.empty()) {
    std::filesystem::create_directories(cache);
    std::ofstream out(path, std::ios::binary);
    const uint64_t n = r.exitance.size();
    out.write(reinterpret_cast<const char*>(&n), sizeof n);
    for (auto* v : {&r.exitance, &r.exitanceStdErr, &r.radiance, &r.radianceStdErr})
      out.write(reinterpret_cast<const char*>(v->data()), std::streamsize(n * sizeof(glm::vec3)));
    out.write(reinterpret_cast<const char*>(&r.seconds), sizeof r.seconds);
    out.write(reinterpret_cast<const char*>(&r.meanScatteringEvents),
              sizeof r.meanScatteringEvents);
    out.write(reinterpret_cast<const char*>(&r.reentries), sizeof r.reentries);
  }
  return r;
}

// The studies' command line: OUT_DIR [--paths N] [--only NAME] [--cache DIR]; `--walks N` is
// `--paths N` for the studies whose reference is walks (exit_model_study,
// material_interface_study).
struct StudyArguments {
  std::string outDir, only, cache;
  uint64_t paths = 0;
};

// Empty outDir: no arguments (print the usage and exit 2).
inline StudyArguments parseStudyArguments(int argc, char** argv, uint64_t defaultPaths) {
  StudyArguments a;
  a.paths = defaultPaths;
  if (argc < 2) return a;
  a.outDir = argv[1];
  for (int i = 2; i + 1 < argc; ++i) {
    const std::string flag = argv[i];
    if (flag == "--paths" || flag == "--walks")
      a.paths = std::strtoull(argv[++i], nullptr, 10);
    else if (flag == "--only")
      a.only = argv[++i];
    else if (flag == "--cache")
      a.cache = argv[++i];
  }
  return a;
}

}  // namespace sss::study
