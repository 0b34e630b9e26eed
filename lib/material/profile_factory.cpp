#include "material/profile_factory.h"

#include "core/error.h"
#include "material/beam_diffusion_profile.h"
#include "material/burley_profile.h"
#include "material/dipole_profile.h"

namespace sss {

std::vector<std::string> listProfiles() {
  return {"dipole", "beam", "burley"};
}

std::unique_ptr<DiffusionProfile> makeProfile(const std::string& kind, const Material& material) {
  if (kind == "dipole") return std::make_unique<DipoleProfile>(material);
  if (kind == "beam") return std::make_unique<BeamDiffusionProfile>(material);
  if (kind == "burley") return std::make_unique<BurleyProfile>(material);
  std::string known;
  for (const std::string& k : listProfiles()) known += (known.empty() ? "" : ", ") + k;
  fail("", "unknown profile '" + kind + "' (known: " + known + ")");
}

}  // namespace sss
