#pragma once

// The topics of ARCHITECTURE.md, one per core/model type.

#include "dds/participant.hpp"
#include "model/messages.hpp"

#define FLEET_DDS_TOPIC(Type)                                                                              \
  template <>                                                                                              \
  struct TopicTraits<model::Type> {                                                                        \
    static const char* const name;                                                                         \
    static const dds_topic_descriptor_t* descriptor();                                                     \
    static dds_return_t write(dds_entity_t writer, const model::Type& value);                              \
    static dds_return_t unregister(dds_entity_t writer, const model::Type& value);                         \
    static dds_return_t dispose(dds_entity_t writer, const model::Type& value);                            \
    static int take(dds_entity_t reader, const std::function<void(model::Type&&, const SampleInfo&)>& fn); \
    static dds_return_t key_of(dds_entity_t entity, dds_instance_handle_t instance, model::Type& out);     \
  };

namespace fleet::dds {

/// Where the robots' own messages (RobotState, RobotPath, OrderState, TrafficRequest,
/// TrafficProgress, SimTruth) are read: each agent writes them in its robot's partition
/// (model::robot_partition), so that DDS Security can grant a robot its own partition alone; the
/// VDA 5050 bridge and the emulated robots of `fleetctl load`, which speak for many robots from one
/// participant, write them in the default partition.
inline std::vector<std::string> robot_report_partitions() {
  return {"", model::every_robot_partition()};
}

FLEET_DDS_TOPIC(ServerInfo)
FLEET_DDS_TOPIC(OrderRequest)
FLEET_DDS_TOPIC(Command)
FLEET_DDS_TOPIC(RequestReply)
FLEET_DDS_TOPIC(OrderAssignment)
FLEET_DDS_TOPIC(OrderReport)
FLEET_DDS_TOPIC(OrderInfo)
FLEET_DDS_TOPIC(OrderHandover)
FLEET_DDS_TOPIC(RobotState)
FLEET_DDS_TOPIC(RobotPath)
FLEET_DDS_TOPIC(MapAssignment)
FLEET_DDS_TOPIC(RobotControl)
FLEET_DDS_TOPIC(PalletTruth)
FLEET_DDS_TOPIC(StaticObstacleState)
FLEET_DDS_TOPIC(FleetView)
FLEET_DDS_TOPIC(NeighbourView)
FLEET_DDS_TOPIC(SimTruth)
FLEET_DDS_TOPIC(TrafficRequest)
FLEET_DDS_TOPIC(TrafficProgress)
FLEET_DDS_TOPIC(TrafficGrant)
FLEET_DDS_TOPIC(ServerLoad)
FLEET_DDS_TOPIC(SiteStateDocument)

}  // namespace fleet::dds

#undef FLEET_DDS_TOPIC
