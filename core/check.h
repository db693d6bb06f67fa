#pragma once
// Always-on checks for broken preconditions (bugs, not bad input): print the
// operands and the location, then abort. Bad *input* goes through Result.
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

namespace hw::detail {
[[noreturn]] inline void checkFailed(const char* file, int line, const std::string& what) {
  std::fprintf(stderr, "%s:%d: CHECK failed: %s\n", file, line, what.c_str());
  std::fflush(stderr);
  std::abort();
}
template <class A, class B>
std::string formatPair(const char* ea, const char* op, const char* eb, const A& a, const B& b) {
  std::ostringstream s;
  s << ea << " " << op << " " << eb << " (" << a << " vs " << b << ")";
  return s.str();
}
}  // namespace hw::detail

#define HW_CHECK(cond) \
  do { if (!(cond)) ::hw::detail::checkFailed(__FILE__, __LINE__, #cond); } while (0)
#define HW_CHECK_OP(a, op, b)                                                        \
  do {                                                                               \
    const auto hwA_ = (a);                                                          \
    const auto hwB_ = (b);                                                          \
    if (!(hwA_ op hwB_))                                                             \
      ::hw::detail::checkFailed(__FILE__, __LINE__,                                  \
                                ::hw::detail::formatPair(#a, #op, #b, hwA_, hwB_));  \
  } while (0)
#define HW_CHECK_EQ(a, b) HW_CHECK_OP(a, ==, b)
#define HW_CHECK_NE(a, b) HW_CHECK_OP(a, !=, b)
#define HW_CHECK_LT(a, b) HW_CHECK_OP(a, <, b)
#define HW_CHECK_LE(a, b) HW_CHECK_OP(a, <=, b)
#define HW_CHECK_GT(a, b) HW_CHECK_OP(a, >, b)
#define HW_CHECK_GE(a, b) HW_CHECK_OP(a, >=, b)
