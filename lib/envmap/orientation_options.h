// --env-rotate and --env-convention, the same on every tool that reads an environment
// (envmap/orientation.h). Header-only with CLI11: included by tools/ only, like core/cli.h.
#pragma once

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

}  // namespace sss::cli
