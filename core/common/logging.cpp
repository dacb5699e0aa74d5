#include "common/logging.hpp"

#include <spdlog/sinks/stdout_sinks.h>

namespace fleet {

Logger make_logger(const std::string& process, const std::string& robot_id, spdlog::level::level_enum level) {
  auto sink = std::make_shared<spdlog::sinks::stderr_sink_mt>();
  const std::string name = robot_id.empty() ? process : process + " " + robot_id;
  auto logger = std::make_shared<spdlog::logger>(name, sink);
  logger->set_pattern("%Y-%m-%d %H:%M:%S.%e [%n] %l: %v");
  logger->set_level(level);
  logger->flush_on(spdlog::level::info);
  return logger;
}

}  // namespace fleet
