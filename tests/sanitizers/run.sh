#!/usr/bin/env bash
# The whole test suite under AddressSanitizer + UndefinedBehaviorSanitizer (with LeakSanitizer):
# the checked build of tests/sanitizers/build.sh (clang; shared with the fuzz targets) in BUILD_DIR
# (default build-checked/), every test through ctest with the settings of env.sh. Exits non-zero
# when a test fails or a sanitizer reports (a report ends the process that made it).
#   tests/sanitizers/run.sh [BUILD_DIR]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=$(realpath -m "${1:-$root/build-checked}")
cd "$root"

# The settings hold for the build too: it runs the test programs to list their tests.
source tests/sanitizers/env.sh
bash tests/sanitizers/build.sh "$build"
# Mesa's llvmpipe driver leaks a few objects and is unloaded by eglTerminate, after which LSan can
# no longer name the library they came from (nor match a suppression): loaded with the program it
# stays mapped to the end, where its memory is still reachable. (clang links ASan's runtime into
# each program, so nothing has to come before it.) Only for the tests labelled `opengl`
# (tests/CMakeLists.txt): the driver brings LLVM with it, 0.18 s more for every process that
# starts, ~900 of them in this suite.
driver=$(ls /usr/lib/*/dri/swrast_dri.so 2>/dev/null | head -1 || true)
# workflow_test drives the tools through Snakemake (the orchestration: rules, reruns, the
# contact sheet); every tool it calls is run under the sanitizers by the tools' own tests, and
# under ASan it alone takes 149 of the suite's 581 s (measured). It runs in the Release suite, as
# does slurm_test (the same workflow through a one-node Slurm: daemons and scheduling). So
# do the tests that only check how each tool refuses a command line (exit status and message,
# before any input is parsed): each run is a fresh process (OIIO's ~260 libraries to bind), and
# the code they reach is parsing, which the other tool tests run under the sanitizers too.
command_line_only='SssIrrmap\.BadOptions|SssIrrmap\.FaceSizesAndEtaAreCheckedAsInTheOtherTools'
command_line_only+='|SssRenderTool\.BadOptionsAreRejectedBeforeAnyOutput'
command_line_only+='|BakeTool\.BadChoicesAreErrors'
command_line_only+='|BakeTool\.EveryToolHasVersionAndHelpEndsWithExamples'
# And the statistical checks of a model against its reference at many samples (5-11 s each under
# ASan, ~55 of the suite's summed seconds): the same code runs under the sanitizers in the quicker
# tests of each subject (UnscatteredLight.*, FarField.*, Diffusion.*, EscapeProbability.*,
# LightTracer.*, ExitLobe.* with its thin slab, Visibility.* with the ratio estimator beside a wall
# and in a concave corner); the Release suite runs these.
statistical='UnscatteredLight\.BackLitSlabMatchesTheClosedForm'
statistical+='|UnscatteredLight\.ReportedNoiseMatchesTheSpreadOverSeeds'
# A heavy-tailed draw (a few rare bright paths decide the pilot's share): in the checked build's
# arithmetic the seed's pilot draws none of them and finds the light negligible.
statistical+='|UnscatteredLight\.AutoLeavesOutALightNoLargerThanItsNoise'
statistical+='|FarField\.SunLitSphereUnlitHalfMatchesTheLightTracer'
statistical+='|FarField\.AveragingBiasIsLargestAtASunsTerminator'
statistical+='|Diffusion\.OtherProfilesMatchExact'
statistical+='|EscapeProbability\.HalfSpaceMatchesTabulatedAlbedoAndPathTracer'
statistical+='|EscapeProbability\.ThinSlabCountsLightReflectedBeforeItsFirstScattering'
statistical+='|LightTracer\.ReportedStandardErrorsMatchTheSpreadOverSeeds'
statistical+='|ExitLobe\.PredictsTheRadianceOnTheUnlitHalfOfASphere'
statistical+='|FarField\.ExitLobeGivesTheRadianceLeavingAThinSlab'
statistical+='|FarField\.NearPartFollowsTheLightTracerUnderAHighSun'
statistical+='|FarField\.ReportedLobeNoiseMatchesTheSpreadOverSeeds'
statistical+='|FarField\.ReportedNearAndFarNoiseMatchTheSpreadOverSeeds'
statistical+='|ExitLobe\.OneLobeForAllExitsFollowsALowAlbedoFaceUnderAHighSun'
statistical+='|FailureModes\.SharpEdgesHoldUnderLightFromAbove'
statistical+='|Visibility\.TheRatioEstimatorIsUnbiasedAndQuieterBesideAWall'
# And the checks that one bake's numbers follow a policy or repeat across thread counts (9-18 s
# each under ASan, ~65 s summed): what they compare is arithmetic, not memory, and each stage
# they run (the pilot, the escape walks, the far field; one thread in several stage tests) runs
# under the sanitizers in the other bake and far-field tests.
policy='BakeTool\.SameOutputForOneAndTwoThreads|FarField\.SameResultForAnyThreadCount'
policy+='|Relight\.SameResultForAnyThreadCount'
policy+='|BakeTool\.EnergyModelFollowsTheObjectSize|FarField\.UniformLightKeepsBEqualToEP'
policy+='|BakeTool\.AutoSamplesFollowTheTolerance'
# And the slowest accuracy checks and process races (9-17 s each under ASan, ~95 s summed,
# measured): an exact sum against its closed form, the lightmap against a dense bake, the far
# field's and a pit's bounces against their policies, a fit over every preset, the visibility noise
# model against its spread, and two bakes racing for one output. The code they run is under the
# sanitizers in the quicker tests of the same subjects (SssIrrmap.*, BakeTexture.GlbCarries...,
# Interreflection.*, GaussianSumFit.RecoversAnExactSum, VisibilityNoiseModel.TighterBudgetPicksMoreRays,
# the BakeTool tests).
slow='Irradiance\.ExactSumOfAUniformEquirectIsTheClosedForm'
slow+='|BakeTexture\.LowPolyLightmapMatchesADenseVertexBake'
slow+='|FarField\.BouncesCarryAllTheLightTheObjectSendsItself|BakeTool\.InterreflectionBrightensAPit'
slow+='|GaussianSumFit\.MeetsToleranceForEveryPresetAndProfile'
slow+='|VisibilityNoiseModel\.PredictsTheMeasuredErrorOfB'
slow+='|Concurrency\.TwoBakesIntoOneOutputLeaveOneWholeBake'
slow+='|Concurrency\.TwoMeshesBakedIntoOneFolderComeOutAsAlone'
# The thin ketchup sphere's exit lobe against its reference (4 s in Release: the unscattered
# light and the walks of a low albedo): the stage it checks runs under the sanitizers in the
# other BakeExitModel tests.
slow+='|BakeExitModel\.ThinLowAlbedoSphereFollowsItsOwnWalks'
# sss-relight and sss-render's relighting as binaries (44 s checked): what they run is under the
# sanitizers in relight_test (lib/bake/relight.h) and the readers' fuzz targets.
slow+='|SssRelightTool\..*'
# And install_test and deb_test (tests/install): they check what `cmake --install` and `cpack`
# lay out and run the installed tools once on quick settings, code that the tools' own tests run
# under the sanitizers. And browser_test (tests/browser): what it checks is a browser drawing our
# GLB; the bake and the GLB writer it runs are under the sanitizers in sss_bake_texture_test.
left_out="^(workflow_test|slurm_test|install_test|deb_test|browser_test|$command_line_only|$statistical|$policy|$slow)\$"
ctest --test-dir "$build" --output-on-failure --no-tests=error -j "$(nproc)" -E "$left_out" \
  -LE '^opengl$'
LD_PRELOAD="$driver" ctest --test-dir "$build" --output-on-failure --no-tests=error \
  -j "$(nproc)" -E "$left_out" -L '^opengl$'
