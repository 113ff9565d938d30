#pragma once
// The one error type for expected failures (bad input, limits, solver failures, cancellation).
// Programming bugs are assertions, not Errors.

#include <stdexcept>
#include <string>

namespace hexcover {

enum class ErrorCode {
  UnknownFormat,    ///< the bytes are none of the supported mesh formats
  MalformedInput,   ///< the file is of a known format but cannot be parsed (names line or offset)
  InvalidMesh,      ///< parsed, but refused by validation (non-orientable, empty, NaN, ...)
  LimitExceeded,    ///< over a configured limit (face count, size)
  InvalidOption,    ///< an option value out of range or inconsistent
  NumericalFailure, ///< a solve did not succeed (singular system, no convergence)
  Canceled,         ///< the caller asked to stop
  Io,               ///< a file could not be opened, read or written
};

/// Stable snake_case name of an error code, used in JSON documents and logs.
inline const char* errorCodeName(ErrorCode code) {
  switch (code) {
    case ErrorCode::UnknownFormat: return "unknown_format";
    case ErrorCode::MalformedInput: return "malformed_input";
    case ErrorCode::InvalidMesh: return "invalid_mesh";
    case ErrorCode::LimitExceeded: return "limit_exceeded";
    case ErrorCode::InvalidOption: return "invalid_option";
    case ErrorCode::NumericalFailure: return "numerical_failure";
    case ErrorCode::Canceled: return "canceled";
    case ErrorCode::Io: return "io";
  }
  return "unknown";
}

/// An expected failure with a message a user can act on.
class Error : public std::runtime_error {
 public:
  Error(ErrorCode code, const std::string& message) : std::runtime_error(message), code_(code) {}
  ErrorCode code() const { return code_; }

 private:
  ErrorCode code_;
};

}  // namespace hexcover
