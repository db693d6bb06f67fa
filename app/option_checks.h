#pragma once
// Checks CLI11 leaves to us, run once after parsing, over every option of the
// subcommands that were given: a number option must be finite (CLI11's
// Range/NonNegativeNumber compare with < and >, which NaN passes), and a path
// option (--out, --diff, ...) must not be empty.
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdlib>
#include <string>

namespace hw::app {

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
