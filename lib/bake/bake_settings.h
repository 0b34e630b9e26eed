// What one bake is asked to do: the inputs (mesh, environment, material, units) and the choices
// (visibility, transport method, profile, energy model, tolerance), each choice an enum with one
// name table used for parsing, printing and --help.
#pragma once

#include <cstdint>
#include <string>

#include "bake/material_map.h"
#include "bake/texture_settings.h"
#include "core/enum_names.h"
#include "core/run_context.h"
#include "envmap/orientation.h"
#include "material/material.h"
#include "transport/far_field.h"
#include "transport/finite_object_energy.h"
#include "transport/unscattered_light.h"

namespace sss {

// E per vertex: the irradiance cubemap looked up at the vertex normal (no shadows), or Embree
// visibility rays against the mesh itself (lib/lighting/visibility.h).
enum class VisibilityMode { None, Rays };
inline constexpr EnumNames<VisibilityMode, 2> kVisibilityModeNames{
    "visibility", {{{VisibilityMode::None, "none"}, {VisibilityMode::Rays, "rays"}}}};

// B per vertex: a diffusion sum of Li & Guo Eq. 7 (lib/diffusion/diffusion.h; Auto picks the
// cheapest that meets the tolerance) or the volumetric Monte Carlo reference (lib/pathtrace).
enum class BakeMethod { Auto, Exact, Gauss, Incremental, Hierarchical, PathTrace };
inline constexpr EnumNames<BakeMethod, 6> kBakeMethodNames{
    "method",
    {{{BakeMethod::Auto, "auto"},
      {BakeMethod::Exact, "exact"},
      {BakeMethod::Gauss, "gauss"},
      {BakeMethod::Incremental, "incremental"},
      {BakeMethod::Hierarchical, "hierarchical"},
      {BakeMethod::PathTrace, "pathtrace"}}}};
// The diffusion method of a method other than PathTrace.
DiffusionMethod diffusionMethodOf(BakeMethod method);
// Its inverse: the method that runs `method` (Auto for Auto).
BakeMethod bakeMethodOf(DiffusionMethod method);

// The diffusion profile R_d (lib/material, makeProfile's names); Auto: autoProfileName() of the
// energy model in use.
enum class ProfileChoice { Auto, Dipole, Beam, Burley };
inline constexpr EnumNames<ProfileChoice, 4> kProfileChoiceNames{
    "profile",
    {{{ProfileChoice::Auto, "auto"},
      {ProfileChoice::Dipole, "dipole"},
      {ProfileChoice::Beam, "beam"},
      {ProfileChoice::Burley, "burley"}}}};

// How light entering from a direction counts (material/directional_albedo_weight.h): weighted by
// the half-space's directional albedo relative to diffuse light (directional), or every direction
// alike, as the diffusion profiles assume (diffuse). Only visibility rays can weight per
// direction; the cubemap lookup is diffuse.
enum class EntryModel { Directional, Diffuse };
inline constexpr EnumNames<EntryModel, 2> kEntryModelNames{
    "entry", {{{EntryModel::Directional, "directional"}, {EntryModel::Diffuse, "diffuse"}}}};

// --bounces auto: as many bounces as B needs to converge, none where a pilot finds them negligible.
inline constexpr int kAutoBounces = -1;

struct BakeSettings {
  std::string meshPath;
  std::string environment;  // an environment file, or "sky" / "sky:<spec>" (loadEnvironment)
  EnvironmentOrientation orientation;  // --env-convention, --env-rotate (envmap/orientation.h)
  Material material;
  // glTF material names -> materials (--material-map); parts it does not name take `material`.
  MaterialMap materialMap;
  // How parts of different materials share their light (material_parts.h).
  MaterialRule materialRule = MaterialRule::Border;
  // Millimetres per mesh unit (> 0), unless sizeMm > 0; 0: the unit the file fixes (glTF's
  // metres), an error for formats without one.
  double mmPerUnit = 0.0;
  double sizeMm = 0.0;  // > 0: scale so that the longest bounding-box side is this long
  VisibilityMode visibility = VisibilityMode::Rays;
  int samples = 0;  // visibility rays per vertex (>= 2); 0: auto (chooseVisibilitySamples)
  RunContext run{.seed = 1, .threads = 0, .quiet = false};  // --seed, --threads, --quiet
  BakeMethod method = BakeMethod::Auto;
  ProfileChoice profile = ProfileChoice::Auto;          // unused by PathTrace
  EnergyModel energy = EnergyModel::Auto;               // unused by PathTrace
  EntryModel entry = EntryModel::Directional;           // unused by PathTrace
  FarFieldMode farField = FarFieldMode::Auto;           // far_field.h; unused by PathTrace
  UnscatteredMode unscattered = UnscatteredMode::Auto;  // unscattered_light.h
  // Relative RMS of B; ErrorBudget (error_budget.h) splits it between the estimates.
  double tolerance = 0.01;
  int walks = 256;  // PathTrace: random walks per vertex (>= 1)
  // Interreflection (interreflection.h): 0 none (a ray that meets the object is dark), N bounces,
  // kAutoBounces (the default) until the series' geometric tail is within the tolerance's share
  // (then added), none where the pilot finds the light the object sends itself below that share.
  // Diffusion methods only.
  int bounces = kAutoBounces;
  // Cosine rays per vertex for the gather (>= 1); 0: gatherRaysFor(tolerance).
  int interreflectionRays = 0;
  int environmentFaceSize = 0;  // 0: from the source resolution
  TextureSettings texture;      // --texture: a UV lightmap beside the per-vertex values
  // --relightable [ORDER]: the SH order of the stored transfer (bake/relight.h); -1: a plain bake.
  int relightOrder = -1;
};

// Everything that needs no file, so that a typo costs nothing: the material, the units, the
// counts and the tolerance. Throws Error naming the setting in the library's terms.
void validateBakeSettings(const BakeSettings& settings);
// The single checks it makes, for tools that check an option as it is parsed.
void checkTolerance(double tolerance);     // in (0, 1)
void checkVisibilitySamples(int samples);  // 0 (auto) or >= 2
void checkPathTracerWalks(int walks);      // >= 1
void checkBounces(int bounces);            // kAutoBounces or >= 0
void checkSizeMm(double sizeMm);           // finite, > 0
void checkRelightOrder(int order);         // -1 (off) or 0..kMaxRelightOrder
inline constexpr int kMaxRelightOrder = 8;

// The gather's rays per vertex when the settings leave them to the tolerance: 64 at 1 %, and as
// the gather's noise falls as 1 / sqrt(rays), 64 (0.01 / tolerance)^2 elsewhere, rounded to a
// power of two in [8, 256] (its stratified sets): the noise a fixed share of the tolerance
// (0.45 of it on dragon_res2 at 1 %, the JSON's interreflection.gather_noise).
int gatherRaysFor(double tolerance);
// settings.interreflectionRays, or gatherRaysFor(settings.tolerance) where it is 0.
int gatherRaysOf(const BakeSettings& settings);
// The gather's rays beside the visibility's cosine set of `visibilityCosineRays` per vertex (0:
// none kept): where the settings leave them to the tolerance, that set alone when it is as many
// as gatherRaysFor's rounding accepts (from 1 / sqrt 2 of the unrounded count up to the rounded
// one), so that the gather traces no ray of its own; else gatherRaysOf.
int gatherRaysWith(const BakeSettings& settings, int visibilityCosineRays);

}  // namespace sss
