#pragma once
// Small JSON helpers shared by the bench reports (nlohmann::json).
#include <cmath>
#include <nlohmann/json.hpp>

namespace hw::bench {

// v as a JSON number, or null when v is NaN or ±inf (JSON has no such numbers).
inline nlohmann::json finiteOrNull(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

}  // namespace hw::bench
