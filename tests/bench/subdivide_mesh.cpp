// subdivide_mesh IN OUT.ply N: splits every edge of IN (any mesh loadMesh reads) into N equal
// parts and every triangle into N^2 flat ones (shared edge vertices, so the result stays closed
// and consistently wound), written as a binary little-endian PLY. For the memory sweep
// (memory_sweep.sh): dragon_res2 (202K triangles) with N = 7 gives 9.9M triangles.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <unordered_map>
#include <vector>

#include <glm/vec3.hpp>

#include "core/atomic_output.h"
#include "core/error.h"
#include "core/tool.h"
#include "mesh/load_mesh.h"

namespace {

struct Subdivision {
  std::vector<glm::vec3> positions;
  std::vector<glm::uvec3> triangles;
};

// Edge (a, b) gets n - 1 new vertices, stored from min(a, b) to max(a, b); k in 1..n-1 counts
// from a.
class EdgeVertices {
 public:
  EdgeVertices(Subdivision& out, int n) : out_(out), n_(n) {}
  unsigned at(unsigned a, unsigned b, int k) {
    const unsigned lo = std::min(a, b), hi = std::max(a, b);
    const std::uint64_t key = (std::uint64_t{lo} << 32) | hi;
    auto [it, inserted] = first_.try_emplace(key, static_cast<unsigned>(out_.positions.size()));
    if (inserted) {
      const glm::vec3 p = out_.positions[lo], q = out_.positions[hi];
      for (int i = 1; i < n_; ++i) out_.positions.push_back(p + (q - p) * (float(i) / float(n_)));
    }
    return it->second + static_cast<unsigned>(a == lo ? k - 1 : n_ - k - 1);
  }

 private:
  Subdivision& out_;
  int n_;
  std::unordered_map<std::uint64_t, unsigned> first_;
};

Subdivision subdivide(const sss::TriangleMesh& mesh, int n) {
  Subdivision out;
  out.positions = mesh.positions;
  out.triangles.reserve(mesh.triangles.size() * n * n);
  EdgeVertices edges(out, n);
  std::vector<unsigned> grid((n + 1) * (n + 1));
  // Grid point (i, j), i + j <= n: v0 + i/n (v1 - v0) + j/n (v2 - v0).
  auto id = [&](int i, int j) -> unsigned& { return grid[i * (n + 1) + j]; };
  for (const glm::uvec3& t : mesh.triangles) {
    const glm::vec3 p0 = mesh.positions[t.x], e1 = mesh.positions[t.y] - p0,
                    e2 = mesh.positions[t.z] - p0;
    id(0, 0) = t.x, id(n, 0) = t.y, id(0, n) = t.z;
    for (int k = 1; k < n; ++k) {
      id(k, 0) = edges.at(t.x, t.y, k);
      id(0, k) = edges.at(t.x, t.z, k);
      id(n - k, k) = edges.at(t.y, t.z, k);
    }
    for (int i = 1; i < n; ++i) {
      for (int j = 1; i + j < n; ++j) {
        id(i, j) = static_cast<unsigned>(out.positions.size());
        out.positions.push_back(p0 + e1 * (float(i) / float(n)) + e2 * (float(j) / float(n)));
      }
    }
    for (int i = 0; i < n; ++i) {
      for (int j = 0; i + j < n; ++j) {
        out.triangles.push_back({id(i, j), id(i + 1, j), id(i, j + 1)});
        if (i + j < n - 1) out.triangles.push_back({id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
      }
    }
  }
  return out;
}

void writeBinaryPly(const std::string& path, const Subdivision& mesh) {
  sss::AtomicOutput output(path);
  {
    std::ofstream out(output.tempPath(), std::ios::binary);
    out << "ply\nformat binary_little_endian 1.0\nelement vertex " << mesh.positions.size()
        << "\nproperty float x\nproperty float y\nproperty float z\nelement face "
        << mesh.triangles.size() << "\nproperty list uchar int vertex_indices\nend_header\n";
    out.write(reinterpret_cast<const char*>(mesh.positions.data()),
              static_cast<std::streamsize>(mesh.positions.size() * sizeof(glm::vec3)));
    std::vector<char> faces(mesh.triangles.size() * 13);
    for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
      faces[13 * f] = 3;
      std::memcpy(&faces[13 * f + 1], &mesh.triangles[f], 12);
    }
    out.write(faces.data(), static_cast<std::streamsize>(faces.size()));
    if (!out.flush()) sss::fail(path, "cannot write");
  }
  output.commit();
}

}  // namespace

int main(int argc, char** argv) {
  return sss::runTool("subdivide_mesh", [&] {
    if (argc != 4 || std::atoi(argv[3]) < 1) {
      throw sss::UsageError("usage: subdivide_mesh IN OUT.ply N (N >= 1 parts per edge)");
    }
    const int n = std::atoi(argv[3]);
    const Subdivision s = subdivide(sss::loadMesh(argv[1]), n);
    writeBinaryPly(argv[2], s);
    std::printf("%zu vertices, %zu triangles\n", s.positions.size(), s.triangles.size());
    return 0;
  });
}
