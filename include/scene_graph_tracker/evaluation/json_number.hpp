// How the evaluation writes a number into report.json: 6 significant digits, null when it is not
// finite (a median of nothing, a ratio of zero counts).
#pragma once

#include <cmath>
#include <iomanip>
#include <sstream>
#include <string>

namespace sgt {

inline std::string jsonNumber(double x) {
  if (!std::isfinite(x)) return "null";
  std::ostringstream o;
  o << std::setprecision(6) << x;
  return o.str();
}

}  // namespace sgt
