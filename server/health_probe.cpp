#include "server/health_probe.h"

#include <httplib.h>

#include <iostream>

namespace hexcover::server {

int probeHealth(const ServerConfig& config, const std::string& path) {
  const bool wildcard = config.host == "0.0.0.0" || config.host == "::" || config.host.empty();
  const std::string host = wildcard ? "127.0.0.1" : config.host;
  httplib::Client client(host, config.port);
  client.set_connection_timeout(3);
  client.set_read_timeout(3);
  const auto response = client.Get(path);
  if (!response) {
    std::cerr << "health check: no answer from " << host << ":" << config.port << path << " ("
              << httplib::to_string(response.error()) << ")\n";
    return 1;
  }
  if (response->status != 200) {
    std::cerr << "health check: " << host << ":" << config.port << path << " answered "
              << response->status << "\n";
    return 1;
  }
  return 0;
}

}  // namespace hexcover::server
