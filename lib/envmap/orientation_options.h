// --env-rotate and --env-convention, the same on every tool that reads an environment
// (envmap/orientation.h), and the choice of -e ENV or --sky [SPEC] of the tools that take either.
// Header-only with CLI11: included by tools/ only, like core/cli.h.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "core/cli.h"
#include "envmap/orientation.h"

namespace sss::cli {

inline void addOrientationOptions(CLI::App& app, EnvironmentOrientation& orientation) {
  app.add_option("--env-rotate", orientation.rotateDeg,
                 "Turn the environment about +Y by DEG degrees, counter-clockwise seen from above "
                 "(the sun of --sky turns with it)")
      ->check(finiteIn())
      ->type_name("DEG")
      ->capture_default_str();
  addEnumOption(app, "--env-convention", orientation.convention, kEquirectConventionNames,
                "The equirect image's convention: sss (centre towards -Z), blender and threejs "
                "(centre towards +X), filament (cmgen, centre towards +Z)");
}

// -e ENV or --sky [SPEC], exactly one of them (sss-bake, sss-relight; sss-relight's -e may be
// given several times); after parsing, sources() are what loadEnvironment reads: the files, or
// "sky" / "sky:<spec>".
struct EnvironmentChoice {
  std::vector<std::string> files;
  std::string skySpec;
  CLI::Option* sky = nullptr;
  std::vector<std::string> sources() const {
    if (sky == nullptr || sky->count() == 0) return files;
    return {skySpec.empty() ? "sky" : "sky:" + skySpec};
  }
  std::string source() const { return sources().front(); }
};

// several: -e may be repeated (-e a.exr -e b.exr), else once.
inline void addEnvironmentChoice(CLI::App& app, EnvironmentChoice& choice, bool several = false) {
  auto* group = app.add_option_group("environment", "Exactly one: -e ENV or --sky");
  group
      ->add_option("-e,--env", choice.files,
                   several ? "Environment: equirect, cross or cubemap-stack image; repeat -e for "
                             "several (with -o DIR/)"
                           : "Environment: equirect, cross or cubemap-stack image")
      ->expected(1)
      ->multi_option_policy(several ? CLI::MultiOptionPolicy::TakeAll
                                    : CLI::MultiOptionPolicy::Throw);
  choice.sky = group
                   ->add_option("--sky", choice.skySpec,
                                "Procedural sun and sky instead of -e, optional spec "
                                "(elevation=45,azimuth=30,turbidity=3)")
                   ->expected(0, 1)
                   ->default_str("");
  group->require_option(1);
}

}  // namespace sss::cli
