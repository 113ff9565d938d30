#include "server/http_server.h"

#include <httplib.h>
#include <sys/socket.h>

#include <charconv>
#include <chrono>
#include <fstream>
#include <random>
#include <regex>

#include "api/job_json.h"
#include "api/option_names.h"
#include "api/problem.h"
#include "server/openapi_document.h"
#include "server/upload.h"
#include "server/web_assets.h"

namespace hexcover::server {

using api::ApiError;
using api::ProblemKind;
using httplib::Request;
using httplib::Response;

namespace {

/// Bytes read and thrown away after a refused upload, so that the client still sees the answer
/// (closing a socket with unread data resets the connection); larger bodies are cut off.
constexpr std::uint64_t kDrainBytes = 8ull << 20;
/// Largest `options` part of a multipart upload.
constexpr std::size_t kMaxOptionsBytes = 64 << 10;
/// Largest body accepted on routes that take none.
constexpr std::size_t kMaxOtherBody = 64 << 10;

constexpr const char* kResultFormats[] = {"obj", "ply", "off", "stl", "glb"};
constexpr const char* kResultMeshes[] = {"triangles", "quads", "hexagons", "textured"};

struct RouteSpec {
  Route route;
  std::string regex;  ///< the httplib pattern
  std::regex pattern;
};

const std::vector<RouteSpec>& routeSpecs() {
  static const std::vector<RouteSpec> specs = [] {
    std::vector<RouteSpec> s;
    const auto add = [&](const char* method, const char* path, const char* regex) {
      s.push_back({{method, path}, regex, std::regex(regex)});
    };
    add("GET", "/livez", "/livez");
    add("GET", "/readyz", "/readyz");
    add("GET", "/metrics", "/metrics");
    add("GET", "/v1/openapi.json", "/v1/openapi\\.json");
    add("POST", "/v1/jobs", "/v1/jobs");
    add("GET", "/v1/jobs", "/v1/jobs");
    add("GET", "/v1/jobs/{id}", "/v1/jobs/([^/]+)");
    add("DELETE", "/v1/jobs/{id}", "/v1/jobs/([^/]+)");
    add("GET", "/v1/jobs/{id}/metrics", "/v1/jobs/([^/]+)/metrics");
    add("GET", "/v1/jobs/{id}/result", "/v1/jobs/([^/]+)/result");
    return s;
  }();
  return specs;
}

/// The httplib pattern of a route template.
const std::string& patternOf(const std::string& method, const std::string& path) {
  for (const auto& spec : routeSpecs())
    if (spec.route.method == method && spec.route.path == path) return spec.regex;
  throw std::logic_error("no route " + method + " " + path);
}

/// Methods of the routes whose path matches `path` (for 405 and its Allow header).
std::vector<std::string> methodsFor(const std::string& path) {
  std::vector<std::string> methods;
  for (const auto& spec : routeSpecs())
    if (std::regex_match(path, spec.pattern)) methods.push_back(spec.route.method);
  return methods;
}

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void sendJson(Response& res, int status, const nlohmann::json& body) {
  res.status = status;
  res.set_content(body.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace),
                  "application/json");
}

void sendProblem(Response& res, const nlohmann::json& problem) {
  res.status = problem.value("status", 500);
  res.set_content(problem.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace),
                  api::kProblemMediaType);
}

void sendProblem(Response& res, ProblemKind kind, const std::string& detail,
                 const nlohmann::json& extensions = nlohmann::json::object()) {
  sendProblem(res, api::problemDocument(kind, detail, extensions));
  if (kind == ProblemKind::QueueFull || kind == ProblemKind::Unavailable)
    res.set_header("Retry-After", "5");
}

/// 64-bit FNV-1a, for weak ETags.
std::string fnv1a(const std::string& text) {
  std::uint64_t hash = 1469598103934665603ull;
  for (const unsigned char c : text) hash = (hash ^ c) * 1099511628211ull;
  char out[17];
  std::snprintf(out, sizeof out, "%016llx", static_cast<unsigned long long>(hash));
  return out;
}

std::string randomName() {
  std::random_device device;
  char name[24];
  std::snprintf(name, sizeof name, "%08x%08x", device(), device());
  return name;
}

/// A query value as JSON: a number when the whole text is one, else the text.
nlohmann::json queryValue(const std::string& text) {
  long long integer = 0;
  if (const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), integer);
      ec == std::errc() && end == text.data() + text.size())
    return integer;
  char* end = nullptr;
  const double number = std::strtod(text.c_str(), &end);
  if (!text.empty() && end == text.c_str() + text.size()) return number;
  return text;
}

/// Options given as query parameters of POST /v1/jobs. Throws ApiError naming an unknown one.
nlohmann::json queryOptions(const Request& req) {
  nlohmann::json options = nlohmann::json::object();
  for (const auto& [name, value] : req.params) {
    if (std::find(api::kOptionNames.begin(), api::kOptionNames.end(), name) ==
        api::kOptionNames.end())
      throw ApiError(ProblemKind::InvalidOption,
                     "unknown query parameter '" + name +
                         "'; the options are " + api::optionNameList(),
                     {{"option", name}});
    if (options.contains(name))
      throw ApiError(ProblemKind::InvalidOption, "query parameter '" + name + "' is given twice",
                     {{"option", name}});
    options[name] = queryValue(value);
  }
  return options;
}

/// Parses a non-negative integer query parameter in [min, max]; throws ApiError naming it.
std::int64_t integerParameter(const Request& req, const std::string& name, std::int64_t fallback,
                              std::int64_t min, std::int64_t max) {
  if (!req.has_param(name)) return fallback;
  const std::string text = req.get_param_value(name);
  std::int64_t value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || value < min || value > max)
    throw ApiError(ProblemKind::InvalidOption,
                   "query parameter '" + name + "' must be an integer in [" + std::to_string(min) +
                       ", " + std::to_string(max) + "], not '" + text + "'",
                   {{"option", name}});
  return value;
}

const char* mediaTypeOf(const std::string& format) {
  if (format == "obj") return "model/obj";
  if (format == "stl") return "model/stl";
  if (format == "glb") return "model/gltf-binary";
  return "application/octet-stream";  // PLY and OFF have no registered media type
}

/// Converts a failure inside a handler to a problem document.
void sendFailure(Response& res, const Log& log, const Request& req) {
  try {
    throw;
  } catch (const ApiError& e) {
    sendProblem(res, e.kind(), e.what(), e.extensions());
  } catch (const Error& e) {
    sendProblem(res, api::problemDocument(e));
  } catch (const std::exception& e) {
    log.error("request_failed", {{"method", req.method}, {"path", req.path}, {"error", e.what()}});
    sendProblem(res, ProblemKind::Internal, "");
  }
}

/// httplib::Server with a larger listen backlog: 0.11.4 listens with a backlog of 5, so a burst
/// of new connections (100 pollers) overflows it and clients wait for SYN retransmission (1 s,
/// then 3 s). Calling listen() again on the bound socket raises the backlog.
class BackloggedServer final : public httplib::Server {
 public:
  bool raiseBacklog(int backlog) { return ::listen(svr_sock_, backlog) == 0; }
};

constexpr int kListenBacklog = 1024;

}  // namespace

const std::vector<Route>& HttpServer::routes() {
  static const std::vector<Route> list = [] {
    std::vector<Route> r;
    for (const auto& spec : routeSpecs()) r.push_back(spec.route);
    return r;
  }();
  return list;
}

HttpServer::HttpServer(const ServerConfig& config, JobService& jobs, const Engine& engine,
                       ServiceMetrics& metrics, const Log& log)
    : config_(config),
      jobs_(jobs),
      engine_(engine),
      metrics_(metrics),
      log_(log),
      server_(std::make_unique<BackloggedServer>()) {
  installRoutes();
}

HttpServer::~HttpServer() = default;

int HttpServer::bind() {
  const int port = config_.port == 0
                       ? server_->bind_to_any_port(config_.host)
                       : (server_->bind_to_port(config_.host, config_.port) ? config_.port : -1);
  if (port <= 0)
    throw std::runtime_error("cannot listen on " + config_.host + ":" +
                             std::to_string(config_.port) + " (address in use or invalid)");
  if (!static_cast<BackloggedServer&>(*server_).raiseBacklog(kListenBacklog))
    log_.warn("listen_backlog", {{"error", "cannot raise the listen backlog"}});
  return port;
}

void HttpServer::run() { server_->listen_after_bind(); }
void HttpServer::stop() { server_->stop(); }
bool HttpServer::running() const { return server_->is_running(); }

// Refusals of an upload that need only its headers: draining, encodings, size, queue bound,
// query options. Used before the body is sent (Expect: 100-continue) and by the handler.
std::optional<ApiError> HttpServer::uploadRefusal(const Request& req) const {
  if (!ready_ || jobs_.draining())
    return ApiError(ProblemKind::Unavailable, "the server is not accepting jobs now; retry later");
  const std::string encoding = req.get_header_value("Content-Encoding");
  if (!encoding.empty() && encoding != "identity")
    return ApiError(
        ProblemKind::UnsupportedMediaType,
        "Content-Encoding '" + encoding + "' is not accepted; send the mesh uncompressed",
        {{"header", "Content-Encoding"}});
  if (req.has_header("Content-Length") &&
      req.get_header_value<std::uint64_t>("Content-Length") > config_.maxUploadBytes)
    return ApiError(ProblemKind::PayloadTooLarge,
                    "the upload of " + req.get_header_value("Content-Length") +
                        " bytes is over the limit of " + std::to_string(config_.maxUploadBytes) +
                        " bytes",
                    {{"limit_bytes", config_.maxUploadBytes}});
  if (jobs_.queueFull())
    return ApiError(ProblemKind::QueueFull, "the job queue is full; retry later");
  try {
    engine_.normalizeOptions(queryOptions(req));
  } catch (const ApiError& e) {
    return e;
  } catch (const Error& e) {
    return ApiError(api::problemKindFor(e.code()), e.what());
  }
  return std::nullopt;
}

void HttpServer::installRoutes() {
  httplib::Server& svr = *server_;
  const int threads = config_.httpThreads;
  svr.new_task_queue = [threads] { return new httplib::ThreadPool(std::size_t(threads)); };
  svr.set_socket_options([](socket_t sock) {  // SO_REUSEADDR only: no silent port sharing
    const int yes = 1;
    setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
  svr.set_keep_alive_timeout(config_.keepAliveSeconds);
  svr.set_keep_alive_max_count(1000);
  svr.set_read_timeout(30);
  svr.set_write_timeout(30);
  // The library's own check, against Content-Length only; uploads are counted by us as well.
  svr.set_payload_max_length(std::size_t(config_.maxUploadBytes + kDrainBytes));

  svr.set_expect_100_continue_handler([this](const Request& req, Response& res) {
    if (req.method == "POST" && req.path == "/v1/jobs")
      if (const auto refusal = uploadRefusal(req)) {
        sendProblem(res, refusal->kind(), refusal->what(), refusal->extensions());
        res.set_header("Connection", "close");
        metrics_.recordRequest("/v1/jobs", "POST", res.status, 0.0);
        return res.status;
      }
    return 100;
  });

  // Bodies on routes that take none are small; refuse big or chunked ones before they are read.
  svr.set_pre_routing_handler([this](const Request& req, Response& res) {
    if (req.method == "POST" || req.method == "OPTIONS")
      return httplib::Server::HandlerResponse::Unhandled;
    const bool chunked =
        req.get_header_value("Transfer-Encoding").find("chunked") != std::string::npos;
    if (chunked || (req.has_header("Content-Length") &&
                    req.get_header_value<std::uint64_t>("Content-Length") > kMaxOtherBody)) {
      sendProblem(res, ProblemKind::PayloadTooLarge,
                  req.method + " " + req.path + " takes no body");
      res.set_header("Connection", "close");
      metrics_.recordRequest("unmatched", req.method, res.status, 0.0);
      return httplib::Server::HandlerResponse::Handled;
    }
    return httplib::Server::HandlerResponse::Unhandled;
  });

  // CORS on every response; preflight answered for every path.
  svr.set_post_routing_handler([this](const Request& req, Response& res) {
    const std::string origin = req.get_header_value("Origin");
    if (origin.empty()) return;
    const auto& allowed = config_.corsOrigins;
    const bool any = std::find(allowed.begin(), allowed.end(), "*") != allowed.end();
    if (!any && std::find(allowed.begin(), allowed.end(), origin) == allowed.end()) return;
    res.set_header("Access-Control-Allow-Origin", any ? "*" : origin);
    if (!any) res.set_header("Vary", "Origin");
    res.set_header("Access-Control-Expose-Headers",
                   "Location, ETag, Retry-After, Link, Content-Disposition, Idempotent-Replayed");
  });
  svr.Options(".*", [](const Request& req, Response& res) {
    res.status = 204;
    res.set_header("Access-Control-Allow-Methods", "GET, POST, DELETE, OPTIONS");
    res.set_header("Access-Control-Allow-Headers",
                   "Content-Type, Idempotency-Key, If-None-Match, Accept");
    res.set_header("Access-Control-Max-Age", "600");
  });

  // Responses the library made itself (no route, or a failure before a handler ran).
  svr.set_error_handler([this](const Request& req, Response& res) {
    if (!res.body.empty()) return;  // already a problem document from a handler
    if (res.status == 404) {
      const auto methods = methodsFor(req.path);
      if (!methods.empty()) {
        std::string allow;
        for (const auto& m : methods) allow += (allow.empty() ? "" : ", ") + m;
        res.set_header("Allow", allow);
        sendProblem(res, ProblemKind::MethodNotAllowed,
                    req.method + " is not allowed on " + req.path + "; allowed: " + allow);
      } else {
        sendProblem(res, ProblemKind::NotFound, "no resource at " + req.path);
      }
    } else if (res.status == 413) {
      sendProblem(res, ProblemKind::PayloadTooLarge, "the request body is over the limit");
    } else if (res.status >= 500) {
      sendProblem(res, ProblemKind::Internal, "");
    } else {
      sendProblem(res, ProblemKind::BadRequest, "the request could not be read");
    }
    metrics_.recordRequest("unmatched", req.method, res.status, 0.0);
  });
  svr.set_exception_handler([this](const Request& req, Response& res, std::exception_ptr ep) {
    try {
      std::rethrow_exception(ep);
    } catch (...) {
      sendFailure(res, log_, req);
    }
  });

  // Wraps a handler: failures become problem documents, every answer is counted and timed.
  const auto handle = [this](const char* method, const char* path, auto body) {
    return [this, method, path, body](const Request& req, Response& res) {
      const auto start = std::chrono::steady_clock::now();
      try {
        body(req, res);
      } catch (...) {
        sendFailure(res, log_, req);
      }
      metrics_.recordRequest(path, method, res.status, secondsSince(start));
    };
  };

  svr.Get("/livez", handle("GET", "/livez", [](const Request&, Response& res) {
            sendJson(res, 200, {{"status", "alive"}});
          }));

  svr.Get("/readyz", handle("GET", "/readyz", [this](const Request&, Response& res) {
            if (ready_ && !jobs_.draining())
              sendJson(res, 200, {{"status", "ready"}});
            else
              sendProblem(res, ProblemKind::Unavailable, "the server is starting or draining");
          }));

  svr.Get("/metrics", handle("GET", "/metrics", [this](const Request&, Response& res) {
            auto gauges = jobs_.gauges();
            gauges.ready = ready_ && !jobs_.draining();
            res.status = 200;
            res.set_content(metrics_.exposition(gauges),
                            "text/plain; version=0.0.4; charset=utf-8");
          }));

  svr.Get(patternOf("GET", "/v1/openapi.json"),
          handle("GET", "/v1/openapi.json", [](const Request&, Response& res) {
            res.status = 200;
            const auto doc = openApiDocument();
            res.set_content(doc.data(), doc.size(), "application/json");
          }));

  svr.Post("/v1/jobs",
           [this](const Request& req, Response& res, const httplib::ContentReader& reader) {
             const auto start = std::chrono::steady_clock::now();
             try {
               receiveUpload(req, res, reader);
             } catch (...) {
               sendFailure(res, log_, req);
               res.set_header("Connection", "close");
             }
             metrics_.recordRequest("/v1/jobs", "POST", res.status, secondsSince(start));
           });

  svr.Get("/v1/jobs", handle("GET", "/v1/jobs", [this](const Request& req, Response& res) {
            std::optional<api::JobState> state;
            if (req.has_param("state")) {
              state = api::parseJobState(req.get_param_value("state"));
              if (!state)
                throw ApiError(ProblemKind::InvalidOption,
                               "query parameter 'state' must be one of queued, running, succeeded, "
                               "failed, canceled",
                               {{"option", "state"}});
            }
            const auto limit = integerParameter(req, "limit", 50, 1, 1000);
            const auto cursor = integerParameter(req, "cursor", INT64_MAX, 1, INT64_MAX);
            const auto page = jobs_.list(state, cursor, std::size_t(limit));
            nlohmann::json list = nlohmann::json::array();
            for (const auto& job : page.jobs) list.push_back(api::jobSummary(job));
            nlohmann::json doc = {
                {"jobs", list}, {"next_cursor", nullptr}, {"links", nlohmann::json::object()}};
            if (page.nextCursor) {
              std::string next = "/v1/jobs?limit=" + std::to_string(limit) +
                                 "&cursor=" + std::to_string(*page.nextCursor);
              if (state) next += std::string("&state=") + api::jobStateName(*state);
              doc["next_cursor"] = std::to_string(*page.nextCursor);
              doc["links"]["next"] = next;
              res.set_header("Link", "<" + next + ">; rel=\"next\"");
            }
            sendJson(res, 200, doc);
          }));

  svr.Get(patternOf("GET", "/v1/jobs/{id}"),
          handle("GET", "/v1/jobs/{id}", [this](const Request& req, Response& res) {
            const std::string id = req.matches[1];
            const auto view = jobs_.find(id);
            if (!view) throw ApiError(ProblemKind::NotFound, "no job " + id);
            nlohmann::json doc = api::jobDocument(view->job, view->queuePosition, unixNow());
            nlohmann::json stable = doc;
            stable.erase("timings");  // moves with the clock, not with the job
            const std::string etag = "W/\"" + fnv1a(stable.dump()) + "\"";
            res.set_header("ETag", etag);
            res.set_header("Cache-Control", "no-cache");
            if (!api::isFinished(view->job.state)) res.set_header("Retry-After", "1");
            if (req.get_header_value("If-None-Match") == etag) {
              res.status = 304;
              return;
            }
            sendJson(res, 200, doc);
          }));

  svr.Delete(patternOf("DELETE", "/v1/jobs/{id}"),
             handle("DELETE", "/v1/jobs/{id}", [this](const Request& req, Response& res) {
               const std::string id = req.matches[1];
               switch (jobs_.cancelOrDelete(id)) {
                 case JobService::Removal::NotFound:
                   throw ApiError(ProblemKind::NotFound, "no job " + id);
                 case JobService::Removal::Deleted:
                   res.status = 204;
                   return;
                 case JobService::Removal::Canceled:
                 case JobService::Removal::CancelRequested: {
                   const auto view = jobs_.find(id);
                   if (!view) {
                     res.status = 204;
                     return;
                   }
                   const bool stopping = view->job.state == api::JobState::Running;
                   sendJson(res, stopping ? 202 : 200,
                            api::jobDocument(view->job, view->queuePosition, unixNow()));
                 }
               }
             }));

  // A job's results exist only once it succeeded: other states answer 409 (with the job's
  // problem document when it failed).
  const auto succeededJob = [this](const std::string& id) {
    auto view = jobs_.find(id);
    if (!view) throw ApiError(ProblemKind::NotFound, "no job " + id);
    if (view->job.state != api::JobState::Succeeded) {
      nlohmann::json extensions = {{"state", api::jobStateName(view->job.state)}};
      if (!view->job.error.is_null()) extensions["error"] = view->job.error;
      throw ApiError(ProblemKind::Conflict,
                     std::string("job ") + id + " is " + api::jobStateName(view->job.state) +
                         "; results exist only for succeeded jobs",
                     extensions);
    }
    return std::move(view->job);
  };

  svr.Get(patternOf("GET", "/v1/jobs/{id}/metrics"),
          handle("GET", "/v1/jobs/{id}/metrics", [succeededJob](const Request& req, Response& res) {
            const auto job = succeededJob(req.matches[1]);
            sendJson(res, 200, job.metrics);
          }));

  svr.Get(
      patternOf("GET", "/v1/jobs/{id}/result"),
      handle(
          "GET", "/v1/jobs/{id}/result", [this, succeededJob](const Request& req, Response& res) {
            const std::string format =
                req.has_param("format") ? req.get_param_value("format") : "obj";
            const std::string mesh =
                req.has_param("mesh") ? req.get_param_value("mesh") : "triangles";
            if (std::find(std::begin(kResultFormats), std::end(kResultFormats), format) ==
                std::end(kResultFormats))
              throw ApiError(ProblemKind::InvalidOption,
                             "query parameter 'format' must be obj, ply, off, stl or glb, not '" +
                                 format + "'",
                             {{"option", "format"}});
            if (std::find(std::begin(kResultMeshes), std::end(kResultMeshes), mesh) ==
                std::end(kResultMeshes))
              throw ApiError(
                  ProblemKind::InvalidOption,
                  "query parameter 'mesh' must be triangles, quads, hexagons or textured, not '" +
                      mesh + "'",
                  {{"option", "mesh"}});
            const auto job = succeededJob(req.matches[1]);
            const api::ResultFile* result = api::findResult(job, mesh, format);
            if (!result) {
              std::string available;
              for (const auto& r : job.results)
                if (r.mesh == mesh) available += (available.empty() ? "" : ", ") + r.format;
              throw ApiError(ProblemKind::NotFound, "the " + mesh + " mesh is not available as " +
                                                        format + "; available formats: " +
                                                        (available.empty() ? "none" : available));
            }
            const auto path = jobs_.jobDir(job.id) / "results" / result->file;
            auto file = std::make_shared<std::ifstream>(path, std::ios::binary);
            if (!*file) throw std::runtime_error("result file missing: " + path.string());
            const auto size = std::filesystem::file_size(path);
            res.status = 200;
            res.set_header("Content-Disposition",
                           "attachment; filename=\"" + job.id + "-" + mesh + "." + format + "\"");
            res.set_header("ETag", "\"" + job.id + "-" + mesh + "-" + format + "\"");
            res.set_content_provider(
                std::size_t(size), mediaTypeOf(format),
                [file](std::size_t offset, std::size_t length, httplib::DataSink& sink) {
                  char buffer[64 << 10];
                  file->seekg(std::streamoff(offset));
                  file->read(buffer, std::streamsize(std::min(length, sizeof buffer)));
                  const auto got = file->gcount();
                  return got > 0 && sink.write(buffer, std::size_t(got));
                });
          }));

  // The web front-end at `/`, after the API so that its routes never shadow one.
  mountWebAssets(svr, config_.webRoot.empty() ? defaultWebRoot() : config_.webRoot);
}

}  // namespace hexcover::server

namespace hexcover::server {

void HttpServer::receiveUpload(const Request& req, Response& res,
                               const httplib::ContentReader& reader) {
  // A refusal before the body is read drains a small body (so that the client, still sending,
  // sees the answer) and closes the connection (so that unread bytes are never parsed as a
  // next request).
  const auto closeWith = [&](const ApiError& error) {
    sendProblem(res, error.kind(), error.what(), error.extensions());
    res.set_header("Connection", "close");
  };
  const auto refuse = [&](const ApiError& error) {
    const std::uint64_t declared = req.has_header("Content-Length")
                                       ? req.get_header_value<std::uint64_t>("Content-Length")
                                       : 0;
    if (declared <= config_.maxUploadBytes + kDrainBytes) {
      std::uint64_t drained = 0;
      const auto discard = [&](const char*, std::size_t size) {
        drained += size;
        return drained <= kDrainBytes + declared;
      };
      if (req.is_multipart_form_data())
        reader([](const httplib::MultipartFormData&) { return true; }, discard);
      else
        reader(discard);
    }
    closeWith(error);
  };
  if (const auto refusal = uploadRefusal(req)) return refuse(*refusal);

  const std::string key = req.get_header_value("Idempotency-Key");
  if (key.size() > 200)
    return refuse(ApiError(ProblemKind::BadRequest, "the Idempotency-Key is over 200 characters",
                           {{"header", "Idempotency-Key"}}));
  if (!key.empty() && !jobs_.beginReceiving(key))
    return refuse(ApiError(ProblemKind::Conflict,
                           "a request with Idempotency-Key '" + key + "' is still being received",
                           {{"header", "Idempotency-Key"}}));
  struct Reservation {
    JobService& jobs;
    const std::string& key;
    ~Reservation() {
      if (!key.empty()) jobs.endReceiving(key);
    }
  } reservation{jobs_, key};

  // Receive: the mesh goes to a file, byte-counted whatever the framing; past the limit the
  // rest is read and dropped up to kDrainBytes so that the 413 reaches the client.
  UploadFile upload(jobs_.uploadDir() / (randomName() + ".part"), config_.maxUploadBytes);
  std::uint64_t received = 0;
  const std::uint64_t cutOff = config_.maxUploadBytes + kDrainBytes;
  std::string optionsText;
  std::string filename;
  bool multipartMesh = false;
  std::string part;
  std::optional<ApiError> partError;
  bool complete = false;
  if (req.is_multipart_form_data()) {
    complete = reader(
        [&](const httplib::MultipartFormData& header) {
          part = header.name;
          if (part == "mesh") {
            if (multipartMesh)
              partError = ApiError(ProblemKind::BadRequest, "the upload has two 'mesh' parts");
            multipartMesh = true;
            filename = header.filename;
          }
          return !partError;
        },
        [&](const char* data, std::size_t size) {
          received += size;
          if (received > config_.maxUploadBytes) return received <= cutOff;
          if (part == "mesh") return upload.append(data, size) || !upload.writeFailed();
          if (part == "options") {
            optionsText.append(data, size);
            if (optionsText.size() > kMaxOptionsBytes)
              partError = ApiError(
                  ProblemKind::BadRequest,
                  "the 'options' part is over " + std::to_string(kMaxOptionsBytes) + " bytes");
            return !partError;
          }
          return true;  // other parts are ignored (but counted)
        });
  } else {
    complete = reader([&](const char* data, std::size_t size) {
      received += size;
      if (received > config_.maxUploadBytes) return received <= cutOff;
      return upload.append(data, size) || !upload.writeFailed();
    });
  }
  upload.finish();

  // Layer 1: framing and limits.
  if (received > config_.maxUploadBytes)
    return closeWith(ApiError(
        ProblemKind::PayloadTooLarge,
        "the upload is over the limit of " + std::to_string(config_.maxUploadBytes) + " bytes",
        {{"limit_bytes", config_.maxUploadBytes}}));
  if (partError) return closeWith(*partError);
  if (upload.writeFailed())
    throw std::runtime_error("cannot write upload to " + upload.path().string());
  if (!complete)
    return closeWith(ApiError(ProblemKind::BadRequest, "the upload was interrupted or malformed"));
  if (req.is_multipart_form_data() && !multipartMesh)
    throw ApiError(ProblemKind::BadRequest,
                   "the multipart upload has no 'mesh' part; send the mesh file as the part named "
                   "'mesh'");
  if (upload.bytes() == 0)
    throw ApiError(ProblemKind::BadRequest, "the upload is empty; send a mesh file as the body");

  // Layer 2: options (query parameters and the `options` part), checked by the engine.
  nlohmann::json options = queryOptions(req);
  if (!optionsText.empty()) {
    nlohmann::json partOptions;
    try {
      partOptions = nlohmann::json::parse(optionsText);
    } catch (const nlohmann::json::parse_error& e) {
      throw ApiError(ProblemKind::InvalidOption,
                     std::string("the 'options' part is not valid JSON: ") + e.what(),
                     {{"option", "options"}, {"byte", e.byte}});
    }
    if (!partOptions.is_object())
      throw ApiError(ProblemKind::InvalidOption, "the 'options' part must be a JSON object",
                     {{"option", "options"}});
    for (const auto& [name, value] : partOptions.items()) {
      if (options.contains(name))
        throw ApiError(ProblemKind::InvalidOption,
                       "option '" + name + "' is given both as a query parameter and in 'options'",
                       {{"option", name}});
      options[name] = value;
    }
  }
  const nlohmann::json normalized = engine_.normalizeOptions(options);

  // Layer 3: the mesh format, from the bytes (Content-Type is not trusted).
  const std::string format = engine_.detectFormat(upload.head());

  Sha256 request;
  request.update(normalized.dump());
  request.update(upload.digest());
  Submission submission{upload.path(), format, filename,     upload.bytes(),
                        normalized,    key,    request.hex()};
  auto accepted = jobs_.submit(std::move(submission));
  upload.release();  // moved into the job, or removed by submit on refusal
  const auto view = jobs_.find(accepted.job.id);
  const nlohmann::json doc = view ? api::jobDocument(view->job, view->queuePosition, unixNow())
                                  : api::jobDocument(accepted.job, std::nullopt, unixNow());
  res.set_header("Location", api::jobPath(accepted.job.id));
  res.set_header("Retry-After", "1");
  if (accepted.replayed) res.set_header("Idempotent-Replayed", "true");
  sendJson(res, 202, doc);
}

}  // namespace hexcover::server
