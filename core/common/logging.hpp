#pragma once

#include <spdlog/spdlog.h>

#include <memory>
#include <string>

namespace fleet {

using Logger = std::shared_ptr<spdlog::logger>;

/// A logger writing one line per event to stderr, prefixed with the process and, for agents,
/// the robot id: `2026-11-21 17:34:31.123 [fleet-agent fl1] info: ...`. Not registered in
/// spdlog's global registry: loggers are passed in, never looked up.
Logger make_logger(const std::string& process, const std::string& robot_id = "",
                   spdlog::level::level_enum level = spdlog::level::info);

}  // namespace fleet
