#include "bake/transport.h"

#include <algorithm>
#include <cmath>

#include "core/format.h"
#include "core/relative_rms.h"
#include "core/timer.h"
#include "core/tool.h"
#include "mesh/triangle_mesh.h"
#include "pathtrace/subsurface_path_tracer.h"
#include "transport/far_field.h"

namespace sss {

namespace {

std::vector<glm::vec3> pathTrace(const TransportInput& in, TransportReport& report) {
  PathTraceOptions options;
  options.samples = in.walks;
  options.run = in.run;
  options.estimateRadiance = false;
  PathTraceResult result = pathTraceSubsurface(in.meshMm, in.radiance, in.material, options);
  PathTraceStageReport& r = report.pathTracer;
  r.walks = in.walks;
  r.g = in.material.g;
  r.meanScatteringEvents = result.meanScatteringEvents;
  r.truncatedWalks = result.truncatedWalks;
  r.escapedWalks = result.escapedWalks;
  r.warnings = result.warnings;
  report.estimatedError = rmsOfRelativeLuminance(result.exitance, result.exitanceStdErr);
  return std::move(result.exitance);
}

std::vector<glm::vec3> diffusionSum(const TransportInput& in, TransportReport& report) {
  const DiffusionInput input{in.meshMm.positions, in.meshMm.normals, in.areasMm2, in.irradiance};
  DiffusionOptions options;
  options.method = diffusionMethodOf(in.method);
  options.tolerance = in.diffusionTolerance;
  options.run = in.run;
  options.meshCache = in.diffusionMeshCache;
  const bool traced = in.farField && in.farField->traced();
  const std::span<const glm::vec3> farExitance =
      traced ? std::span<const glm::vec3>(in.farField->exitance) : std::span<const glm::vec3>();
  DiffusionResult result = diffuseWithEnergy(input, in.profile, options, in.energy, in.material,
                                             farExitance, in.weightSums);
  if (traced)
    report.nearPartNoise = calibrateNearPart(
        result.exitance,
        {in.meshMm, in.areasMm2, farExitance, in.farField->nearExitance, in.farField->nearVariance,
         in.farField->nearFarCovariance, in.farField->report.smoothingMm, in.run.threads});
  report.diffusion = std::move(result.report);
  report.diffusionTolerance = in.diffusionTolerance;
  report.estimatedError = std::hypot(report.diffusion.estimatedError, report.nearPartNoise);
  return std::move(result.exitance);
}

}  // namespace

std::string TransportReport::methodName() const {
  return pathTrace ? kBakeMethodNames.name(BakeMethod::PathTrace)
                   : kDiffusionMethodNames.name(diffusion.method);
}

VertexExitance transport(const TransportInput& in) {
  const Stopwatch clock;
  VertexExitance out;
  out.report.requested = in.method;
  out.report.pathTrace = in.method == BakeMethod::PathTrace;
  out.exitance = out.report.pathTrace ? pathTrace(in, out.report) : diffusionSum(in, out.report);
  out.report.seconds = clock.seconds();
  info(out.report.methodName() + ": " + format("%.3f s", out.report.seconds), in.run.quiet);
  return out;
}

TransportInput linearTransportInput(const TransportInput& transportIn, const VertexExitance& direct,
                                    EnergyWeightSums& wholeEscapeSums) {
  TransportInput in = transportIn;
  in.method = bakeMethodOf(direct.report.diffusion.method);
  in.run.quiet = true;
  if (in.farField && in.farField->traced()) {
    in.farField = nullptr;
    if (in.weightSums) in.weightSums = &wholeEscapeSums;
  }
  return in;
}

IncrementSums incrementSums(BakeMethod direct, double directTolerance, double looseness) {
  constexpr double kLoosestIncrementTolerance = 0.03;
  return {.method = direct == BakeMethod::Gauss ? BakeMethod::Auto : direct,
          .tolerance = std::min(kLoosestIncrementTolerance, looseness * directTolerance)};
}

}  // namespace sss
