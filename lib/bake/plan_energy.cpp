#include "bake/plan_energy.h"

#include "core/timer.h"
#include "core/tool.h"
#include "material/profile_factory.h"

namespace sss {

namespace {

EnergyOptions energyOptionsOf(const EnergyStageInput& in) {
  EnergyOptions options;
  options.model = in.energy;
  options.noiseBudget = in.walkBudget;
  options.nearWindowMm = in.nearWindowMm;
  options.seed = in.seed;
  options.threads = in.threads;
  options.quiet = in.quiet;
  return options;
}

}  // namespace

EnergyStage planEnergy(const EnergyStageInput& in) {
  const Stopwatch clock;
  EnergyStage out;
  EnergyStageReport& report = out.report;
  report.requested = in.energy;
  report.walkBudget = in.walkBudget;
  report.profileRequested = in.profile;
  if (in.runWalks) {
    report.plan = planFiniteObjectEnergy(in.meshMm, in.areasMm2, in.material, energyOptionsOf(in));
    info("energy: " + std::string(kEnergyModelNames.name(report.plan.model)) + " (" +
             report.plan.reason + ")",
         in.quiet);
    if (report.escape() && report.plan.escape.relativeStdError > in.walkBudget)
      warn("energy: " + report.plan.reason);
  }
  report.profileName = in.profile == ProfileChoice::Auto ? autoProfileName(report.plan.model)
                                                         : kProfileChoiceNames.name(in.profile);
  out.profile = makeProfile(report.profileName, in.material);
  report.profileTotalReflectance = out.profile->totalReflectance();
  report.seconds = clock.seconds();
  return out;
}

void useFarField(EnergyStage& stage, const EnergyStageInput& in, double budget,
                 double farFieldError) {
  const Stopwatch clock;
  EnergyOptions options = energyOptionsOf(in);
  options.noiseBudget = budget;
  refineNearShare(stage.report.plan, in.meshMm, in.areasMm2, in.material, options);
  stage.report.farField = true;
  stage.report.farFieldError = farFieldError;
  stage.report.seconds += clock.seconds();
}

}  // namespace sss
