#pragma once
// Checks CLI11 leaves to us, run once after parsing, over every option of the
// subcommands that were given: a number option must be finite (CLI11's
// Range/NonNegativeNumber compare with < and >, which NaN passes), and a path
// option (--out, --diff, ...) must not be empty.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>

#include "core/short_number.h"

namespace hw::app {

// CLI::Range for floating-point options, with the bounds written short
// (CLI11's own writes them with std::to_string: 0.000100, and DBL_MAX as
// 309 digits). `hi` infinite: no upper bound.
inline CLI::Validator numberRange(double lo, double hi) {
  const std::string range = std::isfinite(hi) ? shortNumber(lo) + " to " + shortNumber(hi)
                                              : shortNumber(lo) + " and above";
  return CLI::Validator(
      [lo, hi, range](std::string& in) -> std::string {
        char* end = nullptr;
        const double x = std::strtod(in.c_str(), &end);
        if (in.empty() || end == in.c_str() || *end != '\0')
          return "Value " + in + " is not a number (expected " + range + ")";
        if (std::isnan(x)) return std::string();  // "expected a finite number", after parsing
        if (!std::isfinite(x) || x < lo || x > hi) return "Value " + in + " not in range " + range;
        return std::string();
      },
      "FLOAT in " + range, "RANGE");
}

// A number >= 0 (CLI::NonNegativeNumber, with a message of usual length).
inline CLI::Validator nonNegativeNumber() {
  return numberRange(0.0, std::numeric_limits<double>::infinity());
}

// Error text for the first offending option, or "" when all are fine.
inline std::string checkParsedOptions(const CLI::App& app) {
  static const char* const kPathOptions[] = {"--out",  "--diff",      "--screenshot", "--path",
                                             "--keyframes", "--scene", "--table"};
  for (const CLI::Option* opt : app.get_options()) {
    if (opt->count() == 0) continue;
    const std::string name = opt->get_name();
    const std::string type = opt->get_type_name();
    for (const std::string& v : opt->results()) {
      if (type.rfind("FLOAT", 0) == 0) {
        char* end = nullptr;
        const double x = std::strtod(v.c_str(), &end);
        if (end != v.c_str() && *end == '\0' && !std::isfinite(x))
          return name + ": expected a finite number, got '" + v + "'";
      }
      for (const char* p : kPathOptions)
        if (name == p && v.empty()) return name + ": expected a path, got an empty string";
    }
  }
  for (const CLI::App* sub : app.get_subcommands())
    if (std::string e = checkParsedOptions(*sub); !e.empty()) return e;
  return "";
}

}  // namespace hw::app
