#include "api/problem.h"

namespace hexcover::api {

namespace {

struct ProblemRow {
  ProblemKind kind;
  int status;
  const char* slug;
  const char* title;
};

// The one table: problem kind -> HTTP status, type slug, title.
constexpr ProblemRow kProblemTable[] = {
    {ProblemKind::InvalidOption, 400, "invalid-option", "An option is invalid"},
    {ProblemKind::BadRequest, 400, "bad-request", "The request is malformed"},
    {ProblemKind::NotFound, 404, "not-found", "Not found"},
    {ProblemKind::MethodNotAllowed, 405, "method-not-allowed", "Method not allowed"},
    {ProblemKind::Conflict, 409, "conflict", "The resource is in a conflicting state"},
    {ProblemKind::PayloadTooLarge, 413, "payload-too-large", "The upload is too large"},
    {ProblemKind::UnsupportedMediaType, 415, "unsupported-media-type",
     "Unsupported mesh format or encoding"},
    {ProblemKind::UnprocessableMesh, 422, "unprocessable-mesh", "The mesh cannot be remeshed"},
    {ProblemKind::IdempotencyMismatch, 422, "idempotency-key-reused",
     "The Idempotency-Key was used for a different request"},
    {ProblemKind::QueueFull, 503, "queue-full", "The job queue is full"},
    {ProblemKind::Unavailable, 503, "unavailable", "The server is not accepting work"},
    {ProblemKind::Internal, 500, "internal", "Internal server error"},
};

const ProblemRow& row(ProblemKind kind) {
  for (const auto& r : kProblemTable)
    if (r.kind == kind) return r;
  return kProblemTable[std::size(kProblemTable) - 1];
}

}  // namespace

int httpStatus(ProblemKind kind) { return row(kind).status; }
const char* problemSlug(ProblemKind kind) { return row(kind).slug; }
const char* problemTitle(ProblemKind kind) { return row(kind).title; }

ProblemKind problemKindFor(ErrorCode code) {
  switch (code) {
    case ErrorCode::InvalidOption:
      return ProblemKind::InvalidOption;
    case ErrorCode::UnknownFormat:
      return ProblemKind::UnsupportedMediaType;
    case ErrorCode::MalformedInput:
    case ErrorCode::InvalidMesh:
    case ErrorCode::LimitExceeded:
    case ErrorCode::NumericalFailure:
      return ProblemKind::UnprocessableMesh;
    case ErrorCode::Canceled:
      return ProblemKind::Conflict;
    case ErrorCode::Io:
      return ProblemKind::Internal;
  }
  return ProblemKind::Internal;
}

nlohmann::json problemDocument(ProblemKind kind, const std::string& detail,
                               const nlohmann::json& extensions) {
  nlohmann::json doc = extensions.is_object() ? extensions : nlohmann::json::object();
  doc["type"] = std::string("urn:hexcover:problem:") + problemSlug(kind);
  doc["title"] = problemTitle(kind);
  doc["status"] = httpStatus(kind);
  doc["detail"] = kind == ProblemKind::Internal
                      ? "The server failed to process the request; the failure has been logged."
                      : detail;
  return doc;
}

nlohmann::json problemDocument(const Error& error) {
  return problemDocument(problemKindFor(error.code()), error.what(),
                         {{"code", errorCodeName(error.code())}});
}

}  // namespace hexcover::api
