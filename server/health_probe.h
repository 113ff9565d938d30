#pragma once
// `hexcover-server --health-check [PATH]`: the container's HEALTHCHECK, done by the server binary
// itself (the image has no curl).

#include <string>

#include "server/config.h"

namespace hexcover::server {

/// GETs http://127.0.0.1:<config.port><path> (or the configured host when it is not a wildcard)
/// with a 3 s timeout. Returns the process exit status: 0 when the answer is 200, 1 otherwise
/// (the reason on stderr).
int probeHealth(const ServerConfig& config, const std::string& path = "/readyz");

}  // namespace hexcover::server
