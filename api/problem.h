#pragma once
// RFC 9457 problem documents: the one error envelope of the HTTP API, and the one table from
// problem kind to HTTP status. The server throws ApiError; core's hexcover::Error maps through
// problemKindFor(ErrorCode).

#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "core/common/error.h"

namespace hexcover::api {

/// Every way a request or a job can fail, as the API reports it.
enum class ProblemKind {
  InvalidOption,         ///< 400: an option value is malformed, out of range or inconsistent
  BadRequest,            ///< 400: the request itself is malformed (missing part, bad parameter)
  NotFound,              ///< 404: no such job, route or result
  MethodNotAllowed,      ///< 405: the route exists but not with this method
  Conflict,              ///< 409: the resource is not in a state that allows this
  PayloadTooLarge,       ///< 413: the upload is over the configured limit
  UnsupportedMediaType,  ///< 415: unknown mesh format or content encoding
  UnprocessableMesh,     ///< 422: the mesh parsed but was refused (validation, limits, solver)
  IdempotencyMismatch,   ///< 422: an Idempotency-Key reused with a different request
  QueueFull,             ///< 503: the job queue is at its bound; retry later
  Unavailable,           ///< 503: the server is starting or draining
  Internal,              ///< 500: a bug or an I/O failure on our side; no details are exposed
};

/// HTTP status of a problem kind (the one table).
int httpStatus(ProblemKind kind);
/// Stable slug of a problem kind, the last segment of the problem `type` URI.
const char* problemSlug(ProblemKind kind);
/// Short human title of a problem kind (same for every occurrence, RFC 9457 section 3.1.3).
const char* problemTitle(ProblemKind kind);

/// How a core error is reported: InvalidOption -> 400, UnknownFormat -> 415, MalformedInput,
/// InvalidMesh, LimitExceeded, NumericalFailure -> 422, Canceled -> 409, Io -> 500.
ProblemKind problemKindFor(ErrorCode code);

/// An error that the HTTP layer turns into a problem document.
/// `extensions` are extra members of the document (e.g. {"option": "rosy"} or the mesh report).
class ApiError : public std::runtime_error {
 public:
  ApiError(ProblemKind kind, const std::string& detail,
           nlohmann::json extensions = nlohmann::json::object())
      : std::runtime_error(detail), kind_(kind), extensions_(std::move(extensions)) {}
  ProblemKind kind() const { return kind_; }
  const nlohmann::json& extensions() const { return extensions_; }

 private:
  ProblemKind kind_;
  nlohmann::json extensions_;
};

/// The problem document {type, title, status, detail, ...extensions}.
/// `type` is "urn:hexcover:problem:<slug>"; Internal problems never carry the detail
/// given here but a fixed sentence, so no internals reach a client.
nlohmann::json problemDocument(ProblemKind kind, const std::string& detail,
                               const nlohmann::json& extensions = nlohmann::json::object());

/// The problem document of a core error (adds {"code": errorCodeName(code)}).
nlohmann::json problemDocument(const Error& error);

/// The media type of problem documents.
inline constexpr const char* kProblemMediaType = "application/problem+json";

}  // namespace hexcover::api
