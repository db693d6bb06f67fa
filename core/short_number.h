#pragma once
// Numbers in messages: six significant digits ("%.6g"), so that a value such
// as DBL_MAX reads 1.79769e+308 instead of std::to_string's 309 digits.
#include <cstdio>
#include <string>

namespace hw {

inline std::string shortNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

}  // namespace hw
