// sss-bake --texture: a low-poly UV sphere baked into a lightmap matches a dense sphere baked per
// vertex (the texels, not the 24 x 12 facets, set the detail), its seam agrees, a GLB carries it as
// the emission, and the mistakes a user can make (no texture coordinates, an output that is neither
// an EXR nor a GLB, a size out of range) are one clear line with no output.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/constants.hpp>
#include <nlohmann/json.hpp>

#include "image/image.h"
#include "material/material.h"
#include "mesh/baked_glb.h"
#include "mesh/baked_mesh.h"
#include "mesh/glb_chunks.h"
#include "mesh/lightmapped_glb.h"
#include "mesh/primitives.h"
#include "support/gltf_builder.h"
#include "support/tool_test.h"
#include "support/uv_sphere.h"

namespace sss {
namespace {

using test::Capture;
using test::ScratchDir;
using test::sphereDirection;
using test::ToolRun;
using test::uvSphereGlb;

constexpr float kRadiusM = 0.01f;

class BakeTexture : public ::testing::Test {
 protected:
  ToolRun bake(const std::string& mesh, const std::string& out, const std::string& extra) const {
    return test::runTool("sss-bake",
                         dir_.path(mesh) + " --sky=elevation=20,azimuth=40 -m marble -o " +
                             dir_.path(out) + " --energy halfspace --unscattered off -q " + extra,
                         Capture::StdoutAndStderr);
  }
  ScratchDir dir_;
};

TEST_F(BakeTexture, LowPolyLightmapMatchesADenseVertexBake) {
  test::writeText(dir_.path("sphere.glb"), uvSphereGlb(24, 12, kRadiusM));
  const ToolRun r = bake("sphere.glb", "light.exr", "--texture 128 --json " + dir_.path("r.json"));
  ASSERT_EQ(r.exitCode, 0) << r.output;
  BakedMesh dense;
  dense.mesh = makeIcosphere(5, kRadiusM);
  dense.mmPerUnit = 1000.0;
  writeBakedGlb(dir_.path("dense.glb"), dense);
  ASSERT_EQ(bake("dense.glb", "dense_baked.ply", "").exitCode, 0);
  const BakedMesh reference = readBakedPly(dir_.path("dense_baked.ply")).baked;
  const ImageRgb radiance = readImage(dir_.path("light.exr"));
  const ImageRgb exitance = readImage(dir_.path("light_exitance.exr"));
  ASSERT_EQ(radiance.width, 128);
  ASSERT_EQ(exitance.height, 128);
  // Every texel away from the poles (where the UV sphere's facets fold to a point) against the
  // dense bake's nearest vertex (0.7 degrees apart).
  double err2 = 0.0, ref2 = 0.0, errB2 = 0.0, refB2 = 0.0;
  for (int y = 8; y < 120; ++y) {
    for (int x = 0; x < 128; ++x) {
      const glm::vec3 d = sphereDirection((x + 0.5f) / 128, (y + 0.5f) / 128);
      std::size_t nearest = 0;
      for (std::size_t v = 1; v < reference.mesh.vertexCount(); ++v) {
        if (glm::dot(reference.mesh.normals[v], d) > glm::dot(reference.mesh.normals[nearest], d)) {
          nearest = v;
        }
      }
      const glm::vec3 e = radiance.pixels[y * 128 + x] - reference.radianceNormal[nearest];
      const glm::vec3 eB = exitance.pixels[y * 128 + x] - reference.exitance[nearest];
      err2 += glm::dot(e, e);
      ref2 += glm::dot(reference.radianceNormal[nearest], reference.radianceNormal[nearest]);
      errB2 += glm::dot(eB, eB);
      refB2 += glm::dot(reference.exitance[nearest], reference.exitance[nearest]);
    }
  }
  EXPECT_LT(std::sqrt(err2 / ref2), 0.02);
  EXPECT_LT(std::sqrt(errB2 / refB2), 0.02);
  const auto report = nlohmann::json::parse(test::readFile(dir_.path("r.json")));
  const auto& texture = report["texture"];
  EXPECT_EQ(texture["size"], 128);
  EXPECT_GT(texture["refined_vertices"].get<int>(), 10000);
  // The pole bands' triangles cover half of their rows: 1 - 1/12 of the map.
  EXPECT_NEAR(texture["covered_fraction"].get<double>(), 11.0 / 12.0, 0.005);
  EXPECT_EQ(texture["overlapping_texels"], 0);
  EXPECT_GE(texture["seams"]["edges"].get<int>(), 12);  // the u = 0 / 1 seam
  EXPECT_LT(texture["seams"]["relative_rms"].get<double>(), 0.01);
  EXPECT_EQ(texture["exitance_output"], dir_.path("light_exitance.exr"));
}

// -o NAME.glb: the same bake's lightmap as the asset's emission. Decoded from its 8-bit sRGB PNG
// and scaled by emissiveStrength, the emission under the coat's transmittance at normal incidence
// is the EXR's radiance along the normal to the 8-bit step.
TEST_F(BakeTexture, GlbCarriesTheLightmapAsItsEmission) {
  test::writeText(dir_.path("sphere.glb"), uvSphereGlb(24, 12, kRadiusM));
  ASSERT_EQ(bake("sphere.glb", "light.exr", "--texture 64").exitCode, 0);
  const ToolRun r = bake("sphere.glb", "asset.glb", "--texture 64");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const GlbChunks chunks = readGlbChunks(dir_.path("asset.glb"));
  const auto doc = nlohmann::json::parse(chunks.json);
  const double strength =
      doc["materials"][0]["extensions"]["KHR_materials_emissive_strength"]["emissiveStrength"]
          .get<double>();
  // Marble's eta 1.3: the coat weight whose Schlick reflectance fits F_r(mu, 1.3) best.
  const double coatWeight =
      doc["materials"][0]["extensions"]["KHR_materials_clearcoat"]["clearcoatFactor"];
  EXPECT_NEAR(coatWeight, 0.824, 0.001);
  const double coatTransmittance = 1.0 - coatWeight * kCoatNormalReflectance;
  const auto& view = doc["bufferViews"][doc["images"][0]["bufferView"].get<int>()];
  test::writeText(dir_.path("emission.png"),
                  chunks.bin.substr(view["byteOffset"].get<std::size_t>(),
                                    view["byteLength"].get<std::size_t>()));
  const ImageRgb emission = readImage(dir_.path("emission.png"));
  const ImageRgb radiance = readImage(dir_.path("light.exr"));
  ASSERT_EQ(emission.width, 64);
  double err2 = 0.0, ref2 = 0.0, peak = 0.0;
  for (std::size_t i = 0; i < radiance.pixels.size(); ++i) {
    const glm::dvec3 shown = glm::dvec3(emission.pixels[i]) * strength * coatTransmittance;
    const glm::dvec3 want(radiance.pixels[i]);
    err2 += glm::dot(shown - want, shown - want);
    ref2 += glm::dot(want, want);
    peak = std::max({peak, want.x, want.y, want.z});
  }
  EXPECT_LT(std::sqrt(err2 / ref2), 0.004);  // 8-bit sRGB steps: 0.2-0.4 % at these values
  EXPECT_NEAR(strength * coatTransmittance, peak, 1e-6 * peak);
  // The source's node and mesh, not the refined mesh.
  EXPECT_EQ(doc["nodes"][0]["name"], "sphere");
  EXPECT_EQ(doc["meshes"][0]["name"], "sphere");
  const auto& extras = doc["asset"]["extras"]["sss"];
  EXPECT_EQ(extras["material"]["name"], "marble");
  EXPECT_EQ(extras["report"]["texture"]["size"], 64);
}

// A source material's surface survives the bake: its roughness and normal map on the coat that
// reflects, the normal map's tangents, its image's bytes; what cannot be kept (a map on
// TEXCOORD_1) is one warning line naming the output, the material and the map.
TEST_F(BakeTexture, GlbKeepsTheSourceSurfaceAndNamesWhatItDrops) {
  test::GltfBuilder b;
  const std::vector<std::uint8_t> flat(3 * 4 * 4, 128);
  const std::string normalMap =
      encodePng("normal map", {.width = 4, .height = 4, .srgb8 = flat.data(), .attributes = {}});
  b.doc["images"] = {{{"bufferView", b.view(normalMap)}, {"mimeType", "image/png"}}};
  b.doc["textures"] = {{{"source", 0}}};
  b.doc["materials"] = {
      {{"name", "Wax"},
       {"pbrMetallicRoughness",
        {{"roughnessFactor", 0.4}, {"metallicRoughnessTexture", {{"index", 0}, {"texCoord", 1}}}}},
       {"normalTexture", {{"index", 0}}}}};
  test::GltfBuilder::Primitive p = test::uvSpherePrimitive(b, 24, 12, kRadiusM);
  p.material = 0;
  b.scene({b.node({{"name", "candle"}, {"mesh", b.mesh({p}, "candle")}})});
  test::writeText(dir_.path("candle.glb"), b.glb());
  const std::string out = dir_.path("candle_baked.glb");
  const ToolRun r = test::runTool("sss-bake",
                                  dir_.path("candle.glb") + " --sky -m marble --texture 64 -o " +
                                      out + " --energy halfspace --unscattered off",
                                  Capture::Stderr);
  ASSERT_EQ(r.exitCode, 0) << r.output;
  EXPECT_NE(r.output.find("sss-bake: warning: " + out +
                          ": material 'Wax': metallicRoughnessTexture (TEXCOORD_1) not kept\n"),
            std::string::npos)
      << r.output;
  const GlbChunks chunks = readGlbChunks(out);
  const auto doc = nlohmann::json::parse(chunks.json);
  const auto& m = doc["materials"][0];
  EXPECT_EQ(m["name"], "Wax (baked translucency: emission, coat)");
  EXPECT_EQ(m["pbrMetallicRoughness"]["roughnessFactor"], 0.4);
  EXPECT_FALSE(m["pbrMetallicRoughness"].contains("metallicRoughnessTexture"));
  const auto& coat = m["extensions"]["KHR_materials_clearcoat"];
  EXPECT_EQ(coat["clearcoatRoughnessFactor"], 0.4);
  ASSERT_TRUE(coat.contains("clearcoatNormalTexture"));
  const auto& texture = doc["textures"][coat["clearcoatNormalTexture"]["index"].get<int>()];
  const auto& view =
      doc["bufferViews"][doc["images"][texture["source"].get<int>()]["bufferView"].get<int>()];
  EXPECT_EQ(chunks.bin.substr(view["byteOffset"].get<std::size_t>(),
                              view["byteLength"].get<std::size_t>()),
            normalMap);
  EXPECT_TRUE(doc["meshes"][0]["primitives"][0]["attributes"].contains("TANGENT"));
}

// A sphere of two materials (--material-map) baked to a lightmapped GLB: each half's material
// carries its own medium in KHR_materials_volume (attenuation from its sigma_tr), and the report
// inside says which parts are which.
TEST_F(BakeTexture, GlbGivesEachPartItsOwnMedium) {
  test::GltfBuilder b;
  std::vector<test::GltfBuilder::Primitive> halves = {
      test::uvSpherePrimitive(b, 24, 12, kRadiusM, 0, 6),
      test::uvSpherePrimitive(b, 24, 12, kRadiusM, 6, 12)};
  halves[0].material = b.material("Upper");
  halves[1].material = b.material("Lower");
  b.scene({b.node({{"name", "ball"}, {"mesh", b.mesh(halves, "ball")}})});
  test::writeText(dir_.path("ball.glb"), b.glb());
  const ToolRun r = bake("ball.glb", "ball_baked.glb", "--texture 64 --material-map Upper=skin1");
  ASSERT_EQ(r.exitCode, 0) << r.output;
  const auto doc = nlohmann::json::parse(readGlbChunks(dir_.path("ball_baked.glb")).json);
  ASSERT_EQ(doc["materials"].size(), 2u);
  const auto attenuation = [](const Material& m) {  // the colour after the shortest 1 / sigma_tr
    const glm::dvec3 sigmaTr = m.sigmaTr();
    const double largest = std::max({sigmaTr.x, sigmaTr.y, sigmaTr.z});
    return std::pair(glm::exp(-sigmaTr / largest), 1e-3 / largest);
  };
  const char* presets[2] = {"skin1", "marble"};
  for (int k = 0; k < 2; ++k) {
    SCOPED_TRACE(presets[k]);
    const auto& volume = doc["materials"][k]["extensions"]["KHR_materials_volume"];
    const auto [colour, distanceM] = attenuation(findMaterialPreset(presets[k]));
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(volume["attenuationColor"][c], colour[c], 1e-9);
    EXPECT_NEAR(volume["attenuationDistance"].get<double>(), distanceM, 1e-12);
  }
  const auto& report = doc["asset"]["extras"]["sss"]["report"];
  ASSERT_EQ(report["part_materials"].size(), 2u);
  EXPECT_EQ(report["part_materials"][0]["parts"], nlohmann::json::array({"Upper"}));
}

TEST_F(BakeTexture, MistakesAreOneLineAndWriteNothing) {
  BakedMesh plain;
  plain.mesh = makeIcosphere(1, kRadiusM);
  plain.mmPerUnit = 1000.0;
  writeBakedGlb(dir_.path("no_uv.glb"), plain);
  test::writeText(dir_.path("sphere.glb"), uvSphereGlb(8, 4, kRadiusM));
  const ToolRun noUv = bake("no_uv.glb", "a.exr", "--texture 64");
  EXPECT_EQ(noUv.exitCode, 1);
  EXPECT_EQ(noUv.output, "sss-bake: error: " + dir_.path("no_uv.glb") +
                             ": --texture needs texture coordinates (a glTF with TEXCOORD_0); "
                             "this mesh has none\n");
  const ToolRun png = bake("sphere.glb", "a.png", "--texture 64");
  EXPECT_EQ(png.exitCode, 2);
  EXPECT_NE(png.output.find("with --texture the output is the lightmap, NAME.exr, or the asset"),
            std::string::npos)
      << png.output;
  const ToolRun small = bake("sphere.glb", "a.exr", "--texture 8");
  EXPECT_EQ(small.exitCode, 2);
  EXPECT_NE(small.output.find("texels a side must be in [16, 8192]"), std::string::npos)
      << small.output;
  for (const char* name : {"a.exr", "a_exitance.exr", "a.png", "a_exitance.png"}) {
    EXPECT_FALSE(std::filesystem::exists(dir_.path(name))) << name;
  }
}

}  // namespace
}  // namespace sss
