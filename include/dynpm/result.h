// dynpm/result.h — errors for untrusted input.
//
// Readers, writers and decoders return a Status or a Result<T> instead of throwing: bad bytes
// are an expected outcome, not an exceptional one (draco, tinyobjloader). The message always
// names the file, the place (line or byte offset) and the cause, so the CLI can print it as is.
// Programmer errors (violated preconditions) are assertions, not Status.
#pragma once

#include <cassert>
#include <string>
#include <utility>
#include <variant>

namespace dynpm {

class Status {
 public:
  Status() = default;  // success
  static Status error(std::string message) { return Status(std::move(message)); }

  bool ok() const { return !failed_; }
  explicit operator bool() const { return ok(); }
  const std::string& message() const { return message_; }
  const Status& status() const { return *this; }  // so Status and Result read alike

 private:
  explicit Status(std::string message) : message_(std::move(message)), failed_(true) {}
  std::string message_;
  bool failed_ = false;
};

// A value or an error message. Access to value() on an error is a programmer error.
template <class T>
class Result {
 public:
  Result(T value) : state_(std::move(value)) {}        // NOLINT: implicit on purpose
  Result(Status status) : state_(std::move(status)) {  // NOLINT: implicit on purpose
    assert(!std::get<Status>(state_).ok() && "a Result built from a Status must carry an error");
  }

  bool ok() const { return std::holds_alternative<T>(state_); }
  explicit operator bool() const { return ok(); }

  T& value() & {
    assert(ok());
    return std::get<T>(state_);
  }
  const T& value() const& {
    assert(ok());
    return std::get<T>(state_);
  }
  T&& value() && {
    assert(ok());
    return std::get<T>(std::move(state_));
  }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  T& operator*() & { return value(); }
  const T& operator*() const& { return value(); }

  Status status() const { return ok() ? Status() : std::get<Status>(state_); }
  const std::string& message() const {
    static const std::string kNone;
    return ok() ? kNone : std::get<Status>(state_).message();
  }

 private:
  std::variant<T, Status> state_;
};

}  // namespace dynpm

// Early return of a failed Status or Result from a function returning Status or Result<U>.
#define DYNPM_RETURN_IF_ERROR(expr)                         \
  do {                                                      \
    auto dynpm_status_ = (expr);                            \
    if (!dynpm_status_.ok()) return dynpm_status_.status(); \
  } while (0)
