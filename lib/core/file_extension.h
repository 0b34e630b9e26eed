// The extension that picks a file's format: lower case, without the dot, "" when the last path
// component has none ("a/Mesh.PLY" -> "ply", "a.d/mesh" -> "").
#pragma once

#include <cctype>
#include <string>

namespace sss {

inline std::string lowerExtension(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  const std::size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot + 1);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

}  // namespace sss
