// sss-bake --texture: the UV lightmap a bake fills (texture_stage.h).
#pragma once

namespace sss {

struct TextureSettings {
  int size = 0;     // texels a side; 0: no texture (a per-vertex bake)
  int padding = 4;  // texels of gutter around each chart
  // The refined mesh's longest edge, in texels: at 2, about one vertex a texel (longest-edge
  // bisection leaves edges of 0.5-1x the longest; tests/bench/results/texture/sphere.csv).
  double edgeTexels = 2.0;
};

// Throws Error naming the option: size 0 or in [16, 8192], padding in [0, 64].
void checkTextureSettings(const TextureSettings& settings);

}  // namespace sss
