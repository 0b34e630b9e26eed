// The light a vertex's facets would take in with nothing in the way: the control the visibility
// estimator's ratio is taken against (visibility_vertex_estimator.h).
//
//   T(n)   = integral of F_t(eta, n . w) (n . w)+ L(w) dw          (Li & Guo Eq. 6 without V)
//   T_w(n) = the same with each direction weighted by the entry's w(n . w), per channel
//
// as cubemaps over the normal, each texel the direct sum over the radiance's texels (its brightest
// where they are, the rest box-filtered to kSourceFaceSize: T is a cosine-lobe convolution, so
// the smooth part's resolution moves it only in second order), looked up bilinearly; a vertex takes
// sum_f share_f T(n_f) over its facets (facet_light.h). tests/lighting/visibility_test.cpp bounds
// the lookup against the exact sum over every texel under a small sun.
#pragma once

#include <cstddef>

#include <glm/vec3.hpp>

#include "envmap/cubemap.h"
#include "material/directional_albedo_weight.h"
#include "mesh/triangle_mesh.h"

namespace sss {

class UnoccludedIntake {
 public:
  static constexpr int kFaceSize = 32;        // the normal's cubemaps: 2.8 degrees a texel
  static constexpr int kSourceFaceSize = 32;  // the radiance summed over

  // entry: null for none (entryWeighted stays 0). threads <= 0: all cores.
  UnoccludedIntake(const Cubemap& radiance, float eta, const DirectionalAlbedoWeight* entry,
                   int threads, int faceSize = kFaceSize, int sourceFaceSize = kSourceFaceSize);

  struct Value {
    glm::vec3 transmitted{0.0f};    // sum_f share_f T(n_f)
    glm::vec3 entryWeighted{0.0f};  // sum_f share_f T_w(n_f)
  };
  // A vertex without facets (no triangle of any area, or a smooth one) takes its normal.
  Value at(const VertexFacets& facets, std::size_t v, const glm::vec3& normal) const;

 private:
  Cubemap transmitted_, entryWeighted_;
  bool hasEntry_ = false;
};

}  // namespace sss
