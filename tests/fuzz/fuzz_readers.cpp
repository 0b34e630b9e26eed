#include "fuzz_readers.h"

#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "bake/material_map.h"
#include "bake/relight.h"
#include "core/error.h"
#include "envmap/environment.h"
#include "image/image.h"  // NonFiniteTexelsError
#include "mesh/baked_glb.h"
#include "mesh/baked_ply.h"
#include "mesh/load_mesh.h"

namespace sss::fuzz {
namespace {

// OpenImageIO picks its reader from the extension (and tries the others when that one refuses),
// so the environment target names each input after its magic: the seeds are EXR, HDR and PFM.
std::string imageExtension(std::string_view bytes) {
  if (bytes.starts_with("#?")) return "hdr";
  if (bytes.starts_with("PF") || bytes.starts_with("Pf")) return "pfm";
  return "exr";
}

// The loader as sss-irrmap and sss-bake call it, into a small cubemap (faceSize 0 would follow the
// image's width: a valid 2:1 image at the pixel limit would make every input slow without reaching
// other code); NaN/Inf texels are refused, then read again with sanitize as --sanitize does.
void readEnvironment(const std::string& path) {
  EnvironmentOptions options;
  options.faceSize = 8;
  options.threads = 1;
  try {
    loadEnvironment(path, options);
  } catch (const NonFiniteTexelsError&) {
    options.read.sanitize = true;
    loadEnvironment(path, options);
  }
}

// readImage as the tools call it, refused NaN/Inf texels read again with sanitize. The image
// targets feed lib/image's own readers (image_format.h picks them by content, the extension
// aside); "environment" goes on to the layouts and the cubemap.
void readImageFile(const std::string& path) {
  try {
    readImage(path);
  } catch (const NonFiniteTexelsError&) {
    readImage(path, {true, true});
  }
}

bool isImageTarget(std::string_view target) {
  return target == "exr" || target == "hdr" || target == "png";
}

}  // namespace

const std::vector<std::string>& targetNames() {
  static const std::vector<std::string> names = {
      "ply",  "obj", "off", "stl", "environment", "baked_ply",   "baked_glb",
      "gltf", "glb", "exr", "hdr", "png",         "material_map"};
  return names;
}

void readInput(std::string_view target, std::string_view bytes, const std::string& dir) {
  const std::string ext = target == "environment"    ? imageExtension(bytes)
                          : target == "baked_ply"    ? "ply"
                          : target == "baked_glb"    ? "glb"
                          : target == "material_map" ? "json"
                                                     : std::string(target);
  const std::string path = (std::filesystem::path(dir) / ("input." + ext)).string();
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (!out) throw std::runtime_error("cannot write " + path);
  }
  if (target == "environment") {
    readEnvironment(path);
  } else if (isImageTarget(target)) {
    readImageFile(path);
  } else if (target == "material_map") {
    parseMaterialMap(path);
  } else if (target == "baked_ply") {
    checkRelightTransport(path, readBakedPly(path).baked);
  } else if (target == "baked_glb") {
    checkRelightTransport(path, readBakedGlb(path).baked);
  } else if (target == "ply" || target == "obj" || target == "off" || target == "stl" ||
             target == "gltf" || target == "glb") {
    MeshReport report;
    MeshParts parts;
    loadMesh(path, &report, &parts);
  } else {
    throw std::logic_error("unknown fuzz target '" + std::string(target) + "'");
  }
}

}  // namespace sss::fuzz
