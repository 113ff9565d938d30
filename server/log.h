#pragma once
// Structured logs: one JSON object per line on stdout ({"time", "level", "event", ...fields}),
// built with nlohmann/json (spdlog neither formats JSON nor escapes messages) and written through
// an spdlog sink, which serializes concurrent writers.

#include <memory>
#include <nlohmann/json.hpp>
#include <string_view>

namespace spdlog {
class logger;
}

namespace hexcover::server {

class Log {
 public:
  /// Logs to stdout, flushing every record (so a supervisor or a test sees it at once).
  Log();
  /// Logs to an existing spdlog logger (tests may pass one with a memory sink).
  explicit Log(std::shared_ptr<spdlog::logger> logger);

  /// Writes {"time", "level", "event", ...fields}. `fields` must be an object (or null).
  void info(std::string_view event, const nlohmann::json& fields = nullptr) const;
  void warn(std::string_view event, const nlohmann::json& fields = nullptr) const;
  void error(std::string_view event, const nlohmann::json& fields = nullptr) const;

 private:
  void write(int level, std::string_view event, const nlohmann::json& fields) const;
  std::shared_ptr<spdlog::logger> logger_;
};

}  // namespace hexcover::server
