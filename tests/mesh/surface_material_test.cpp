// A glTF's surface materials (mesh/gltf_materials.h) read and written back on the lightmapped GLB
// (mesh/lightmapped_glb.h): what the bake does not replace is kept (roughness on the coat and the
// base, normal and occlusion maps with their scale and strength, alpha, double-sidedness, the
// images' bytes and their samplers); what cannot be kept is named, not an error; malformed
// material JSON is one error naming the file. The written file passes the Khronos validator.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "image/image.h"
#include "mesh/glb_chunks.h"
#include "mesh/lightmapped_glb.h"
#include "mesh/load_mesh.h"
#include "support/glb_test.h"
#include "support/gltf_builder.h"
#include "support/uv_sphere.h"
#include "test_util.h"

namespace sss {
namespace {

using test::GltfBuilder;
using test::ScratchDir;
using Json = nlohmann::json;

// A w x h PNG of one colour.
std::string png(int w, int h, std::uint8_t value) {
  const std::vector<std::uint8_t> pixels(std::size_t(3 * w * h), value);
  return encodePng("test image",
                   {.width = w, .height = h, .srgb8 = pixels.data(), .attributes = {}});
}

const std::string kPngA = png(4, 4, 200), kPngB = png(2, 2, 40);

// Two spheres, "Skin" and "Teeth". Skin keeps everything; Teeth's roughness map is on TEXCOORD_1,
// its normal map has only a WebP source and its occlusion map's image is a GIF.
GltfBuilder twoMaterialScene() {
  GltfBuilder b;
  b.doc["images"] =
      Json::array({{{"bufferView", b.view(kPngA)}, {"mimeType", "image/png"}},
                   {{"uri", "data:image/png;base64," + GltfBuilder::base64(kPngB)}},
                   {{"bufferView", b.view("GIF89a\x01\x00\x01\x00")}, {"mimeType", "image/png"}}});
  b.doc["samplers"] =
      Json::array({{{"magFilter", 9728}, {"minFilter", 9986}, {"wrapS", 33648}, {"wrapT", 33071}}});
  b.doc["textures"] = Json::array({{{"source", 0}, {"sampler", 0}},
                                   {{"source", 1}},
                                   {{"extensions", {{"EXT_texture_webp", {{"source", 0}}}}}},
                                   {{"source", 2}}});
  b.doc["materials"] = Json::array(
      {{{"name", "Skin"},
        {"pbrMetallicRoughness",
         {{"baseColorFactor", {0.8, 0.6, 0.5, 0.9}},
          {"roughnessFactor", 0.35},
          {"metallicFactor", 0.0},
          {"baseColorTexture", {{"index", 0}}},
          {"metallicRoughnessTexture", {{"index", 1}}}}},
        {"normalTexture", {{"index", 0}, {"scale", 0.7}}},
        {"occlusionTexture", {{"index", 1}, {"strength", 0.5}}},
        {"alphaMode", "MASK"},
        {"alphaCutoff", 0.4},
        {"doubleSided", true},
        {"extensions", {{"KHR_materials_sheen", Json::object()}}}},
       {{"name", "Teeth"},
        {"pbrMetallicRoughness",
         {{"roughnessFactor", 0.6}, {"metallicRoughnessTexture", {{"index", 1}, {"texCoord", 1}}}}},
        {"normalTexture", {{"index", 2}}},
        {"occlusionTexture", {{"index", 3}}}}});
  GltfBuilder::Primitive skin = test::uvSpherePrimitive(b, 8, 4, 0.01f);
  GltfBuilder::Primitive teeth = test::uvSpherePrimitive(b, 8, 4, 0.005f);
  skin.material = 0;
  teeth.material = 1;
  const int a = b.node({{"name", "head"}, {"mesh", b.mesh({skin}, "head")}});
  const int t = b.node(
      {{"name", "teeth"}, {"mesh", b.mesh({teeth}, "teeth")}, {"translation", {0.05, 0, 0}}});
  b.scene({a, t});
  return b;
}

TEST(SurfaceMaterial, WhatTheBakeDoesNotReplaceIsReadAndWhatCannotBeKeptIsNamed) {
  ScratchDir dir;
  test::writeFile(dir.path("scene.glb"), twoMaterialScene().glb());
  MeshParts parts;
  loadMesh(dir.path("scene.glb"), nullptr, &parts);
  ASSERT_EQ(parts.parts.size(), 2u);
  EXPECT_EQ(parts.parts[0].materialIndex, 0);
  EXPECT_EQ(parts.parts[1].materialIndex, 1);
  const SurfaceMaterials& s = parts.surfaces;
  ASSERT_EQ(s.materials.size(), 2u);
  ASSERT_EQ(s.images.size(), 2u);  // the PNGs; not the GIF
  EXPECT_EQ(s.images[0].bytes, kPngA);
  EXPECT_EQ(s.images[1].bytes, kPngB);
  EXPECT_EQ(s.images[1].mimeType, "image/png");
  const SurfaceMaterial& skin = s.materials[0];
  EXPECT_EQ(skin.alpha, 0.9);
  EXPECT_EQ(skin.roughness, 0.35);
  ASSERT_TRUE(skin.baseColor && skin.roughnessMap && skin.normal && skin.occlusion);
  EXPECT_EQ(skin.baseColor->image, 0u);
  EXPECT_EQ(skin.baseColor->magFilter, 9728);
  EXPECT_EQ(skin.baseColor->minFilter, 9986);
  EXPECT_EQ(skin.baseColor->wrapS, kGltfMirroredRepeat);
  EXPECT_EQ(skin.baseColor->wrapT, kGltfClampToEdge);
  EXPECT_EQ(skin.roughnessMap->image, 1u);
  EXPECT_EQ(skin.roughnessMap->wrapS, kGltfRepeat);  // no sampler: repeat, filters unset
  EXPECT_EQ(skin.roughnessMap->magFilter, 0);
  EXPECT_EQ(skin.normal->scale, 0.7);
  EXPECT_EQ(skin.occlusion->scale, 0.5);
  EXPECT_EQ(skin.alphaMode, "MASK");
  EXPECT_EQ(skin.alphaCutoff, 0.4);
  EXPECT_TRUE(skin.doubleSided);
  ASSERT_EQ(skin.dropped.size(), 1u);
  EXPECT_NE(skin.dropped[0].find("KHR_materials_sheen"), std::string::npos);
  const SurfaceMaterial& teeth = s.materials[1];
  EXPECT_EQ(teeth.roughness, 0.6);
  EXPECT_EQ(teeth.alphaMode, "OPAQUE");
  EXPECT_FALSE(teeth.roughnessMap || teeth.normal || teeth.occlusion);
  ASSERT_EQ(teeth.dropped.size(), 3u);
  EXPECT_NE(teeth.dropped[0].find("TEXCOORD_1"), std::string::npos) << teeth.dropped[0];
  EXPECT_NE(teeth.dropped[1].find("no PNG or JPEG source"), std::string::npos) << teeth.dropped[1];
  EXPECT_NE(teeth.dropped[2].find("not a PNG or JPEG"), std::string::npos) << teeth.dropped[2];
}

LightmappedAsset surfaceAssetOf(const std::string& path) {
  LightmappedAsset a;
  a.mesh = loadMesh(path, nullptr, &a.parts);
  a.mmPerUnit = a.parts.mmPerUnit;
  a.emissivePng = png(8, 8, 128);
  a.emissiveStrength = 2.0;
  a.medium = {"skin1", {0.032, 0.17, 0.48}, {0.74, 0.88, 1.01}};
  a.eta = 1.4;
  a.thicknessM = 0.01;
  a.extrasJson = R"({"format": 1})";
  return a;
}

// The bytes of image `i` of a written GLB.
std::string imageBytes(const GlbChunks& chunks, const Json& doc, std::size_t i) {
  const Json& view = doc["bufferViews"][doc["images"][i]["bufferView"].get<std::size_t>()];
  return chunks.bin.substr(view["byteOffset"].get<std::size_t>(),
                           view["byteLength"].get<std::size_t>());
}

// A float accessor of a written GLB, `components` per element.
std::vector<float> floats(const GlbChunks& chunks, const Json& doc, std::size_t accessor,
                          int components) {
  const Json& a = doc["accessors"][accessor];
  const Json& view = doc["bufferViews"][a["bufferView"].get<std::size_t>()];
  std::vector<float> out(a["count"].get<std::size_t>() * std::size_t(components));
  std::memcpy(out.data(), chunks.bin.data() + view["byteOffset"].get<std::size_t>(),
              out.size() * 4);
  return out;
}

// The normal-mapped primitive's TANGENT against each triangle's own texture-space derivatives:
// T along +u and cross(N, T) W along -v (the normal map's +Y is up in the image), on every
// triangle with texture-space area. Returns the triangles checked.
int expectTangentsFollowTheTexcoords(const GlbChunks& chunks, const Json& doc,
                                     const Json& primitive) {
  const Json& at = primitive["attributes"];
  const std::vector<float> p = floats(chunks, doc, at["POSITION"], 3),
                           n = floats(chunks, doc, at["NORMAL"], 3),
                           uv = floats(chunks, doc, at["TEXCOORD_0"], 2),
                           t = floats(chunks, doc, at["TANGENT"], 4);
  const Json& ia = doc["accessors"][primitive["indices"].get<std::size_t>()];
  std::vector<std::uint32_t> idx(ia["count"].get<std::size_t>());
  const Json& iv = doc["bufferViews"][ia["bufferView"].get<std::size_t>()];
  std::memcpy(idx.data(), chunks.bin.data() + iv["byteOffset"].get<std::size_t>(), idx.size() * 4);
  const auto vec3 = [](const std::vector<float>& v, std::uint32_t i) {
    return glm::dvec3(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
  };
  int checked = 0;
  for (std::size_t k = 0; k + 2 < idx.size(); k += 3) {
    const std::uint32_t a = idx[k], b = idx[k + 1], c = idx[k + 2];
    const glm::dvec3 e1 = vec3(p, b) - vec3(p, a), e2 = vec3(p, c) - vec3(p, a);
    const glm::dvec2 s1(uv[2 * b] - uv[2 * a], uv[2 * b + 1] - uv[2 * a + 1]);
    const glm::dvec2 s2(uv[2 * c] - uv[2 * a], uv[2 * c + 1] - uv[2 * a + 1]);
    const double det = s1.x * s2.y - s2.x * s1.y;
    if (std::abs(det) < 1e-9) continue;
    const glm::dvec3 dpdu = (e1 * s2.y - e2 * s1.y) / det, dpdv = (e2 * s1.x - e1 * s2.x) / det;
    for (const std::uint32_t v : {a, b, c}) {
      const glm::dvec3 tangent(t[4 * v], t[4 * v + 1], t[4 * v + 2]);
      EXPECT_NEAR(glm::length(tangent), 1.0, 1e-5);
      EXPECT_NEAR(glm::dot(tangent, vec3(n, v)), 0.0, 1e-5);
      EXPECT_GT(glm::dot(tangent, dpdu), 0.0);
      EXPECT_GT(glm::dot(glm::cross(vec3(n, v), tangent) * double(t[4 * v + 3]), -dpdv), 0.0);
    }
    ++checked;
  }
  return checked;
}

TEST(SurfaceMaterial, TheLightmappedGlbKeepsEachPartsSurfaceAndPassesTheValidator) {
  ScratchDir dir;
  test::writeFile(dir.path("scene.glb"), twoMaterialScene().glb());
  const LightmappedAsset in = surfaceAssetOf(dir.path("scene.glb"));
  const std::string out = dir.path("out.glb");
  writeLightmappedGlb(out, in);
  const GlbChunks chunks = readGlbChunks(out);
  const Json doc = Json::parse(chunks.json);
  ASSERT_EQ(doc["materials"].size(), 2u);
  EXPECT_EQ(doc["meshes"][0]["primitives"][0]["material"], 0);
  EXPECT_EQ(doc["meshes"][1]["primitives"][0]["material"], 1);
  // The lightmap stays texture, image and sampler 0; the kept PNGs follow, once each.
  ASSERT_EQ(doc["images"].size(), 3u);
  EXPECT_EQ(imageBytes(chunks, doc, 0), in.emissivePng);
  EXPECT_EQ(imageBytes(chunks, doc, 1), kPngA);
  EXPECT_EQ(imageBytes(chunks, doc, 2), kPngB);
  const Json& skin = doc["materials"][0];
  EXPECT_EQ(skin["name"], "Skin (baked translucency: emission, coat)");
  const Json& pbr = skin["pbrMetallicRoughness"];
  EXPECT_EQ(pbr["baseColorFactor"], Json({0.0, 0.0, 0.0, 0.9}));
  EXPECT_EQ(pbr["roughnessFactor"], 0.35);
  EXPECT_EQ(pbr["metallicFactor"], 0.0);
  const Json& coat = skin["extensions"]["KHR_materials_clearcoat"];
  EXPECT_EQ(coat["clearcoatRoughnessFactor"], 0.35);
  EXPECT_EQ(coat["clearcoatRoughnessTexture"], pbr["metallicRoughnessTexture"]);
  EXPECT_EQ(coat["clearcoatNormalTexture"], skin["normalTexture"]);
  EXPECT_EQ(skin["normalTexture"]["scale"], 0.7);
  EXPECT_EQ(skin["occlusionTexture"]["strength"], 0.5);
  EXPECT_EQ(skin["alphaMode"], "MASK");
  EXPECT_EQ(skin["alphaCutoff"], 0.4);
  EXPECT_EQ(skin["doubleSided"], true);
  EXPECT_EQ(skin["emissiveTexture"]["index"], 0);
  // Each kept texture points at its own image with the source's sampler.
  const Json& base = doc["textures"][pbr["baseColorTexture"]["index"].get<std::size_t>()];
  EXPECT_EQ(base["source"], 1);
  EXPECT_EQ(doc["samplers"][base["sampler"].get<std::size_t>()],
            Json({{"magFilter", 9728}, {"minFilter", 9986}, {"wrapS", 33648}, {"wrapT", 33071}}));
  const Json& rough = doc["textures"][pbr["metallicRoughnessTexture"]["index"].get<std::size_t>()];
  EXPECT_EQ(rough["source"], 2);
  const Json& teeth = doc["materials"][1];
  EXPECT_EQ(teeth["pbrMetallicRoughness"]["roughnessFactor"], 0.6);
  EXPECT_FALSE(teeth.contains("normalTexture") || teeth.contains("occlusionTexture") ||
               teeth["pbrMetallicRoughness"].contains("metallicRoughnessTexture"));
  // A normal map needs a tangent space: written where one is kept, and only there.
  EXPECT_GT(expectTangentsFollowTheTexcoords(chunks, doc, doc["meshes"][0]["primitives"][0]), 40);
  EXPECT_FALSE(doc["meshes"][1]["primitives"][0]["attributes"].contains("TANGENT"));
  // Double-sided: no volume (it bounds none), and no transmission kept for it.
  EXPECT_FALSE(skin["extensions"].contains("KHR_materials_volume"));
  EXPECT_TRUE(teeth["extensions"].contains("KHR_materials_volume"));
  const std::vector<std::string> notes = droppedSurfaceNotes(in);
  ASSERT_EQ(notes.size(), 4u);
  EXPECT_EQ(notes[0],
            "material 'Skin': KHR_materials_sheen (the bake writes its own material "
            "extensions) not kept");
  test::expectValidGltf(out);
}

TEST(SurfaceMaterial, AMalformedMaterialIsOneErrorNamingTheFile) {
  ScratchDir dir;
  const std::string path = dir.path("bad.glb");
  const auto expectRefused = [&](const auto& edit, const std::string& part) {
    GltfBuilder b = twoMaterialScene();
    edit(b.doc);
    test::writeFile(path, b.glb());
    test::expectError([&] { loadMesh(path); }, path, part);
  };
  expectRefused([](Json& d) { d["materials"][0]["pbrMetallicRoughness"]["roughnessFactor"] = 2; },
                "roughnessFactor");
  expectRefused([](Json& d) { d["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"] = {1}; },
                "baseColorFactor");
  expectRefused([](Json& d) { d["materials"][0]["alphaMode"] = "CUTOUT"; }, "alphaMode");
  expectRefused([](Json& d) { d["materials"][0]["doubleSided"] = 1; }, "doubleSided");
  expectRefused([](Json& d) { d["materials"][0]["normalTexture"]["index"] = 9; }, "textures");
  expectRefused([](Json& d) { d["materials"][0]["occlusionTexture"]["strength"] = -1; },
                "strength");
  expectRefused([](Json& d) { d["samplers"][0]["wrapS"] = 7; }, "wrapS");
  expectRefused([](Json& d) { d["textures"][0]["source"] = 12; }, "images");
}

TEST(SurfaceMaterial, AnImageThatCannotBeReadIsDroppedNotFatal) {
  ScratchDir dir;
  GltfBuilder b = twoMaterialScene();
  b.doc["images"][1] = {{"uri", "missing.png"}};  // Skin's roughness and occlusion map
  b.doc["images"][0]["bufferView"] = 99;          // out of range: the image cannot be read
  test::writeFile(dir.path("scene.glb"), b.glb());
  MeshParts parts;
  loadMesh(dir.path("scene.glb"), nullptr, &parts);
  const SurfaceMaterial& skin = parts.surfaces.materials.at(0);
  EXPECT_TRUE(parts.surfaces.images.empty());
  EXPECT_FALSE(skin.baseColor || skin.roughnessMap || skin.normal || skin.occlusion);
  ASSERT_EQ(skin.dropped.size(), 5u);  // four textures and the extension
  EXPECT_NE(skin.dropped[0].find("image 0 cannot be read"), std::string::npos) << skin.dropped[0];
  EXPECT_NE(skin.dropped[1].find("missing.png"), std::string::npos) << skin.dropped[1];
}

}  // namespace
}  // namespace sss
