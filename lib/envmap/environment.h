// An environment, from any source the tools accept, as a radiance cubemap.
#pragma once

#include <string>

#include <glm/vec3.hpp>

#include "core/enum_names.h"
#include "envmap/cubemap.h"
#include "envmap/orientation.h"
#include "image/image.h"

namespace sss {

enum class EnvironmentLayout { Equirect, Cross, CubemapStack };
inline constexpr EnumNames<EnvironmentLayout, 3> kEnvironmentLayoutNames{
    "environment layout",
    {{{EnvironmentLayout::Equirect, "equirect"},
      {EnvironmentLayout::Cross, "cross"},
      {EnvironmentLayout::CubemapStack, "cubemap-stack"}}}};

// Layout from the image shape: 2:1 equirect, 4:3 or 3:4 cross, 1:6 our cubemap stack. Anything
// else throws Error naming the file and its size.
EnvironmentLayout detectLayout(const std::string& path, int width, int height);

// Resampling an image into a cubemap of `faceSize` (0: keep about the source's resolution: W / 4
// for an equirect). Equirect sources are area-averaged by supersampling (k x k bilinear lookups
// per texel, denser than the source texels), which keeps the flux (tests/envmap check it).
// threads <= 0: all cores (the result does not depend on it). `orientation` turns the environment
// (envmap/orientation.h): an equirect is looked up along the turned direction (exact), a cube or
// cross source is resampled bilinearly; the identity changes nothing.
Cubemap cubemapFromImage(const ImageRgb& image, EnvironmentLayout layout, int faceSize,
                         int threads = 0, const EnvironmentOrientation& orientation = {});

// The unfolded horizontal cross (4:3): middle row -X, +Z, +X, -Z as GL faces are laid out; +Y
// above and -Y below the +Z face. Used for previews and read back by cubemapFromImage.
ImageRgb cubemapToCross(const Cubemap& cubemap);
// Stacked faces N x 6N, the on-disk cubemap layout.
ImageRgb cubemapToStack(const Cubemap& cubemap);

// Procedural sun + sky (`--sky`): a sky dome with a sun disc, ground below the horizon.
struct SkyParameters {
  glm::vec3 sunDirection = glm::vec3(0.3f, 0.6f, -0.74f);  // towards the sun; normalized on use
  float turbidity = 3.0f;                                  // haze: 2 (clear) to 10 (hazy)
  float sunAngularRadiusDeg = 0.27f;
  float sunIntensity = 1.0f;  // scales the sun's radiance
  glm::vec3 groundAlbedo = glm::vec3(0.3f);
};
// Parses "elevation=45,azimuth=30,turbidity=3" style specs (keys elevation, azimuth, turbidity,
// sun, radius, ground); throws Error naming the key and its range.
SkyParameters parseSkySpec(const std::string& spec);
Cubemap makeSky(const SkyParameters& sky, int faceSize, int threads = 0);
// The sky turned by --env-rotate: the sun turns with it (the Preetham sky depends only on the
// angles to the sun and the zenith, so this turns the whole sky exactly). No convention applies.
SkyParameters rotatedSky(SkyParameters sky, const EnvironmentOrientation& orientation);

// The largest cubemap face a tool may ask for (--size, --radiance-size, --env-size): twice the
// face of a 16K equirect (16384 / 4), the largest common HDRI; a float RGB cubemap of 8192^2
// faces takes 4.5 GiB. Throws Error unless 1 <= faceSize <= kMaxFaceSize.
inline constexpr int kMaxFaceSize = 8192;
void checkFaceSize(int faceSize);

struct EnvironmentOptions {
  ImageReadOptions read;
  int faceSize = 0;                      // 0: chosen from the source resolution
  int threads = 0;                       // <= 0: all cores
  EnvironmentOrientation orientation{};  // --env-convention, --env-rotate
};
// Reads an environment file (equirect, cross or our stack) into a radiance cubemap; the special
// name "sky" or "sky:<spec>" gives makeSky instead. Throws Error naming the file (or the sky
// source).
Cubemap loadEnvironment(const std::string& source, const EnvironmentOptions& options = {});

}  // namespace sss
