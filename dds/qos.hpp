#pragma once

#include <dds/dds.h>

#include <string_view>

namespace fleet::dds {

/// An owned dds_qos_t.
class Qos {
 public:
  Qos() : qos_(dds_create_qos()) {}
  ~Qos() { dds_delete_qos(qos_); }
  Qos(const Qos& other) : qos_(dds_create_qos()) { dds_copy_qos(qos_, other.qos_); }
  Qos& operator=(const Qos& other) {
    if (this != &other) dds_copy_qos(qos_, other.qos_);
    return *this;
  }
  dds_qos_t* get() const { return qos_; }

 private:
  dds_qos_t* qos_;
};

/// The QoS classes of ARCHITECTURE.md, named once (STYLE.md 9). Every topic uses one of them.
namespace qos {

/// Latched state (MapAssignment, StaticObstacle, Order, OrderInfo, ServerInfo, RequestReply):
/// reliable, transient-local, keep-last 1 per key, so a late joiner gets the current value.
Qos latched_state();

/// Live state (RobotState, FleetView, SimTruth, RobotPath): reliable, volatile, keep-last 1 per
/// key: a slow reader skips to the newest value instead of queueing old poses. Writers assert
/// liveliness automatically with a 1 s lease so a dead publisher is noticed.
Qos live_state();

/// RobotState: live state with a 0.5 s deadline (wall time), so the server hears from DDS itself
/// when a robot stops publishing: half the 1 s lease, the robot is stalled before it is lost.
/// Agents publish at agent.state_hz x time_scale (at most 100 Hz): 2 Hz or more keeps within it.
Qos robot_state();

/// Requests (OrderRequest, Command, OrderState): reliable, volatile, keep-all bounded to 1000.
Qos requests();

/// Whether the server alone writes the topic (its orders, grants, views, the site's state): such
/// topics are created with exclusive ownership, so every reader and writer of them takes it from
/// the topic, and a reader takes each instance from its strongest live writer. Servers write with
/// a strength from their term (orders::strength, given to their dds::Participant): of an active
/// server and one that took over from it, the robots follow the one that took over.
bool server_owned(std::string_view topic_name);

/// The topic QoS of a server-owned topic: exclusive ownership.
Qos server_owned_topic();

}  // namespace qos
}  // namespace fleet::dds
