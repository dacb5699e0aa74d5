#pragma once

#include <dds/dds.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "common/log_limiter.hpp"
#include "dds/participant.hpp"

namespace fleet::server {

/// The server's door for the robots' own messages (RobotState, RobotPath, OrderState,
/// TrafficRequest, SimTruth): a sample is taken only from a writer that may speak for the robot
/// it names, judged by the writer's DDS partitions (model::judge_sender). Each refused writer is
/// logged once and each refused sample counted. The warnings a bad sample gives (a pose that is
/// not a number, an unknown robot) are rate-limited per writer: a writer sending one at 20 Hz
/// gives a line every ten seconds, with the count of those held back.
class SenderGate {
 public:
  SenderGate(bool secured, std::shared_ptr<spdlog::logger> log);

  /// Whether the sample `info`, taken by `reader` of `topic` and naming `robot_id`, is admitted.
  /// A sample without data (its writer gone) is admitted unless its writer was refused before.
  bool admit(dds_entity_t reader, const dds::SampleInfo& info, const std::string& robot_id, const char* topic);
  /// Logs `message` as a warning of the kind `what` about the sample's writer, rate-limited.
  void warn(const dds::SampleInfo& info, const std::string& what, const std::string& message);

  /// Samples refused so far.
  std::int64_t refused() const { return refused_; }
  /// Each refused writer once: what it wrote and in which partitions.
  const std::vector<std::string>& refused_senders() const { return senders_; }
  /// Whether the refusals changed since the last call that said so, at most once a second: the
  /// server publishes them in its ServerInfo then.
  bool take_change();

 private:
  double now_s() const;

  bool secured_;
  std::shared_ptr<spdlog::logger> log_;
  LogLimiter limiter_;
  std::map<dds_instance_handle_t, std::vector<std::string>> partitions_;  ///< per writer seen
  std::set<std::pair<dds_instance_handle_t, std::string>> logged_;        ///< (writer, topic) refused and logged
  std::vector<std::string> senders_;
  std::int64_t refused_ = 0;
  bool changed_ = false;
  double last_change_s_ = -1e9;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace fleet::server
