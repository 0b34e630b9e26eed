// A UV lightmap filled from per-vertex values of a refined mesh (uv_refinement.h): each texel
// whose centre lies in a triangle in UV space takes the barycentric interpolation of its corners'
// values, the texels around each chart are padded, and the texels on either side of a UV seam are
// compared.
//
// Texel (x, y) covers u in [x, x + 1) / size and v in [y, y + 1) / size, its centre at
// ((x + 0.5) / size, (y + 0.5) / size); row 0 is v = 0, the top of the image, as glTF's texture
// coordinates put it (glTF 2.0 specification, 3.8.1: "the origin ... is the top left corner").
//
// Padding (the gutter): `padding` rounds of dilation, each giving every empty texel next to a
// filled one the mean of its filled 8-neighbours, so that bilinear filtering and mipmaps near a
// chart's border read the chart's own light and not the empty background.
//
// Seams: a surface edge whose two triangles have different texture coordinates is drawn twice,
// once in each chart. Along every such edge the map is read (bilinearly, as a renderer reads it)
// at both sides' coordinates at `seamSamples` points; the relative RMS of the differences over all
// samples and channels says how far a viewer would see the seam.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "lightmap/uv_refinement.h"

namespace sss {

struct LightmapLayout {
  int size = 0;         // texels per side
  int padding = 4;      // dilation rounds around each chart, texels
  int seamSamples = 8;  // points per seam edge
};

struct SeamReport {
  std::size_t edges = 0;       // surface edges on a UV seam
  double relativeRms = 0.0;    // of the two sides' differences, over their mean
  double worstRelative = 0.0;  // the largest |difference| over the mean value on the seams
};

struct Lightmap {
  int size = 0;
  // Per texel (row-major, row 0 at v = 0), one image per field given to fillLightmap.
  std::vector<std::vector<glm::vec3>> images;
  // Per texel: 0 empty, 1 inside a triangle, 2 filled by padding.
  std::vector<std::uint8_t> coverage;
  std::size_t coveredTexels = 0, paddedTexels = 0;
  // Texels whose centre lies strictly inside two of the mesh's triangles (the unwrap overlaps):
  // the later triangle's values win.
  std::size_t overlappingTexels = 0;
};

// Fills one image per field (each a value per refined vertex).
Lightmap fillLightmap(const UvRefinement& refinement,
                      std::span<const std::span<const glm::vec3>> fields,
                      const LightmapLayout& layout);

// Bilinear lookup of image at texture coordinates uv, as a renderer's linear filter reads it
// (texel centres at (x + 0.5) / size; coordinates clamped to the border).
glm::vec3 sampleBilinear(std::span<const glm::vec3> image, int size, glm::vec2 uv);

// The seams of the refined mesh, read in `image` (one of the lightmap's).
SeamReport compareSeams(const UvRefinement& refinement, std::span<const glm::vec3> image, int size,
                        int samplesPerEdge);

}  // namespace sss
