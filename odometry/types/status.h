// Error handling for data errors: a Status carries a message that names the file, field and value;
// Expected<T> is either a value or such a Status. Programmer errors assert instead.
#pragma once

#include <cassert>
#include <string>
#include <utility>
#include <variant>

namespace uf {

class Status {
 public:
  Status() = default;  // ok
  static Status Error(std::string message) { return Status(std::move(message)); }

  bool ok() const { return !failed_; }
  const std::string& message() const { return message_; }

 private:
  explicit Status(std::string message) : failed_(true), message_(std::move(message)) {}
  bool failed_ = false;
  std::string message_;
};

template <typename T>
class Expected {
 public:
  Expected(T value) : data_(std::move(value)) {}  // NOLINT: implicit by design, like std::expected
  Expected(Status error) : data_(std::move(error)) { assert(!std::get<Status>(data_).ok()); }  // NOLINT

  bool ok() const { return std::holds_alternative<T>(data_); }
  explicit operator bool() const { return ok(); }

  const T& value() const& { return std::get<T>(data_); }
  T& value() & { return std::get<T>(data_); }
  T&& value() && { return std::get<T>(std::move(data_)); }
  const T& operator*() const& { return value(); }
  T& operator*() & { return value(); }
  const T* operator->() const { return &value(); }
  T* operator->() { return &value(); }

  const Status& status() const { return std::get<Status>(data_); }
  const std::string& error() const { return status().message(); }

 private:
  std::variant<T, Status> data_;
};

}  // namespace uf
