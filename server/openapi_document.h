#pragma once
// The OpenAPI 3.1 document of API v1 (api/openapi.json), embedded at build time.

#include <string_view>

namespace hexcover::server {

/// The text of api/openapi.json.
std::string_view openApiDocument();

}  // namespace hexcover::server
