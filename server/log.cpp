#include "server/log.h"

#include <spdlog/sinks/stdout_sinks.h>
#include <spdlog/spdlog.h>

#include <chrono>

#include "api/job_json.h"

namespace hexcover::server {

namespace {

std::shared_ptr<spdlog::logger> stdoutLogger() {
  auto logger = std::make_shared<spdlog::logger>("hexcover-server",
                                                 std::make_shared<spdlog::sinks::stdout_sink_mt>());
  logger->set_pattern("%v");
  logger->set_level(spdlog::level::info);
  logger->flush_on(spdlog::level::info);
  return logger;
}

}  // namespace

Log::Log() : logger_(stdoutLogger()) {}
Log::Log(std::shared_ptr<spdlog::logger> logger) : logger_(std::move(logger)) {}

void Log::info(std::string_view event, const nlohmann::json& fields) const {
  write(spdlog::level::info, event, fields);
}
void Log::warn(std::string_view event, const nlohmann::json& fields) const {
  write(spdlog::level::warn, event, fields);
}
void Log::error(std::string_view event, const nlohmann::json& fields) const {
  write(spdlog::level::err, event, fields);
}

void Log::write(int level, std::string_view event, const nlohmann::json& fields) const {
  const auto lvl = static_cast<spdlog::level::level_enum>(level);
  if (!logger_->should_log(lvl)) return;
  const double now =
      std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
  nlohmann::json record = {{"time", api::rfc3339(now)},
                           {"level", spdlog::level::to_string_view(lvl).data()},
                           {"event", event}};
  if (fields.is_object()) record.update(fields);
  const std::string line = record.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  logger_->log(lvl, spdlog::string_view_t(line.data(), line.size()));
}

}  // namespace hexcover::server
