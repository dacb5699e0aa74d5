#pragma once

#include <string>
#include <vector>

namespace fleet::model {

/// Whether a robot's own message (RobotState, RobotPath, OrderState, TrafficRequest, SimTruth)
/// may be taken from the writer that sent it, judged by the DDS partitions it writes in.
enum class SenderVerdict {
  kAccepted,
  kAnotherRobotsName,    ///< written in robot X's partition, naming robot Y
  kOutsideAnyPartition,  ///< written in the default partition on a domain with DDS Security
};

/// A writer in robot X's partition (robot_partition) speaks for X alone. A writer in the default
/// partition (fleet-vda5050 and the emulated robots of fleetctl load, which speak for many robots)
/// may name any robot, unless the domain is secured: there DDS access control grants each robot
/// its own partition and nothing else, so that partition is the writer's proven identity and a
/// message from anywhere else is refused.
SenderVerdict judge_sender(const std::vector<std::string>& writer_partitions, const std::string& robot_id,
                           bool secured);

/// What a verdict means, for a log line.
const char* to_string(SenderVerdict verdict);

}  // namespace fleet::model
