#pragma once
// Error values for bad input from outside (files, paths, CLI, GL/context
// failures). Messages say what, where, and expected vs got; only main turns
// them into exit codes.
#include <optional>
#include <string>
#include <utility>
#include <variant>

#include "core/check.h"

namespace hw {

struct Error {
  std::string message;
};

inline Error makeError(std::string message) { return Error{std::move(message)}; }

template <class T>
class [[nodiscard]] Result {
 public:
  Result(T value) : v_(std::move(value)) {}  // NOLINT: implicit by design
  Result(Error e) : v_(std::move(e)) {}      // NOLINT
  bool ok() const { return v_.index() == 0; }
  explicit operator bool() const { return ok(); }
  T& value() & { HW_CHECK(ok()); return std::get<0>(v_); }
  const T& value() const& { HW_CHECK(ok()); return std::get<0>(v_); }
  T&& value() && { HW_CHECK(ok()); return std::get<0>(std::move(v_)); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  T& operator*() { return value(); }
  const Error& error() const { HW_CHECK(!ok()); return std::get<1>(v_); }

 private:
  std::variant<T, Error> v_;
};

template <>
class [[nodiscard]] Result<void> {
 public:
  Result() = default;
  Result(Error e) : e_(std::move(e)) {}  // NOLINT
  bool ok() const { return !e_.has_value(); }
  explicit operator bool() const { return ok(); }
  const Error& error() const { HW_CHECK(!ok()); return *e_; }

 private:
  std::optional<Error> e_;
};

using Status = Result<void>;

}  // namespace hw

// Propagate an error from an expression returning Result<...>.
#define HW_TRY(expr)                              \
  do {                                            \
    auto hwRes_ = (expr);                         \
    if (!hwRes_.ok()) return hwRes_.error();      \
  } while (0)
