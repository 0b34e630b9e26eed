// Helper of irrmap_vs_cmft.sh (sss-irrmap against cmft). Subcommands:
//   dds ENV.exr OUT.dds
//       the equirect map as an uncompressed RGBA32F DDS (legacy header, D3DFMT_A32B32G32R32F):
//       what cmft reads fastest, losslessly.
//   exr ENV.exr OUT.exr
//       the same pixels as an uncompressed float EXR (the sample maps are DWAB-compressed): our
//       input equivalent to cmft's uncompressed DDS.
//   tiny OUT.exr
//       a 64 x 32 grey equirect: sss-irrmap on it measures the per-process cost of OIIO's first
//       image read and write (its format catalogue) with almost no work.
//   error ENV.exr OURS.exr CMFT.dds
//       both irradiance cubemaps against the exact sum over every texel of ENV (each with its
//       solid angle) at the texel centres of their faces; one CSV line per cubemap:
//       name,relative_rms,worst_texel,min_texel,probe_rms. relative_rms = sqrt(sum |a - r|^2 /
//       sum |r|^2) over texels (RGB norms), worst_texel = max |a - r| / |r|, probe_rms the
//       relative RMS through the renderer's bilinear lookup at 1024 Fibonacci normals.
//       cmft maps a latlong image to the cube mirrored in z against our convention (found with a
//       test image whose texels hold their own direction; `orientation` checks it on a map):
//       its faces are mirrored back before comparing (an exact permutation of texels). cmft
//       writes E / pi (the radiance a white Lambertian surface reflects): scaled by pi.
//   orientation ENV.exr CMFT.dds
//       cmft's radiance faces (--filter none) against our cubemapFromImage of the same map:
//       relative RMS per face, to check that the conventions agree.
//   batch OUT_DIR ENV.exr...
//       the 8 maps in one process (as an sss-irrmap batch runs them): per map read, irradiance
//       at 1% tolerance on 32-texel faces, cubemap and preview written; CSV per map.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "core/relative_rms.h"
#include "core/timer.h"
#include "envmap/cubemap_io.h"
#include "envmap/environment.h"
#include "irradiance/brute_force.h"
#include "irradiance/irradiance.h"

namespace {

using namespace sss;

constexpr std::uint32_t kDdsMagic = 0x20534444;  // "DDS "
constexpr std::uint32_t kFourCcRgba32f = 116;    // D3DFMT_A32B32G32R32F
constexpr std::uint32_t kFourCcDx10 = 0x30315844;

void writeDds(const ImageRgb& image, const std::string& path) {
  std::uint32_t h[32] = {};
  h[0] = kDdsMagic;
  h[1] = 124;                             // header size
  h[2] = 0x1 | 0x2 | 0x4 | 0x8 | 0x1000;  // caps, height, width, pitch, pixel format
  h[3] = static_cast<std::uint32_t>(image.height);
  h[4] = static_cast<std::uint32_t>(image.width);
  h[5] = static_cast<std::uint32_t>(image.width) * 16;  // pitch
  h[7] = 1;                                             // mips
  h[19] = 32;                                           // pixel format size
  h[20] = 0x4;                                          // DDPF_FOURCC
  h[21] = kFourCcRgba32f;
  h[27] = 0x1000;  // DDSCAPS_TEXTURE
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(h), sizeof h);
  std::vector<float> rgba;
  rgba.reserve(image.pixels.size() * 4);
  for (const glm::vec3& p : image.pixels) rgba.insert(rgba.end(), {p.x, p.y, p.z, 1.0f});
  out.write(reinterpret_cast<const char*>(rgba.data()),
            static_cast<std::streamsize>(rgba.size() * sizeof(float)));
  if (!out) throw std::runtime_error(path + ": cannot write");
}

// A DDS cubemap of RGBA32F faces (cmft's output), faces +X -X +Y -Y +Z -Z.
Cubemap readDdsCubemap(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::uint32_t h[32];
  in.read(reinterpret_cast<char*>(h), sizeof h);
  if (!in || h[0] != kDdsMagic) throw std::runtime_error(path + ": not a DDS file");
  if (h[21] == kFourCcDx10)
    in.seekg(20, std::ios::cur);
  else if (h[21] != kFourCcRgba32f)
    throw std::runtime_error(path + ": not RGBA32F");
  const int n = static_cast<int>(h[4]);
  if (n <= 0 || static_cast<int>(h[3]) != n) throw std::runtime_error(path + ": not square");
  Cubemap cube(n);
  std::vector<float> face(static_cast<std::size_t>(n) * n * 4);
  for (int f = 0; f < 6; ++f) {
    in.read(reinterpret_cast<char*>(face.data()),
            static_cast<std::streamsize>(face.size() * sizeof(float)));
    if (!in) throw std::runtime_error(path + ": truncated");
    for (int i = 0; i < n * n; ++i) {
      cube.at(f, i % n, i / n) = glm::vec3(face[4 * i], face[4 * i + 1], face[4 * i + 2]);
    }
  }
  return cube;
}

// cmft's cube in our convention: our texel along d holds cmft's texel along (d.x, d.y, -d.z).
Cubemap mirroredInZ(const Cubemap& cube) {
  const int n = cube.size();
  Cubemap out(n);
  forEachTexel(n, [&](int f, int x, int y) {
    const glm::vec3 d = out.direction(f, x, y);
    const CubeCoord c = Cubemap::project(glm::vec3(d.x, d.y, -d.z));
    const int sx = std::min(n - 1, static_cast<int>(c.s * n));
    const int sy = std::min(n - 1, static_cast<int>(c.t * n));
    out.at(f, x, y) = cube.at(c.face, sx, sy);
  });
  return out;
}

std::vector<glm::vec3> texelDirections(int n) {
  const Cubemap cube(n);
  std::vector<glm::vec3> dirs(cube.texelCount());
  forEachTexel(n,
               [&](int f, int x, int y) { dirs[cube.index(f, x, y)] = cube.direction(f, x, y); });
  return dirs;
}

void printErrors(const char* name, const Cubemap& cube, const std::vector<glm::vec3>& reference,
                 const std::vector<glm::vec3>& probes, const std::vector<glm::vec3>& probeRef) {
  const std::vector<glm::vec3> texels(cube.data(), cube.data() + cube.texelCount());
  double worst = 0.0;
  float lowest = INFINITY;
  for (std::size_t i = 0; i < texels.size(); ++i) {
    const double r = glm::length(glm::dvec3(reference[i]));
    worst = std::max(worst, glm::length(glm::dvec3(texels[i]) - glm::dvec3(reference[i])) / r);
    lowest = std::min({lowest, texels[i].x, texels[i].y, texels[i].z});
  }
  std::vector<glm::vec3> looked(probes.size());
  for (std::size_t i = 0; i < probes.size(); ++i) looked[i] = cube.sample(probes[i]);
  std::printf("%s,%.6g,%.6g,%.6g,%.6g\n", name, relativeRms(texels, reference), worst, lowest,
              relativeRms(looked, probeRef));
}

int error(const std::string& env, const std::string& ours, const std::string& cmft) {
  const ImageRgb image = readImage(env);
  const Cubemap a = readCubemap(ours);
  Cubemap b = mirroredInZ(readDdsCubemap(cmft));
  for (std::size_t i = 0; i < b.texelCount(); ++i) b.data()[i] *= static_cast<float>(M_PI);
  if (a.size() != b.size()) throw std::runtime_error("face sizes differ");
  const RadianceGrid grid = RadianceGrid::fromEquirect(image, 1);
  const std::vector<glm::vec3> normals = texelDirections(a.size());
  const std::vector<glm::vec3> reference = irradianceAtNormals(grid, normals, 1.0f);
  const std::vector<glm::vec3> probes = fibonacciSphere(1024);
  const std::vector<glm::vec3> probeRef = irradianceAtNormals(grid, probes, 1.0f);
  printErrors("sss-irrmap", a, reference, probes, probeRef);
  printErrors("cmft", b, reference, probes, probeRef);
  return 0;
}

int orientation(const std::string& env, const std::string& cmft) {
  const Cubemap theirs = mirroredInZ(readDdsCubemap(cmft));
  const Cubemap ours = cubemapFromImage(readImage(env), EnvironmentLayout::Equirect, theirs.size());
  const int n = ours.size();
  for (int f = 0; f < 6; ++f) {
    std::vector<glm::vec3> a(ours.data() + f * n * n, ours.data() + (f + 1) * n * n);
    std::vector<glm::vec3> b(theirs.data() + f * n * n, theirs.data() + (f + 1) * n * n);
    std::printf("face %d: relative RMS %.4f\n", f, relativeRms(b, a));
  }
  return 0;
}

int batch(const std::string& outDir, const std::vector<std::string>& envs) {
  std::printf("map,read_ms,irradiance_ms,write_ms,total_ms,cpu_ms,estimated_error\n");
  for (const std::string& env : envs) {
    const double cpu0 = processCpuMilliseconds();
    Stopwatch total, watch;
    const ImageRgb image = readImage(env);
    const double readMs = watch.milliseconds();
    IrradianceOptions options;
    options.faceSize = 32;
    const IrradianceResult result = computeIrradianceFromEquirect(image, options);
    const double irradianceMs = result.timings.totalMs;
    watch.restart();
    const std::string out =
        outDir + "/" + std::filesystem::path(env).stem().string() + "_irradiance.exr";
    writeCubemap(out, result.irradiance);
    writeCubemapPreview(cubemapPreviewPath(out), result.irradiance);
    std::printf("%s,%.3f,%.3f,%.3f,%.3f,%.3f,%.6g\n", std::filesystem::path(env).stem().c_str(),
                readMs, irradianceMs, watch.milliseconds(), total.milliseconds(),
                processCpuMilliseconds() - cpu0, result.estimatedError);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  try {
    if (args.size() == 3 && args[0] == "dds") {
      writeDds(readImage(args[1]), args[2]);
      return 0;
    }
    if (args.size() == 3 && args[0] == "exr") {
      writeImage(args[2], readImage(args[1]), {{"compression", "none"}});
      return 0;
    }
    if (args.size() == 2 && args[0] == "tiny") {
      ImageRgb grey;
      grey.width = 64;
      grey.height = 32;
      grey.pixels.assign(64 * 32, glm::vec3(0.5f));
      writeImage(args[1], grey);
      return 0;
    }
    if (args.size() == 4 && args[0] == "error") return error(args[1], args[2], args[3]);
    if (args.size() == 3 && args[0] == "orientation") return orientation(args[1], args[2]);
    if (args.size() >= 3 && args[0] == "batch") {
      return batch(args[1], std::vector<std::string>(args.begin() + 2, args.end()));
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "irrmap_compare: error: %s\n", e.what());
    return 1;
  }
  std::fprintf(stderr,
               "usage: irrmap_compare dds ENV.exr OUT.dds | exr ENV.exr OUT.exr | tiny OUT.exr | "
               "error ENV.exr OURS.exr CMFT.dds | "
               "orientation ENV.exr CMFT.dds | batch OUT_DIR ENV.exr...\n");
  return 2;
}
