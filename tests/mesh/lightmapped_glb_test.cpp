// The lightmapped GLB (mesh/lightmapped_glb.h): a two-node scene read, written and read back keeps
// its nodes (names, world transforms, a mirroring one included), its welded vertices and triangles
// with their winding and texture coordinates, and carries the lightmap and the material's
// extensions as written; an asset it cannot write is one error naming the file and writes nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "mesh/glb_chunks.h"
#include "mesh/lightmapped_glb.h"
#include "mesh/load_mesh.h"
#include "support/gltf_builder.h"
#include "support/uv_sphere.h"
#include "test_util.h"

namespace sss {
namespace {

using test::GltfBuilder;
using test::ScratchDir;
using Json = nlohmann::json;

// Two nodes placing one UV sphere mesh: one scaled and moved, one mirrored by its matrix.
std::string twoNodeScene() {
  GltfBuilder b;
  const int ball = b.mesh({test::uvSpherePrimitive(b, 8, 4, 0.01f)}, "ball");
  const int left = b.node(
      {{"name", "left"}, {"mesh", ball}, {"translation", {-0.05, 0, 0}}, {"scale", {2, 2, 2}}});
  const int right = b.node({{"name", "right"},
                            {"mesh", ball},
                            {"matrix", {-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0.05, 0, 0, 1}}});
  b.scene({left, right});
  return b.glb();
}

LightmappedAsset assetOf(const std::string& path) {
  LightmappedAsset a;
  a.mesh = loadMesh(path, nullptr, &a.parts);
  a.mmPerUnit = a.parts.mmPerUnit;
  a.emissivePng = "not checked by the writer: stored as given";
  a.emissiveStrength = 2.5;
  a.medium = {"marble", {0.0021, 0.0041, 0.0071}, {2.19, 2.62, 3.0}};
  a.eta = 1.3;
  a.thicknessM = 0.02;
  a.extrasJson = R"({"format": 1})";
  return a;
}

// The triangle of `mesh` whose corners lie at t's corners in the same cyclic order (-1: none).
long findTriangle(const TriangleMesh& mesh, const TriangleMesh& other, std::size_t t, int& shift) {
  for (std::size_t u = 0; u < mesh.triangles.size(); ++u) {
    for (shift = 0; shift < 3; ++shift) {
      bool same = true;
      for (int c = 0; c < 3 && same; ++c) {
        const glm::vec3 p = mesh.positions[mesh.triangles[u][(c + shift) % 3]];
        same = glm::distance(p, other.positions[other.triangles[t][c]]) < 1e-6f;
      }
      if (same) return static_cast<long>(u);
    }
  }
  return -1;
}

TEST(LightmappedGlb, SceneRoundTripsWithItsTexcoordsAndWinding) {
  ScratchDir dir;
  test::writeFile(dir.path("scene.glb"), twoNodeScene());
  const LightmappedAsset in = assetOf(dir.path("scene.glb"));
  writeLightmappedGlb(dir.path("out.glb"), in);
  MeshParts backParts;
  const TriangleMesh back = loadMesh(dir.path("out.glb"), nullptr, &backParts);
  ASSERT_EQ(back.vertexCount(), in.mesh.vertexCount());
  ASSERT_EQ(back.triangleCount(), in.mesh.triangleCount());
  ASSERT_EQ(backParts.parts.size(), 2u);
  for (std::size_t p = 0; p < 2; ++p) {
    EXPECT_EQ(backParts.parts[p].node, in.parts.parts[p].node);
    EXPECT_EQ(backParts.parts[p].mesh, "ball");
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r)
        EXPECT_NEAR(backParts.parts[p].transform[c][r], in.parts.parts[p].transform[c][r], 1e-12);
  }
  for (std::size_t t = 0; t < back.triangleCount(); ++t) {
    int shift = 0;
    const long u = findTriangle(in.mesh, back, t, shift);
    ASSERT_GE(u, 0) << "triangle " << t << " is not in the source with the same winding";
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(backParts.cornerTexcoords[3 * t + c],
                in.parts.cornerTexcoords[3 * u + (c + shift) % 3]);
      EXPECT_GT(glm::dot(back.normals[back.triangles[t][c]],
                         in.mesh.normals[in.mesh.triangles[u][(c + shift) % 3]]),
                0.99999f);
    }
  }
  const GlbChunks chunks = readGlbChunks(dir.path("out.glb"));
  const Json doc = Json::parse(chunks.json);
  EXPECT_EQ(doc["nodes"].size(), 2u);
  EXPECT_EQ(doc["nodes"][0]["name"], "left");
  const Json& material = doc["materials"][0];
  EXPECT_EQ(material["pbrMetallicRoughness"]["baseColorFactor"], Json({0.0, 0.0, 0.0, 1.0}));
  EXPECT_EQ(material["emissiveTexture"]["index"], 0);
  const Json& ext = material["extensions"];
  EXPECT_EQ(ext["KHR_materials_emissive_strength"]["emissiveStrength"], 2.5);
  EXPECT_EQ(ext["KHR_materials_clearcoat"]["clearcoatFactor"], 1.0);
  EXPECT_EQ(ext["KHR_materials_specular"]["specularFactor"], 0.0);
  EXPECT_EQ(ext["KHR_materials_ior"]["ior"], 1.3);
  // The diffuse light's attenuation: the bluest channel (largest sigma_tr) falls to 1/e over the
  // distance; thickness in the nodes' frame (mean scale (2 + 1) / 2).
  const Json& volume = ext["KHR_materials_volume"];
  EXPECT_NEAR(volume["attenuationColor"][2].get<double>(), std::exp(-1.0), 1e-12);
  const double sigmaTrBlue = std::sqrt(3 * 0.0071 * (0.0071 + 3.0));
  EXPECT_NEAR(volume["attenuationDistance"].get<double>(), 1e-3 / sigmaTrBlue, 1e-12);
  EXPECT_NEAR(volume["thicknessFactor"].get<double>(), 0.02 / 1.5, 1e-12);
  const Json& image = doc["images"][0];
  EXPECT_EQ(image["mimeType"], "image/png");
  const Json& view = doc["bufferViews"][image["bufferView"].get<int>()];
  EXPECT_EQ(chunks.bin.substr(view["byteOffset"].get<std::size_t>(),
                              view["byteLength"].get<std::size_t>()),
            in.emissivePng);
  EXPECT_EQ(doc["asset"]["extras"]["sss"]["format"], 1);
}

TEST(LightmappedGlb, WhatCannotBeWrittenIsOneErrorAndNoFile) {
  ScratchDir dir;
  test::writeFile(dir.path("scene.glb"), twoNodeScene());
  LightmappedAsset noUv = assetOf(dir.path("scene.glb"));
  noUv.parts.cornerTexcoords.clear();
  LightmappedAsset nan = assetOf(dir.path("scene.glb"));
  nan.emissiveStrength = std::nan("");
  LightmappedAsset badExtras = assetOf(dir.path("scene.glb"));
  badExtras.extrasJson = "{";
  const std::string out = dir.path("out.glb");
  test::expectError([&] { writeLightmappedGlb(out, noUv); }, out,
                    "no texture coordinate per triangle corner");
  test::expectError([&] { writeLightmappedGlb(out, nan); }, out, "empty or not finite");
  test::expectError([&] { writeLightmappedGlb(out, badExtras); }, out, "cannot encode");
  EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace
}  // namespace sss
