#include "mesh/units.h"

#include <cmath>
#include <sstream>

#include "core/error.h"

namespace sss {

double parseUnit(const std::string& unit) {
  if (unit == "mm") return 1.0;
  if (unit == "cm") return 10.0;
  if (unit == "m") return 1000.0;
  fail("", "unknown length unit '" + unit + "' (use mm, cm or m)");
}

double checkMmPerUnit(double mmPerUnit, const std::string& what) {
  if (!std::isfinite(mmPerUnit) || mmPerUnit <= 0.0) {
    std::ostringstream value;
    value << mmPerUnit;
    fail(what, "must be a positive length in millimetres, got " + value.str());
  }
  return mmPerUnit;
}

}  // namespace sss
