#include "dds/qos.hpp"

namespace fleet::dds::qos {

Qos latched_state() {
  Qos q;
  dds_qset_reliability(q.get(), DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
  dds_qset_durability(q.get(), DDS_DURABILITY_TRANSIENT_LOCAL);
  dds_qset_history(q.get(), DDS_HISTORY_KEEP_LAST, 1);
  return q;
}

Qos live_state() {
  Qos q;
  dds_qset_reliability(q.get(), DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
  dds_qset_durability(q.get(), DDS_DURABILITY_VOLATILE);
  dds_qset_history(q.get(), DDS_HISTORY_KEEP_LAST, 1);
  dds_qset_liveliness(q.get(), DDS_LIVELINESS_AUTOMATIC, DDS_SECS(1));
  return q;
}

Qos robot_state() {
  Qos q = live_state();
  dds_qset_deadline(q.get(), DDS_MSECS(500));
  return q;
}

bool server_owned(std::string_view topic_name) {
  static constexpr std::string_view kServerOwned[] = {
      "fleet/ServerInfo",    "fleet/RequestReply", "fleet/Order",         "fleet/OrderInfo",
      "fleet/MapAssignment", "fleet/RobotControl", "fleet/PalletTruth",   "fleet/StaticObstacles",
      "fleet/SiteState",     "fleet/FleetView",    "fleet/NeighbourView", "fleet/TrafficGrant"};
  for (const std::string_view name : kServerOwned) {
    if (name == topic_name) return true;
  }
  return false;
}

Qos server_owned_topic() {
  Qos q;
  dds_qset_ownership(q.get(), DDS_OWNERSHIP_EXCLUSIVE);
  return q;
}

Qos requests() {
  Qos q;
  dds_qset_reliability(q.get(), DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
  dds_qset_durability(q.get(), DDS_DURABILITY_VOLATILE);
  dds_qset_history(q.get(), DDS_HISTORY_KEEP_ALL, 0);
  dds_qset_resource_limits(q.get(), 1000, DDS_LENGTH_UNLIMITED, DDS_LENGTH_UNLIMITED);
  return q;
}

}  // namespace fleet::dds::qos
