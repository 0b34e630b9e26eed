// The diffusion sums of Li & Guo Eq. 7: the exitance at every vertex from the transmitted
// irradiance at all vertices,
//
//   B(x_o) = sum_i R_d(|x_i - x_o|) E(x_i) A_i,
//
// with positions in mm, A_i the area a vertex stands for (mm^2, one third of its triangles:
// Li & Guo's M) and R_d a diffusion profile (lib/material) or its sum of normalized Gaussians
// G(v, r) = exp(-r^2 / 2v) / (2 pi v) (Li & Guo Eq. 9 drops the 1/v; corrected here).
//
// Methods:
//   exact         every pair with the profile itself, O(N^2): the reference
//                 (exact_diffusion_sum.h).
//   gauss         the Gaussian fit, every pair closer than a cutoff radius per Gaussian (energy
//                 beyond r_c of a 2D Gaussian is exp(-r_c^2 / 2v)), over an octree
//                 (octree_gaussian_sum.h, diffusion_octree.h).
//   incremental   Li & Guo Eq. 11: pass k convolves pass k-1 with G(v_k - v_(k-1)); exact on
//                 a plane, approximate on a discrete curved surface (incremental_diffusion.h;
//                 measured in docs/physics.md, "Where we correct the paper").
//   hierarchical  Jensen & Buhler 2002: octree clusters (area-weighted irradiance sums, centroid,
//                 spread) replace far groups of points when the cluster is small against the
//                 narrowest Gaussian that still reaches it; for wide (translucent) kernels.
//   auto          the cheapest of exact, gauss and hierarchical that meets the tolerance, from
//                 cost estimates (diffusion.cpp).
// Error budget of the Gaussian methods: the fit gets half the tolerance, truncation a quarter,
// clusters about a sixth.
// Stability: the self term integrates the profile over the vertex's disc of area A_i, and each
// source point is a disc (per-axis variance rho^2 / 4), so meshes coarser than the mean free path
// stay finite and close to the continuous answer.
// Sources without light (E = 0 over an octree node, or at a point) are skipped by the octree sums:
// their terms are zero (the bounces' light on convex parts, a compact light's unlit side).
// Determinism: every vertex sums its terms in a fixed order: identical for any thread count.
#pragma once

#include <memory>

#include "diffusion/diffusion_types.h"
#include "material/gaussian_sum_fit.h"

namespace sss {

struct DiffusionOctree;  // diffusion_octree.h (private to lib/diffusion)

// What diffuse() builds that does not depend on the light, kept between calls that sum over one
// mesh many times (a bake's bounces, a relight's transports; DiffusionOptions::meshCache): the
// octree over its vertices (Morton order, receiver groups), rebuilt when a call's positions,
// normals or areas differ from the kept ones (compared by value), and the profile's Gaussian fits,
// one per profile and tolerance. One caller at a time.
class DiffusionMeshCache {
 public:
  DiffusionMeshCache();
  ~DiffusionMeshCache();
  DiffusionMeshCache(const DiffusionMeshCache&) = delete;
  DiffusionMeshCache& operator=(const DiffusionMeshCache&) = delete;
  // The octree of `input`'s mesh, built or kept.
  std::shared_ptr<const DiffusionOctree> octree(const DiffusionInput& input);
  // fitGaussians(profile, tolerance, maxGaussians), fitted or kept: the fit is deterministic, so a
  // kept one is the one a new fit would give. Profiles are told apart by their name and values.
  GaussianSumFit fit(const DiffusionProfile& profile, double tolerance, int maxGaussians);

 private:
  struct KeptFit {
    std::vector<double> profileValues;  // profileFingerprint
    std::string profileName;
    double tolerance = 0;
    int maxGaussians = 0;
    GaussianSumFit fit;
  };
  std::vector<glm::vec3> positions_, normals_;
  std::vector<float> areas_;
  std::shared_ptr<const DiffusionOctree> octree_;
  std::vector<KeptFit> fits_;
};

// Throws sss::Error on mismatched array lengths, non-finite input or negative areas.
DiffusionResult diffuse(const DiffusionInput& input, const DiffusionProfile& profile,
                        const DiffusionOptions& options = {});

}  // namespace sss
