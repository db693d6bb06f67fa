#pragma once
// Small JSON helpers shared by the bench reports (nlohmann::json).
#include <cmath>
#include <nlohmann/json.hpp>

#include "keyframe/keyframe_planner.h"

namespace hw::bench {

// v as a JSON number, or null when v is NaN or ±inf (JSON has no such numbers).
inline nlohmann::json finiteOrNull(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

// j as a double, or NaN when it is not a number (e.g. the null finiteOrNull
// writes): the inverse of finiteOrNull when reading a report back.
inline double numberOrNan(const nlohmann::json& j) {
  return j.is_number() ? j.get<double>() : std::nan("");
}

// A predictor fit: {"intercept", "slope", "slope2"} (null when not finite),
// and "more" (the slopes of regressors 3..) only when the fit has them.
inline nlohmann::json fitJson(const keyframe::PsnrFit& f) {
  nlohmann::json j = {{"intercept", finiteOrNull(f.intercept)},
                      {"slope", finiteOrNull(f.slope)},
                      {"slope2", finiteOrNull(f.slope2)}};
  if (!f.more.empty()) {
    nlohmann::json m = nlohmann::json::array();
    for (double v : f.more) m.push_back(finiteOrNull(v));
    j["more"] = m;
  }
  return j;
}

}  // namespace hw::bench
