// The texture bake's two stages (sss-bake --texture SIZE): before the bake, the mesh refined until
// its vertices are as dense as the texels (lightmap/uv_refinement.h); after it, the lightmap of
// the radiance along the normal and of the exitance filled from the refined vertices, padded,
// and its seams compared (lightmap/lightmap.h).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "bake/prepare_mesh.h"
#include "bake/texture_settings.h"
#include "lightmap/lightmap.h"
#include "lightmap/uv_refinement.h"
#include "material/material.h"
#include "mesh/baked_ply.h"
#include "mesh/lightmapped_glb.h"

namespace sss {

struct LightmapReport {
  int size = 0, padding = 0;
  std::size_t originalVertices = 0, originalTriangles = 0;
  std::size_t refinedVertices = 0, refinedTriangles = 0;
  std::size_t coveredTexels = 0, paddedTexels = 0, overlappingTexels = 0;
  SeamReport seams;  // of the radiance along the normal
  double refineSeconds = 0.0, fillSeconds = 0.0;
};

// The mesh as read (file units), with its parts and texture coordinates: what a lightmapped GLB
// draws the lightmap on.
struct TextureSource {
  TriangleMesh mesh;
  MeshParts parts;
};

struct TextureMesh {
  PreparedMesh mesh;  // refined: what stages 2-12 bake (moved there)
  TextureSource source;
  std::string file;  // the mesh's
  UvRefinement refinement;
  LightmapReport report;
};

// Stage 1b. Throws Error naming the mesh when it has no TEXCOORD_0, coordinates outside [0, 1],
// or would not fit in memory refined.
TextureMesh refineForTexture(PreparedMesh mesh, const TextureSettings& settings, bool quiet);

struct BakedLightmap {
  Lightmap map;  // images[0]: radiance along the normal, images[1]: exitance B
  LightmapReport report;
};

// Stage 13: the lightmap of the refined bake.
BakedLightmap bakeLightmap(const TextureMesh& texture, const BakedMesh& baked,
                           const TextureSettings& settings, bool quiet);

}  // namespace sss

namespace sss {

// For -o NAME.glb (mesh/lightmapped_glb.h): the source mesh with the lightmap as its emission
// under a clear coat weighted to follow the material's Fresnel reflectance. The emission is the
// radiance along the normal over the coat's transmittance at normal incidence (the coat darkens
// it by that much there), stored as 8-bit sRGB over its largest value, which becomes
// emissiveStrength. asset.extras.sss holds the source's unit, the material,
// how the emission was made and `reportJson` (the bake's report, JSON text, or empty).
// partMaterials: each part's material where they differ (BakeOutput::partMaterials), each
// written in its part's KHR_materials_volume; empty: the baked mesh's for all.
LightmappedAsset lightmappedAsset(const TextureSource& source, const Lightmap& map,
                                  const BakedMesh& baked,
                                  const std::vector<Material>& partMaterials,
                                  const std::string& reportJson);

}  // namespace sss
