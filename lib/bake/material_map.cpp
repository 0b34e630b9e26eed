#include "bake/material_map.h"

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/file_extension.h"
#include "core/format.h"
#include "core/paths.h"

namespace sss {
namespace {

void addEntry(MaterialMap& map, const std::string& name, const std::string& preset,
              const std::string& where) {
  for (const auto& [key, material] : map.entries) {
    if (key == name) fail(where, "names the material '" + name + "' twice");
  }
  try {
    map.entries.emplace_back(name, findMaterialPreset(preset));
  } catch (const Error& e) {
    fail(where, "'" + name + "': " + e.what());
  }
}

// A material map names a few parts; a larger file is not one (and is not parsed into memory).
constexpr std::uintmax_t kMaxMapBytes = 1 << 20;

MaterialMap parseJsonMap(const std::string& path) {
  checkInputFile(path);
  std::error_code error;
  const std::uintmax_t bytes = std::filesystem::file_size(path, error);
  if (!error && bytes > kMaxMapBytes)
    fail(path, "material map: " + std::to_string(bytes) + " bytes, more than a map's 1 MiB");
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open the material map");
  nlohmann::json json;
  // The object's names as parsed: JSON keeps the last of a repeated name, which would bake a part
  // with a material the file also contradicts.
  std::vector<std::string> names;
  std::string repeated;
  const auto seeNames = [&](int depth, nlohmann::json::parse_event_t event, nlohmann::json& value) {
    if (depth == 1 && event == nlohmann::json::parse_event_t::key && value.is_string()) {
      const std::string& name = value.get_ref<const std::string&>();
      if (std::find(names.begin(), names.end(), name) != names.end()) repeated = name;
      names.push_back(name);
    }
    return true;
  };
  try {
    json = nlohmann::json::parse(in, seeNames);
  } catch (const nlohmann::json::exception& e) {
    fail(path, std::string("material map: ") + e.what());
  }
  if (!json.is_object()) fail(path, "material map: not a JSON object of names to presets");
  if (!repeated.empty()) fail(path, "material map: names the material '" + repeated + "' twice");
  MaterialMap map;
  for (const auto& [name, preset] : json.items()) {
    if (!preset.is_string()) fail(path, "material map: '" + name + "' is not a preset name");
    addEntry(map, name, preset.get<std::string>(), path + ": material map");
  }
  return map;
}

}  // namespace

MaterialMap parseMaterialMap(const std::string& spec) {
  if (lowerExtension(spec) == "json") return parseJsonMap(spec);
  MaterialMap map;
  std::istringstream entries(spec);
  for (std::string entry; std::getline(entries, entry, ',');) {
    const std::size_t equals = entry.find('=');
    if (equals == std::string::npos || equals == 0 || equals + 1 == entry.size()) {
      fail("--material-map", "'" + entry + "' is not name=preset");
    }
    addEntry(map, entry.substr(0, equals), entry.substr(equals + 1), "--material-map");
  }
  if (map.empty()) fail("--material-map", "no name=preset entry");
  return map;
}

PartMaterials materialsForParts(const std::string& path, const MaterialMap& map,
                                const MeshParts& parts, const Material& fallback) {
  PartMaterials out;
  out.partMaterial.assign(parts.parts.size(), 0);
  if (map.empty()) {
    out.materials = {fallback};
    return out;
  }
  const std::vector<std::string> keys = parts.materials();
  for (const auto& [key, material] : map.entries) {
    if (std::find(keys.begin(), keys.end(), key) == keys.end()) {
      fail(path, "--material-map names the material '" + key + "', which no part of the mesh has" +
                     (keys.empty() ? " (it has no parts: only glTF files do)" : ""));
    }
  }
  // A preset the map names takes -m's g (--g); -m's own material keeps its --eta and --g.
  const auto materialOf = [&](const std::string& key) {
    for (const auto& [name, material] : map.entries) {
      if (name != key || material.name == fallback.name) continue;
      Material m = material;
      m.g = fallback.g;
      return m;
    }
    return fallback;
  };
  for (std::size_t p = 0; p < parts.parts.size(); ++p) {
    const Material m = materialOf(parts.parts[p].material);
    std::size_t k = 0;
    while (k < out.materials.size() && out.materials[k].name != m.name) ++k;
    if (k == out.materials.size()) out.materials.push_back(m);
    out.partMaterial[p] = std::uint32_t(k);
  }
  for (const Material& m : out.materials) {
    if (m.eta != out.materials.front().eta) {
      fail(path, "the material map gives the parts materials of different eta (" +
                     out.materials.front().name + " " + format("%g", out.materials.front().eta) +
                     ", " + m.name + " " + format("%g", m.eta) +
                     "): light crossing between them would refract, which the bake does not model");
    }
  }
  return out;
}

}  // namespace sss
