#pragma once

#include <map>
#include <string>

#include "common/logging.hpp"
#include "dds/participant.hpp"
#include "dds/topics.hpp"

namespace fleet::server {

/// TrafficGrants out to the agents, each into its robot's own partition: written when a grant
/// changed, and repeated now and then for an agent that (re)started.
class GrantPublisher {
 public:
  GrantPublisher(dds::Participant& participant, Logger log);

  /// Opens the writer of a robot's grants ahead of its first grant, so that its reader has matched.
  void open(const std::string& robot_id);
  void publish(model::TrafficGrant grant, double now_wall);
  /// The next grant of the robot goes out even if unchanged (it is back after being lost).
  void forget(const std::string& robot_id) { sent_.erase(robot_id); }

 private:
  Logger log_;
  std::map<std::string, model::TrafficGrant> sent_;
  std::map<std::string, double> sent_wall_;
  dds::PartitionWriters<model::TrafficGrant> writers_;
};

}  // namespace fleet::server
