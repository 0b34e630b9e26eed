// An object of several materials (a glTF whose parts --material-map maps to different presets):
// light crosses between the parts. The bake runs whole once per material, as if the object were
// all of it (every stage: entry, escape energy, diffusion sum, far field, bounces, exit), and
// mixes the results per vertex by the share of the vertex's area (a third of each of its
// triangles, Li & Guo's M) that is of each material.
//
// That mix alone is the receiver's rule of renderers with a profile per pixel (e.g. Jimenez et
// al. 2015, "Separable Subsurface Scattering"): light entering part A and leaving from part B is
// spread with B's transport. Near a border it gives the weaker absorber's side (per channel) too
// much light: it assumes the light there is not lost into the stronger absorber. The symmetric
// kernel, the mean of the two materials' transports for light crossing between parts
// ((T_A + T_B) / 2; reciprocal, as the true transport in a medium of one eta is, and T_A within
// part A), fixes that side in part but errs the other way on the stronger absorber's side, where
// it carries half of the weaker absorber's far-reaching light that the stronger one absorbs. So
// the bake takes, per vertex and channel, the lower of the two (the border rule): to the
// receiver's mix it adds the symmetric kernel's change where that change removes light. Each
// material m's part of the change is (T_m(s_m E) - s_m T_m(E)) / 2, s_m the vertices' shares of
// m, through the bounces' linear transport (the traced far field and the bounces keep the
// receiver's rule). Both rules are exact far from the borders. docs/accuracy.md ("Several
// materials") has the three rules against a Monte Carlo of both media.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "bake/bake_report.h"
#include "mesh/baked_ply.h"
#include "mesh/triangle_mesh.h"

namespace sss {

// Per material, per vertex: the share of the vertex's area of that material (shares sum to 1).
// trianglePart: each triangle's part; partMaterial: each part's material (material_map.h).
std::vector<std::vector<float>> vertexMaterialShares(const TriangleMesh& mesh,
                                                     std::span<const std::uint32_t> trianglePart,
                                                     std::span<const std::uint32_t> partMaterial,
                                                     std::size_t materials);

// The per-vertex fields of `bakes` (one per material, of one mesh) mixed by `shares`: E, B, the
// radiance along the normal, and the far field's B and exit slope (a bake without a traced far
// field counts as 0 and the normalized exit, slope 0). The header (material, comments) is
// that of bakes[header]; relightable fields are not mixed (the bake refuses them with several
// materials).
BakedMesh mixBakedMeshes(std::vector<BakedMesh> bakes,
                         const std::vector<std::vector<float>>& shares, std::size_t header);

// The materials' predicted errors (relative RMS over the surface) mixed as their vertices are:
// each error in quadrature, weighted by the material's area share.
BakeErrorReport mixErrorReports(std::span<const BakeErrorReport> errors,
                                std::span<const double> areaShares);

// The error near the borders, relative RMS of the radiance along the normal
// over the surface (area-weighted), an upper estimate: at a vertex of material m at surface
// distance d (along the mesh's edges) from the nearest border vertex, half the difference between
// the materials' radiance there, decaying as exp(-sigma_tr,m d) (sigma_tr = sqrt(3 sigma_a
// sigma_t'), the diffusion's attenuation into m: a border is a change of medium whose effect the
// diffusion carries that far). Against a Monte Carlo of both media it is 1.2-1.8x the measured
// error (docs/accuracy.md, "Several materials"). radiance: per material, its bake's radiance
// along the normal; sigmaTr: per material, per mm.
double materialInterfaceError(const TriangleMesh& meshMm, std::span<const float> vertexAreas,
                              const std::vector<std::vector<float>>& shares,
                              const std::vector<std::span<const glm::vec3>>& radiance,
                              std::span<const glm::dvec3> sigmaTr);

// The materials' symmetric changes (above; per material, per vertex; an empty vector: none)
// summed and added to B and to the radiance along the normal of the receiver's mix: by the border
// rule where, per channel, they remove light; by the symmetric kernel everywhere; by the
// receiver's rule nowhere.
void applySymmetricChange(BakedMesh& mixed, const std::vector<std::vector<glm::vec3>>& exitance,
                          const std::vector<std::vector<glm::vec3>>& radiance, MaterialRule rule);

// Per material, the share of the whole surface's area.
std::vector<double> areaShares(const std::vector<std::vector<float>>& shares,
                               std::span<const float> vertexAreas);

}  // namespace sss
