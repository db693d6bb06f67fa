#pragma once
// Error values of the hybridwalk library and the project inside it: a
// Result<T> holds a T or an Error whose message says what went wrong, where,
// and what was expected; Status is Result<void>. Nothing in the library throws
// across its interface or exits: bad input (scene files, camera paths,
// options, GL context failures) comes back as an Error. Reading the value of a
// Result that holds an Error (or the error of one that does not) is a bug in
// the caller: it prints the location and aborts.
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <utility>
#include <variant>

namespace hw {

struct Error {
  std::string message;
};

inline Error makeError(std::string message) { return Error{std::move(message)}; }

namespace detail {
[[noreturn]] inline void resultMisused(const char* what) {
  std::fprintf(stderr, "hybridwalk: %s\n", what);
  std::fflush(stderr);
  std::abort();
}
}  // namespace detail

template <class T>
class [[nodiscard]] Result {
 public:
  Result(T value) : v_(std::move(value)) {}  // NOLINT: implicit by design
  Result(Error e) : v_(std::move(e)) {}      // NOLINT
  bool ok() const { return v_.index() == 0; }
  explicit operator bool() const { return ok(); }
  T& value() & {
    need(ok());
    return std::get<0>(v_);
  }
  const T& value() const& {
    need(ok());
    return std::get<0>(v_);
  }
  T&& value() && {
    need(ok());
    return std::get<0>(std::move(v_));
  }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  T& operator*() { return value(); }
  const Error& error() const {
    need(!ok());
    return std::get<1>(v_);
  }

 private:
  static void need(bool cond) {
    if (!cond) detail::resultMisused("Result: value() of an error, or error() of a value");
  }
  std::variant<T, Error> v_;
};

template <>
class [[nodiscard]] Result<void> {
 public:
  Result() = default;
  Result(Error e) : e_(std::move(e)) {}  // NOLINT
  bool ok() const { return !e_.has_value(); }
  explicit operator bool() const { return ok(); }
  const Error& error() const {
    if (!e_) detail::resultMisused("Status: error() of a success");
    return *e_;
  }

 private:
  std::optional<Error> e_;
};

using Status = Result<void>;

}  // namespace hw

// The public API's names for them.
namespace hybridwalk {
using hw::Error;
using hw::Result;
using hw::Status;
}  // namespace hybridwalk
