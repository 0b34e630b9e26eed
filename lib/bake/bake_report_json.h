// The JSON of `sss-bake --json`, built once from the bake's report structs (bake_report.h): one
// toJson per report type. Keys are snake_case, lengths in mm, times in seconds.
#pragma once

#include <nlohmann/json.hpp>

#include "bake/bake_report.h"

namespace sss {

using Json = nlohmann::ordered_json;

Json toJson(const MeshStageReport& report);
Json toJson(const EnergyStageReport& report);  // the "energy" object
Json toJson(const LightingReport& report);     // "visibility"
Json toJson(const TransportReport& report);    // "exitance"
Json toJson(const BakeErrorReport& report);    // "estimated_error"
Json toJson(const LightmapReport& report);     // "texture"
// The whole report; the tool adds "output" and its own stage times.
Json toJson(const BakeReport& report);

}  // namespace sss
