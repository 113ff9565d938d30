// Problem documents: one table with a distinct status for each kind the API distinguishes,
// RFC 9457 members present, internals never exposed.

#include "api/problem.h"

#include <gtest/gtest.h>

namespace hexcover::api {
namespace {

TEST(Problem, EveryKindHasTheStatusOfTheTable) {
  EXPECT_EQ(httpStatus(ProblemKind::InvalidOption), 400);
  EXPECT_EQ(httpStatus(ProblemKind::BadRequest), 400);
  EXPECT_EQ(httpStatus(ProblemKind::NotFound), 404);
  EXPECT_EQ(httpStatus(ProblemKind::MethodNotAllowed), 405);
  EXPECT_EQ(httpStatus(ProblemKind::Conflict), 409);
  EXPECT_EQ(httpStatus(ProblemKind::PayloadTooLarge), 413);
  EXPECT_EQ(httpStatus(ProblemKind::UnsupportedMediaType), 415);
  EXPECT_EQ(httpStatus(ProblemKind::UnprocessableMesh), 422);
  EXPECT_EQ(httpStatus(ProblemKind::IdempotencyMismatch), 422);
  EXPECT_EQ(httpStatus(ProblemKind::QueueFull), 503);
  EXPECT_EQ(httpStatus(ProblemKind::Unavailable), 503);
  EXPECT_EQ(httpStatus(ProblemKind::Internal), 500);
}

TEST(Problem, CoreErrorsMapToClientOrServerStatuses) {
  EXPECT_EQ(httpStatus(problemKindFor(ErrorCode::InvalidOption)), 400);
  EXPECT_EQ(httpStatus(problemKindFor(ErrorCode::UnknownFormat)), 415);
  EXPECT_EQ(httpStatus(problemKindFor(ErrorCode::MalformedInput)), 422);
  EXPECT_EQ(httpStatus(problemKindFor(ErrorCode::InvalidMesh)), 422);
  EXPECT_EQ(httpStatus(problemKindFor(ErrorCode::LimitExceeded)), 422);
  EXPECT_EQ(httpStatus(problemKindFor(ErrorCode::Io)), 500);
}

TEST(Problem, DocumentHasTheRfc9457MembersAndTheExtensions) {
  const auto doc =
      problemDocument(ProblemKind::InvalidOption, "option 'rosy' must be 6", {{"option", "rosy"}});
  EXPECT_EQ(doc.at("status"), 400);
  EXPECT_EQ(doc.at("type"), "urn:hexcover:problem:invalid-option");
  EXPECT_EQ(doc.at("title"), "An option is invalid");
  EXPECT_EQ(doc.at("detail"), "option 'rosy' must be 6");
  EXPECT_EQ(doc.at("option"), "rosy");
}

TEST(Problem, ExtensionsCannotOverrideTheStandardMembers) {
  const auto doc =
      problemDocument(ProblemKind::NotFound, "no job x", {{"status", 200}, {"type", "x"}});
  EXPECT_EQ(doc.at("status"), 404);
  EXPECT_EQ(doc.at("type"), "urn:hexcover:problem:not-found");
}

TEST(Problem, InternalProblemsHideTheirDetail) {
  const auto doc = problemDocument(ProblemKind::Internal, "segfault in solver.cpp:42 at 0x7ff");
  EXPECT_EQ(doc.at("status"), 500);
  EXPECT_EQ(doc.dump().find("solver.cpp"), std::string::npos);
  const auto io = problemDocument(Error(ErrorCode::Io, "cannot open /var/secret/file"));
  EXPECT_EQ(io.dump().find("/var/secret"), std::string::npos);
}

TEST(Problem, CoreErrorDocumentCarriesTheErrorCodeAndMessage) {
  const auto doc = problemDocument(Error(ErrorCode::InvalidMesh, "non-orientable component 0"));
  EXPECT_EQ(doc.at("status"), 422);
  EXPECT_EQ(doc.at("code"), "invalid_mesh");
  EXPECT_EQ(doc.at("detail"), "non-orientable component 0");
}

}  // namespace
}  // namespace hexcover::api
