#pragma once
// Small JSON helpers for reports (nlohmann::json): JSON has no NaN or ±inf.
#include <cmath>

#include <nlohmann/json.hpp>

namespace hw {

// v as a JSON number, or null when v is NaN or ±inf.
inline nlohmann::json finiteOrNull(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

// j as a double, or NaN when it is not a number (e.g. the null finiteOrNull
// writes): the inverse of finiteOrNull when reading a report back.
inline double numberOrNan(const nlohmann::json& j) {
  return j.is_number() ? j.get<double>() : std::nan("");
}

}  // namespace hw
