// The OpenAPI document describes the API the server answers: every route of the server is an
// operation of the document, and every operation of the document is answered by a route.

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>

#include "server/openapi_document.h"
#include "tests/server/in_process_server.h"

namespace hexcover::server::test {
namespace {

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return text;
}

TEST(OpenApi, EveryRouteTheServerAnswersIsDescribed) {
  const auto doc = nlohmann::json::parse(openApiDocument());
  EXPECT_EQ(doc.at("openapi"), "3.1.0");
  for (const auto& route : HttpServer::routes()) {
    SCOPED_TRACE(route.method + " " + route.path);
    ASSERT_TRUE(doc.at("paths").contains(route.path));
    EXPECT_TRUE(doc.at("paths").at(route.path).contains(lower(route.method)));
  }
}

TEST(OpenApi, EveryDescribedOperationIsARouteOfTheServer) {
  const auto doc = nlohmann::json::parse(openApiDocument());
  const auto& routes = HttpServer::routes();
  for (const auto& [path, item] : doc.at("paths").items())
    for (const auto& [method, operation] : item.items()) {
      if (method == "parameters") continue;
      EXPECT_TRUE(
          std::any_of(routes.begin(), routes.end(),
                      [&](const Route& r) { return r.path == path && lower(r.method) == method; }))
          << method << " " << path;
    }
}

TEST(OpenApi, ServedDocumentIsTheEmbeddedOneAndEveryRouteAnswersWithoutRoutingErrors) {
  InProcessServer server;
  auto client = server.client();
  const auto served = client.Get("/v1/openapi.json");
  ASSERT_EQ(served->status, 200);
  EXPECT_EQ(served->body, std::string(openApiDocument()));
  // Each route is reachable: it answers neither "no such route" (404 from routing) nor 405.
  for (const auto& route : HttpServer::routes()) {
    if (route.method != "GET") continue;
    std::string path = route.path;
    if (const auto at = path.find("{id}"); at != std::string::npos) continue;  // needs a job
    const auto res = client.Get(path.c_str());
    ASSERT_TRUE(res) << path;
    EXPECT_NE(res->status, 404) << path;
    EXPECT_NE(res->status, 405) << path;
  }
}

TEST(OpenApi, ProblemResponsesAreDescribedForEveryErrorStatusTheApiUses) {
  const auto doc = nlohmann::json::parse(openApiDocument());
  const auto& post = doc.at("paths").at("/v1/jobs").at("post").at("responses");
  for (const char* status : {"400", "409", "413", "415", "422", "500", "503"})
    EXPECT_TRUE(post.contains(status)) << status;
}

}  // namespace
}  // namespace hexcover::server::test
