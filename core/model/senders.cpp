#include "model/senders.hpp"

#include "model/messages.hpp"

namespace fleet::model {

SenderVerdict judge_sender(const std::vector<std::string>& writer_partitions, const std::string& robot_id,
                           bool secured) {
  const bool in_default = writer_partitions.empty() || (writer_partitions.size() == 1 && writer_partitions[0].empty());
  if (in_default) return secured ? SenderVerdict::kOutsideAnyPartition : SenderVerdict::kAccepted;
  if (writer_partitions.size() == 1 && writer_partitions[0] == robot_partition(robot_id)) {
    return SenderVerdict::kAccepted;
  }
  return SenderVerdict::kAnotherRobotsName;
}

const char* to_string(SenderVerdict verdict) {
  switch (verdict) {
    case SenderVerdict::kAccepted:
      return "accepted";
    case SenderVerdict::kAnotherRobotsName:
      return "names a robot other than the one whose partition it writes in";
    case SenderVerdict::kOutsideAnyPartition:
      return "comes from outside every robot's partition on a domain with DDS Security";
  }
  return "?";
}

}  // namespace fleet::model
