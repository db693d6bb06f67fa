#pragma once
// Error values for bad input from outside (files, paths, CLI, GL/context
// failures). Messages say what, where, and expected vs got; only main turns
// them into exit codes. Result, Status and Error are defined in the public
// header (the library's API returns them too).
#include "core/check.h"
#include "hybridwalk/result.h"

// Propagate an error from an expression returning Result<...>.
#define HW_TRY(expr)                         \
  do {                                       \
    auto hwRes_ = (expr);                    \
    if (!hwRes_.ok()) return hwRes_.error(); \
  } while (0)
