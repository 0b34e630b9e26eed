// The diffusion profiles by name (sss-bake --profile): dipole_profile.h, beam_diffusion_profile.h
// and burley_profile.h behind the DiffusionProfile interface (diffusion_profile.h).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "material/diffusion_profile.h"

namespace sss {

// kind: one of listProfiles(). Validates the material; throws sss::Error naming the kinds.
std::unique_ptr<DiffusionProfile> makeProfile(const std::string& kind, const Material& material);
std::vector<std::string> listProfiles();

}  // namespace sss
