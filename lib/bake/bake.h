// The sss-bake pipeline: mesh + environment + material -> per-vertex transmitted irradiance E
// (Eq. 6, with or without the mesh's own shadows) and exitance B (Eq. 7, a diffusion method, or
// the Monte Carlo reference), ready for writeBakedPly.
//
// Stages, each timed: load and clean the mesh (lib/mesh), scale it to millimetres, load the
// environment as a radiance cubemap (lib/envmap), E per vertex (visibility "none": the irradiance
// cubemap of lib/irradiance computed with the material's eta, looked up at the vertex normal;
// "rays": visibility.h), then B (lib/bake/diffusion.h with a profile of lib/material, or
// lib/pathtrace). Every input is validated before the first expensive stage.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "material/material.h"
#include "mesh/baked_ply.h"

namespace sss {

enum class VisibilityMode { None, Rays };
// "none" or "rays"; throws Error otherwise.
VisibilityMode parseVisibilityMode(const std::string& name);

struct BakeSettings {
  std::string meshPath;
  std::string environment;  // an environment file, or "sky" / "sky:<spec>" (loadEnvironment)
  Material material;        // validated by bake()
  double mmPerUnit = 0.0;   // millimetres per mesh unit (> 0), unless sizeMm > 0
  double sizeMm = 0.0;      // > 0: scale so that the longest bounding-box side is this long
  VisibilityMode visibility = VisibilityMode::Rays;
  int samples = 64;                // visibility rays per vertex
  uint64_t seed = 1;               // visibility rays and Monte Carlo walks
  std::string method = "auto";     // a diffusion method (diffusion.h) or "pathtrace"
  std::string profile = "dipole";  // listProfiles(); unused by pathtrace
  double tolerance = 0.01;         // relative RMS of B (diffusion methods)
  int walks = 256;                 // pathtrace: random walks per vertex
  int environmentFaceSize = 0;     // 0: from the source resolution
  int threads = 0;                 // <= 0: all cores
  bool quiet = false;              // no progress bars or info lines
};

struct BakeOutput {
  BakedMesh baked;         // positions in the mesh's own units, mmPerUnit recorded
  std::string reportJson;  // counts, units, material, profile fit, method, stage times, errors
};

// Runs every stage. Warnings (mesh cleanup, long walks) go to stderr through warn(); errors throw
// sss::Error naming the file and the problem. Writes nothing.
BakeOutput bake(const BakeSettings& settings);

}  // namespace sss
