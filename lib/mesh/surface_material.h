// A scene file's surface materials (glTF 2.0, section 3.9), kept so that an asset written back
// (mesh/lightmapped_glb.h) keeps what the bake does not replace: the surface's roughness, normal
// and occlusion maps, its alpha and how it is drawn. The images are kept as the file holds them
// (PNG or JPEG bytes), never decoded.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace sss {

// glTF's sampler enums (section 3.8.4; 5.26): wrapping and filtering. 0: absent (the viewer's
// choice of filter).
inline constexpr int kGltfRepeat = 10497, kGltfClampToEdge = 33071, kGltfMirroredRepeat = 33648;
inline constexpr int kGltfNearest = 9728, kGltfLinear = 9729, kGltfNearestMipmapNearest = 9984,
                     kGltfLinearMipmapLinear = 9987;

struct SurfaceImage {
  std::string mimeType;  // "image/png" or "image/jpeg"
  std::string bytes;
};

// A material's texture: which image, sampled how, and its scale (normalTexture.scale,
// occlusionTexture.strength; 1 for the others). Always TEXCOORD_0.
struct SurfaceTexture {
  std::uint32_t image = 0;  // into SurfaceMaterials::images
  int magFilter = 0, minFilter = 0;
  int wrapS = kGltfRepeat, wrapT = kGltfRepeat;
  double scale = 1.0;
  bool operator==(const SurfaceTexture&) const = default;
};

struct SurfaceMaterial {
  std::string name;
  double alpha = 1.0;                          // baseColorFactor's alpha
  std::optional<SurfaceTexture> baseColor;     // kept for its alpha (MASK, BLEND)
  double roughness = 1.0;                      // roughnessFactor
  std::optional<SurfaceTexture> roughnessMap;  // metallicRoughnessTexture: roughness in G
  std::optional<SurfaceTexture> normal, occlusion;
  std::string alphaMode = "OPAQUE";  // OPAQUE, MASK or BLEND
  double alphaCutoff = 0.5;
  bool doubleSided = false;
  // What the file gives that is not kept, each "<what> (<why>)", e.g. "normalTexture
  // (TEXCOORD_1)"; the base colour's RGB and the emission are always replaced by the bake.
  std::vector<std::string> dropped;
};

struct SurfaceMaterials {
  std::vector<SurfaceMaterial> materials;  // as the file indexes them
  std::vector<SurfaceImage> images;        // those the kept textures use
};

}  // namespace sss
