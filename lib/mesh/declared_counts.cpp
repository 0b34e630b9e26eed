#include "mesh/declared_counts.h"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

#include "core/file_extension.h"

namespace sss {
namespace {

constexpr std::size_t kHeadBytes = 64 * 1024;

// Bytes of a binary PLY scalar type (1 for a name this reader does not know: a lower bound).
std::uint64_t plyTypeBytes(const std::string& type) {
  for (const char* t : {"short", "ushort", "int16", "uint16"}) {
    if (type == t) return 2;
  }
  for (const char* t : {"int", "uint", "float", "int32", "uint32", "float32"}) {
    if (type == t) return 4;
  }
  return type == "double" || type == "float64" ? 8 : 1;
}

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::uint64_t minRecordBytes = 0;  // faces with 3 corners; ASCII: 2 bytes per number
};

// The PLY header's counts, when the file is at least as long as the smallest body they allow.
DeclaredMeshCounts plyCounts(const std::string& head, std::uint64_t fileSize) {
  std::istringstream in(head);
  std::vector<PlyElement> elements;
  bool binary = false;
  for (std::string line; std::getline(in, line);) {
    std::istringstream words(line);
    std::string word, type;
    words >> word;
    if (word == "format") {
      words >> type;
      binary = type != "ascii";
    } else if (word == "element") {
      PlyElement e;
      if (!(words >> e.name >> e.count) || e.count > fileSize) return {};
      elements.push_back(e);
    } else if (word == "property" && !elements.empty()) {
      PlyElement& e = elements.back();
      const std::uint64_t corners = e.name == "face" ? 3 : 0;
      if (words >> type && type == "list") {
        std::string countType, itemType;
        words >> countType >> itemType;
        e.minRecordBytes +=
            binary ? plyTypeBytes(countType) + corners * plyTypeBytes(itemType) : 2 * (1 + corners);
      } else {
        e.minRecordBytes += binary ? plyTypeBytes(type) : 2;
      }
    } else if (word == "end_header") {
      DeclaredMeshCounts counts;
      std::uint64_t body = static_cast<std::uint64_t>(in.tellg());
      for (const PlyElement& e : elements) {
        body += e.count * std::max<std::uint64_t>(e.minRecordBytes, 1);
        if (e.name == "vertex") counts.vertices = e.count;
        if (e.name == "face") counts.faces = e.count;
      }
      counts.known = body <= fileSize;
      return counts;
    }
  }
  return {};  // no end_header in the first 64 KiB
}

// ASCII OFF: "[C|N|ST|4|n]OFF" then "V F E" (comments '#'); at least "0 0 0\n" per vertex and
// "3 0 1 2\n" per face.
DeclaredMeshCounts offCounts(const std::string& head, std::uint64_t fileSize) {
  std::istringstream in(head);
  std::vector<std::string> words;
  for (std::string line; words.size() < 4 && std::getline(in, line);) {
    std::istringstream w(line.substr(0, line.find('#')));
    for (std::string word; words.size() < 4 && w >> word;) words.push_back(word);
  }
  if (words.size() < 3 || words[0].size() < 3 ||
      words[0].compare(words[0].size() - 3, 3, "OFF") != 0 || words[1] == "BINARY") {
    return {};
  }
  DeclaredMeshCounts counts;
  try {
    counts.vertices = std::stoull(words[1]);
    counts.faces = std::stoull(words[2]);
  } catch (const std::exception&) {
    return {};
  }
  counts.known = counts.vertices <= fileSize && counts.faces <= fileSize &&
                 6 * counts.vertices + 8 * counts.faces <= fileSize;
  return counts;
}

// Binary STL: an 80-byte header, a 32-bit triangle count, 50 bytes per triangle.
DeclaredMeshCounts stlCounts(const std::string& head, std::uint64_t fileSize) {
  if (head.size() < 84) return {};
  std::uint32_t n = 0;
  std::memcpy(&n, head.data() + 80, 4);
  if (84 + 50 * std::uint64_t{n} != fileSize) return {};  // ASCII STL, or a broken one
  DeclaredMeshCounts counts;
  counts.known = true;
  counts.faces = n;  // vertices: unknown until shared corners are merged
  return counts;
}

}  // namespace

DeclaredMeshCounts declaredMeshCounts(const std::string& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) return {};
  const std::streamoff size = in.tellg();
  if (size <= 0) return {};
  in.seekg(0);
  std::string head(std::min<std::size_t>(kHeadBytes, static_cast<std::size_t>(size)), '\0');
  if (!in.read(head.data(), static_cast<std::streamsize>(head.size()))) return {};
  const std::string ext = lowerExtension(path);
  const auto fileSize = static_cast<std::uint64_t>(size);
  if (ext == "ply") return plyCounts(head, fileSize);
  if (ext == "off") return offCounts(head, fileSize);
  if (ext == "stl") return stlCounts(head, fileSize);
  return {};
}

}  // namespace sss
