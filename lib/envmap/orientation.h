// How an environment is turned before use: the equirect convention its image was made for and a
// rotation about +Y (`--env-convention`, `--env-rotate`, every tool that reads an environment).
//
// An equirect convention is the world direction each pixel shows. Ours (equirect.h): the image
// centre looks towards -Z, u = 0.75 towards +X. The others, in our Y-up frame, differ from ours by
// a turn about +Y (the top row is straight up and none is mirrored seen from inside):
//   blender   Cycles' equirectangular_to_direction (intern/cycles/kernel/camera/projection.h,
//             range (-2 pi, pi, -pi, pi)): u = 0.5 - atan2(y, x) / 2 pi in Blender's Z-up frame,
//             centre towards +X, u = 0.75 towards -Y; through glTF's axes (Blender -Y = our +Z)
//             the centre looks towards +X and u = 0.75 towards +Z.
//   threejs   three.js equirectUv (src/renderers/shaders/ShaderChunk/common.glsl.js):
//             u = atan(z, x) / 2 pi + 0.5, v = asin(y) / pi + 0.5 (flipY: v = 1 is the top row):
//             centre towards +X, u = 0.75 towards +Z: the same as blender.
//   filament  cmgen (tools/cmgen, libs/ibl CubemapUtils::equirectangularToCubemap: u from
//             atan2(x, z), centre towards +Z), then mirrored in x by default (mirrorCubemap,
//             "--no-mirror: skip mirroring"): centre towards +Z, u = 0.75 towards -X.
// So a pixel's direction is R_y(conventionTurn) applied to ours: blender and threejs -90 degrees,
// filament 180 degrees.
//
// --env-rotate DEG turns the environment by DEG degrees about +Y, counter-clockwise seen from
// above (right-handed, as a positive rotation of a mesh about +Y): what was towards -Z is then
// towards -X for DEG = 90. The light arriving along a world direction w is the source's along
// R_y(-DEG) w, so turning the environment by DEG is the same as turning the mesh (and camera) by
// -DEG. It is applied where directions are mapped (exact for an equirect or the sky's sun, a
// bilinear resampling only for a cube or cross source).
#pragma once

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include "core/enum_names.h"

namespace sss {

enum class EquirectConvention { Sss, Blender, Threejs, Filament };
inline constexpr EnumNames<EquirectConvention, 4> kEquirectConventionNames{
    "equirect convention",
    {{{EquirectConvention::Sss, "sss"},
      {EquirectConvention::Blender, "blender"},
      {EquirectConvention::Threejs, "threejs"},
      {EquirectConvention::Filament, "filament"}}}};

// The turn about +Y from our equirect convention to `convention` (degrees), see above.
double conventionTurnDeg(EquirectConvention convention);

struct EnvironmentOrientation {
  EquirectConvention convention = EquirectConvention::Sss;  // equirect sources only
  double rotateDeg = 0.0;                                   // about +Y, counter-clockwise
};

// R_y(deg): the right-handed rotation about +Y (+X towards -Z for 90 degrees).
glm::mat3 rotationAboutY(double deg);

// The matrix taking a world direction to the direction in the source's own frame that shows it
// (for an equirect, the direction our equirectCoord maps to the pixel): R_y(-(turn + rotate)).
// `equirect` says whether the convention applies.
glm::mat3 sourceFromWorld(const EnvironmentOrientation& orientation, bool equirect);
// Whether sourceFromWorld is the identity (then nothing is resampled: results stay bit-exact).
bool isIdentity(const EnvironmentOrientation& orientation, bool equirect);

// Throws Error unless the angle is finite.
void checkEnvRotate(double deg);

}  // namespace sss
