#include "bake/material_map.h"

#include <algorithm>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/file_extension.h"
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

MaterialMap parseJsonMap(const std::string& path) {
  checkInputFile(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open the material map");
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    fail(path, std::string("material map: ") + e.what());
  }
  if (!json.is_object()) fail(path, "material map: not a JSON object of names to presets");
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

Material materialForParts(const std::string& path, const MaterialMap& map, const MeshParts& parts,
                          const Material& fallback) {
  if (map.empty()) return fallback;
  const std::vector<std::string> keys = parts.materials();
  for (const auto& [key, material] : map.entries) {
    if (std::find(keys.begin(), keys.end(), key) == keys.end()) {
      fail(path, "--material-map names the material '" + key + "', which no part of the mesh has" +
                     (keys.empty() ? " (it has no parts: only glTF files do)" : ""));
    }
  }
  const auto materialOf = [&](const std::string& key) -> const Material& {
    for (const auto& [name, material] : map.entries)
      if (name == key) return material;
    return fallback;
  };
  const Material& first = materialOf(keys.front());
  for (const std::string& key : keys) {
    const Material& m = materialOf(key);
    if (m.name != first.name) {
      fail(path, "the material map gives the parts different materials ('" + keys.front() + "' " +
                     first.name + ", '" + key + "' " + m.name +
                     "): a material per part is not yet supported; bake the parts separately");
    }
  }
  if (first.name == fallback.name) return fallback;  // with its --eta and --g
  Material chosen = first;
  chosen.g = fallback.g;
  return chosen;
}

}  // namespace sss
