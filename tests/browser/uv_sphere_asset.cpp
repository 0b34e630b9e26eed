// Writes the UV sphere of tests/support/uv_sphere.h as a GLB: the browser test's asset.
//   uv_sphere_asset OUT.glb SEGMENTS RINGS RADIUS_M
#include <cstdio>
#include <cstdlib>
#include <string>

#include "support/uv_sphere.h"

int main(int argc, char** argv) {
  if (argc != 5) {
    std::fprintf(stderr, "usage: uv_sphere_asset OUT.glb SEGMENTS RINGS RADIUS_M\n");
    return 2;
  }
  const std::string glb =
      sss::test::uvSphereGlb(std::atoi(argv[2]), std::atoi(argv[3]), std::strtof(argv[4], nullptr));
  std::FILE* out = std::fopen(argv[1], "wb");
  if (!out || std::fwrite(glb.data(), 1, glb.size(), out) != glb.size() || std::fclose(out) != 0) {
    std::fprintf(stderr, "uv_sphere_asset: error: cannot write %s\n", argv[1]);
    return 1;
  }
  return 0;
}
