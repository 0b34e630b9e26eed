// Length units. Material coefficients are per millimetre, so every mesh carries how many
// millimetres one of its units is (mm per unit).
#pragma once

#include <string>

namespace sss {

// Millimetres per unit for "mm", "cm" or "m" (1, 10, 1000). Throws Error naming the accepted
// units for anything else.
double parseUnit(const std::string& unit);

// Checks a --mm-per-unit value: finite and positive; throws Error("<what>: ...") otherwise.
double checkMmPerUnit(double mmPerUnit, const std::string& what = "mm per unit");

}  // namespace sss
