// What the bake's traced stages share (far_field.h, unscattered_light.h): light traced with the
// forward light tracer (pathtrace/light_tracer.h) where a pilot or a cheap test says it matters,
// and a report of what was traced and why. Serialized once (bake/bake_report_json.cpp).
#pragma once

#include <cstdint>
#include <string>

namespace sss {

// Auto: traced where the stage's own test finds it matters; Off: never; On: always.
enum class TracedMode { Auto, Off, On };

struct TracedStageReport {
  TracedMode requested = TracedMode::Auto;
  bool traced = false;
  std::string reason;  // why it was traced or not: the request, or auto's test
  uint64_t paths = 0;  // light paths traced, the pilot's included
  // The noise the traced light leaves, relative RMS (each stage says of what).
  double relativeStdError = 0.0;
  double seconds = 0.0;
};

}  // namespace sss
