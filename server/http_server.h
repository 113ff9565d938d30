#pragma once
// The HTTP transport of API v1 (cpp-httplib 0.11.4 as Debian ships it): routes, validation of
// requests in layers (framing and limits, then options, then the mesh format), problem
// documents, CORS, health and Prometheus metrics. Handlers validate, store, enqueue and answer;
// they never run geometry.
//
// Gaps of that cpp-httplib version handled here: its payload limit ignores chunked and
// compressed bodies (we count bytes while receiving and refuse Content-Encoding); a handler that
// leaves a body unread would have it parsed as the next request (refusals close the connection,
// and Expect: 100-continue requests are refused before the body is sent); exception text would
// leak into a header (exception handler); stop() waits on idle keep-alive connections (bounded
// keep-alive timeout); SO_REUSEPORT is on by default (own socket options); mounted files are
// read whole into memory (downloads use content providers).

#include <atomic>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "api/problem.h"
#include "server/config.h"
#include "server/engine.h"
#include "server/job_service.h"
#include "server/log.h"
#include "server/service_metrics.h"

namespace httplib {
class Server;
class ContentReader;
struct Request;
struct Response;
}  // namespace httplib

namespace hexcover::server {

/// A route the server answers: method and path template ("/v1/jobs/{id}").
struct Route {
  std::string method;
  std::string path;
};

class HttpServer {
 public:
  HttpServer(const ServerConfig& config, JobService& jobs, const Engine& engine,
             ServiceMetrics& metrics, const Log& log);
  ~HttpServer();
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  /// Binds config.host:config.port (port 0: any free one) and returns the port.
  /// Throws std::runtime_error when the address is taken or invalid.
  int bind();
  /// Serves until stop(); call from its own thread after bind().
  void run();
  /// Stops accepting and closes connections (waits at most the keep-alive timeout).
  void stop();
  bool running() const;

  /// /readyz answers 200 only while ready (after start-up, before draining).
  void setReady(bool ready) { ready_ = ready; }
  bool ready() const { return ready_; }

  /// Every route the server answers (the OpenAPI document must describe each).
  static const std::vector<Route>& routes();

 private:
  void installRoutes();
  /// Why an upload must be refused from its headers alone, if it must.
  std::optional<api::ApiError> uploadRefusal(const httplib::Request& req) const;
  /// POST /v1/jobs: streams the body to disk, validates, submits, answers 202.
  void receiveUpload(const httplib::Request& req, httplib::Response& res,
                     const httplib::ContentReader& reader);
  const ServerConfig& config_;
  JobService& jobs_;
  const Engine& engine_;
  ServiceMetrics& metrics_;
  const Log& log_;
  std::unique_ptr<httplib::Server> server_;
  std::atomic<bool> ready_{false};
};

}  // namespace hexcover::server
