#include "bake/bake_settings.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "material/diffusion_profile.h"
#include "material/profile_factory.h"
#include "mesh/units.h"

namespace sss {

DiffusionMethod diffusionMethodOf(BakeMethod method) {
  switch (method) {
    case BakeMethod::Exact:
      return DiffusionMethod::Exact;
    case BakeMethod::Gauss:
      return DiffusionMethod::Gauss;
    case BakeMethod::Incremental:
      return DiffusionMethod::Incremental;
    case BakeMethod::Hierarchical:
      return DiffusionMethod::Hierarchical;
    case BakeMethod::Auto:
    case BakeMethod::PathTrace:
      break;
  }
  return DiffusionMethod::Auto;
}

BakeMethod bakeMethodOf(DiffusionMethod method) {
  // Every diffusion method is a bake method of the same name.
  return kBakeMethodNames.parse(kDiffusionMethodNames.name(method));
}

void checkTolerance(double tolerance) {
  if (!(tolerance > 0.0 && tolerance < 1.0)) {
    fail("", "the tolerance must be in (0, 1), e.g. 0.01 for 1%");
  }
}

void checkVisibilitySamples(int samples) {
  if (samples != 0 && samples < 2) fail("", "visibility rays per vertex must be at least 2");
}

void checkBounces(int bounces) {
  if (bounces < kAutoBounces) fail("", "bounces must be auto or a count >= 0");
}

void checkPathTracerWalks(int walks) {
  if (walks < 1) fail("", "the path tracer needs at least 1 walk per vertex");
}

void checkSizeMm(double sizeMm) {
  if (!(std::isfinite(sizeMm) && sizeMm > 0.0)) {
    fail("", "the mesh size must be a positive, finite length in mm");
  }
}

void checkRelightOrder(int order) {
  if (order < -1 || order > kMaxRelightOrder)
    throw Error("--relightable " + std::to_string(order) + ": the SH order must be in [0, " +
                std::to_string(kMaxRelightOrder) + "]");
}

void checkTextureSettings(const TextureSettings& s) {
  if (s.size != 0 && (s.size < 16 || s.size > 8192)) {
    throw Error("--texture " + std::to_string(s.size) + ": texels a side must be in [16, 8192]");
  }
  if (s.padding < 0 || s.padding > 64) {
    throw Error("--texture-padding " + std::to_string(s.padding) + ": must be in [0, 64] texels");
  }
  if (!(s.edgeTexels >= 0.25 && s.edgeTexels <= 16.0)) {
    throw Error("texture refinement: edge length " + std::to_string(s.edgeTexels) +
                " texels must be in [0.25, 16]");
  }
}

void validateBakeSettings(const BakeSettings& s) {
  validateMaterial(s.material, "material");
  if (s.profile != ProfileChoice::Auto) {
    makeProfile(kProfileChoiceNames.name(s.profile), s.material);  // validates the pair
  }
  if (s.sizeMm > 0.0) {
    checkSizeMm(s.sizeMm);
  } else if (s.mmPerUnit != 0.0) {  // 0: the file's own unit (prepare_mesh.h)
    checkMmPerUnit(s.mmPerUnit, "millimetres per mesh unit");
  }
  checkVisibilitySamples(s.samples);
  if (s.method == BakeMethod::PathTrace) checkPathTracerWalks(s.walks);
  checkBounces(s.bounces);
  if (s.interreflectionRays < 0) fail("", "interreflection needs at least 1 ray per vertex");
  checkTolerance(s.tolerance);
  checkTextureSettings(s.texture);
  checkRelightOrder(s.relightOrder);
  if (s.relightOrder >= 0 && s.method == BakeMethod::PathTrace)
    throw Error(
        "--relightable needs a diffusion method: the path tracer is not linear in a "
        "stored transfer");
  if (s.relightOrder >= 0 && s.texture.size > 0)
    throw Error(
        "--relightable with --texture: a relightable lightmap is not supported; bake the "
        "transfer per vertex");
}

namespace {

constexpr double kSqrt2 = 1.4142135623730951;

// The gather's rays a tolerance asks for before rounding: its noise falls as 1 / sqrt(rays).
double gatherRaysWanted(double tolerance) {
  return 64.0 * std::pow(0.01 / std::max(tolerance, 1e-6), 2.0);
}

}  // namespace

int gatherRaysFor(double tolerance) {
  const double rays = gatherRaysWanted(tolerance);
  int power = 8;
  while (power < 256 && power * kSqrt2 < rays) power *= 2;
  return power;
}

int gatherRaysOf(const BakeSettings& settings) {
  return settings.interreflectionRays > 0 ? settings.interreflectionRays
                                          : gatherRaysFor(settings.tolerance);
}

int gatherRaysWith(const BakeSettings& settings, int visibilityCosineRays) {
  const int rounded = gatherRaysOf(settings);
  if (settings.interreflectionRays > 0 || visibilityCosineRays < 1) return rounded;
  const bool asGood = visibilityCosineRays * kSqrt2 >= gatherRaysWanted(settings.tolerance);
  return asGood && visibilityCosineRays <= rounded ? visibilityCosineRays : rounded;
}

}  // namespace sss
