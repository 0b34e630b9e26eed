// Materials: presets, validation messages, and the Jensen & Buhler 2002 albedo/mfp inversion.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/error.h"
#include "material/dipole_profile.h"
#include "material/halfspace_albedo.h"
#include "material/material.h"

namespace sss {
namespace {

std::string errorOf(const Material& m) {
  try {
    validateMaterial(m, "test.json");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(Material, PresetsAreJensen2001Figure5) {
  ASSERT_EQ(materialPresets().size(), 11u);
  const Material marble = findMaterialPreset("marble");
  EXPECT_EQ(marble.sigmaSPrime, glm::dvec3(2.19, 2.62, 3.00));
  EXPECT_EQ(marble.sigmaA, glm::dvec3(0.0021, 0.0041, 0.0071));
  EXPECT_EQ(marble.eta, 1.3);
  const Material ketchup = findMaterialPreset("Ketchup");  // case-insensitive
  EXPECT_EQ(ketchup.sigmaSPrime, glm::dvec3(0.18, 0.07, 0.03));
  EXPECT_EQ(ketchup.sigmaA, glm::dvec3(0.061, 0.97, 1.45));
  for (const Material& m : materialPresets()) EXPECT_NO_THROW(validateMaterial(m, m.name));
}

TEST(Material, DerivedQuantities) {
  const Material skin = findMaterialPreset("skin1");
  EXPECT_NEAR(skin.sigmaTPrime().x, 0.772, 1e-12);
  EXPECT_NEAR(skin.reducedAlbedo().x, 0.74 / 0.772, 1e-12);
  EXPECT_NEAR(skin.sigmaTr().x, std::sqrt(3.0 * 0.032 * 0.772), 1e-12);
  EXPECT_NEAR(skin.diffuseMeanFreePath().x, 1.0 / std::sqrt(3.0 * 0.032 * 0.772), 1e-12);
  EXPECT_NEAR(skin.meanFreePath().x, 1.0 / 0.772, 1e-12);
}

TEST(Material, UnknownPresetListsNames) {
  try {
    findMaterialPreset("jade");
    FAIL() << "no error";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("unknown material 'jade'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("apple"), std::string::npos) << msg;
    EXPECT_NE(msg.find("wholemilk"), std::string::npos) << msg;
  }
}

TEST(Material, BadMaterialsThrowClearMessages) {
  const Material good = findMaterialPreset("marble");
  auto with = [&](auto change) {
    Material m = good;
    change(m);
    return errorOf(m);
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(errorOf(good), "");
  EXPECT_EQ(with([](Material& m) { m.sigmaA.y = -0.1; }),
            "test.json: sigma_a is negative (0.0021,-0.1,0.0071)");
  EXPECT_NE(with([&](Material& m) { m.sigmaSPrime.x = nan; }).find("sigma_s' is not a finite"),
            std::string::npos);
  EXPECT_NE(with([](Material& m) { m.sigmaSPrime.z = INFINITY; }).find("not a finite"),
            std::string::npos);
  EXPECT_NE(with([](Material& m) { m.sigmaA.x = 2e4; }).find("sigma_a is absurdly large"),
            std::string::npos);
  EXPECT_EQ(with([](Material& m) { m.sigmaA.z = 0, m.sigmaSPrime.z = 0; }),
            "test.json: zero extinction (sigma_a + sigma_s' = 0) in channel B");
  EXPECT_EQ(with([](Material& m) { m.eta = 0.9; }), "test.json: eta 0.9 is outside [1, 3]");
  EXPECT_EQ(with([](Material& m) { m.eta = 3.5; }), "test.json: eta 3.5 is outside [1, 3]");
  EXPECT_NE(with([&](Material& m) { m.eta = nan; }).find("eta"), std::string::npos);
  EXPECT_NE(with([](Material& m) { m.g = 1.0; }).find("g 1 is outside (-1, 1)"), std::string::npos);
}

// Jensen & Buhler 2002: (total diffuse reflectance, l_d = 1/sigma_tr) -> coefficients, invertible
// through the Monte Carlo half-space albedo (the energy the bake's profiles return).
TEST(Material, AlbedoMfpInversionRoundTrips) {
  for (const Material& m : materialPresets()) {
    const glm::dvec3 ap = m.reducedAlbedo();
    const glm::dvec3 albedo(halfSpaceDiffuseAlbedo(ap.x, m.eta),
                            halfSpaceDiffuseAlbedo(ap.y, m.eta),
                            halfSpaceDiffuseAlbedo(ap.z, m.eta));
    const Material back = materialFromAlbedoMfp(albedo, m.diffuseMeanFreePath(), m.eta, m.name);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(back.sigmaA[c] / m.sigmaA[c], 1.0, 1e-6) << m.name << " channel " << c;
      EXPECT_NEAR(back.sigmaSPrime[c] / m.sigmaSPrime[c], 1.0, 1e-6) << m.name << " " << c;
    }
    const glm::dvec3 again = back.reducedAlbedo();
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(halfSpaceDiffuseAlbedo(again[c], m.eta), albedo[c], 1e-9) << m.name << " " << c;
  }
}

TEST(Material, AlbedoMfpInversionRejectsBadInput) {
  const glm::dvec3 mfp(1.0);
  EXPECT_THROW(materialFromAlbedoMfp(glm::dvec3(0.5, 0.0, 0.5), mfp, 1.3), Error);
  EXPECT_THROW(materialFromAlbedoMfp(glm::dvec3(0.5, 1.0, 0.5), mfp, 1.3), Error);
  EXPECT_THROW(materialFromAlbedoMfp(glm::dvec3(0.5), glm::dvec3(1.0, -1.0, 1.0), 1.3), Error);
  EXPECT_THROW(materialFromAlbedoMfp(glm::dvec3(0.5), mfp, 0.8), Error);
  try {
    materialFromAlbedoMfp(glm::dvec3(0.5, 1.2, 0.5), mfp, 1.3, "skin.json");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind("skin.json: albedo 0.5,1.2,0.5 must lie in (0, ", 0), 0u)
        << e.what();
  }
}

}  // namespace
}  // namespace sss
