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
  options.run = in.run;
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
         in.run.quiet);
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

EnergyStageReport energyWithFarField(const EnergyStageInput& in, EnergyStageReport energy,
                                     double budget, double farFieldError) {
  const Stopwatch clock;
  EnergyOptions options = energyOptionsOf(in);
  options.noiseBudget = budget;
  refineNearShare(energy.plan, in.meshMm, in.areasMm2, in.material, options);
  energy.farField = true;
  energy.farFieldError = farFieldError;
  energy.seconds += clock.seconds();
  return energy;
}

}  // namespace sss
