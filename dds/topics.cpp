#include "dds/topics.hpp"

#include <algorithm>
#include <deque>
#include <optional>

#include "fleet.h"
#include "model/names.hpp"

namespace fleet::dds {

namespace {

// --- to the wire: C structs borrow from the model value for the duration of one write ---------

char* borrow(const std::string& s) {
  return const_cast<char*>(s.c_str());
}

/// Owns the arrays a wire struct points into while it is written.
struct Scratch {
  std::deque<std::vector<char*>> strings;
  std::deque<std::vector<fleet_msg_Point2D>> points;
  std::deque<std::vector<fleet_msg_RobotSnapshot>> snapshots;
  std::deque<std::vector<fleet_msg_OrderEvent>> events;
  std::deque<std::vector<int32_t>> ints;
  std::deque<std::vector<fleet_msg_Pose2D>> poses;
  std::deque<std::vector<fleet_msg_SimTruth>> truths;
  std::deque<std::string> texts;

  /// A string made for the message, kept until it is written.
  char* text(std::string made) { return borrow(texts.emplace_back(std::move(made))); }

  dds_sequence_string string_seq(const std::vector<std::string>& items) {
    auto& buffer = strings.emplace_back();
    for (const auto& s : items) buffer.push_back(borrow(s));
    return {static_cast<uint32_t>(buffer.size()), static_cast<uint32_t>(buffer.size()), buffer.data(), false};
  }

  dds_sequence_fleet_msg_Point2D point_seq(const std::vector<geometry::Vec2>& items) {
    auto& buffer = points.emplace_back();
    for (const auto& p : items) buffer.push_back({p.x, p.y});
    return {static_cast<uint32_t>(buffer.size()), static_cast<uint32_t>(buffer.size()), buffer.data(), false};
  }

  /// An optional pose as a sequence of at most one.
  dds_sequence_fleet_msg_Pose2D pose_seq(const std::optional<geometry::Pose2>& item) {
    auto& buffer = poses.emplace_back();
    if (item) buffer.push_back({item->x, item->y, item->yaw});
    return {static_cast<uint32_t>(buffer.size()), static_cast<uint32_t>(buffer.size()), buffer.data(), false};
  }
};

dds_sequence_long int_seq(Scratch& s, const std::vector<int>& items) {
  auto& buffer = s.ints.emplace_back(items.begin(), items.end());
  return {static_cast<uint32_t>(buffer.size()), static_cast<uint32_t>(buffer.size()), buffer.data(), false};
}

fleet_msg_Pose2D wire_pose(const geometry::Pose2& p) {
  return {p.x, p.y, p.yaw};
}

// --- from the wire ---------------------------------------------------------------------------

std::string text(const char* s) {
  return s ? std::string(s) : std::string();
}

geometry::Pose2 model_pose(const fleet_msg_Pose2D& p) {
  return {p.x, p.y, p.yaw};
}

std::vector<std::string> strings_of(const dds_sequence_string& seq) {
  std::vector<std::string> out;
  out.reserve(seq._length);
  for (uint32_t i = 0; i < seq._length; ++i) out.push_back(text(seq._buffer[i]));
  return out;
}

std::vector<int> ints_of(const dds_sequence_long& seq) {
  return std::vector<int>(seq._buffer, seq._buffer + seq._length);
}

std::vector<geometry::Vec2> points_of(const dds_sequence_fleet_msg_Point2D& seq) {
  std::vector<geometry::Vec2> out;
  out.reserve(seq._length);
  for (uint32_t i = 0; i < seq._length; ++i) out.push_back({seq._buffer[i].x, seq._buffer[i].y});
  return out;
}

std::optional<geometry::Pose2> pose_of(const dds_sequence_fleet_msg_Pose2D& seq) {
  if (seq._length == 0) return std::nullopt;
  return model_pose(seq._buffer[0]);
}

template <typename Wire, typename Model, typename FromWire>
int take_samples(dds_entity_t reader, const std::function<void(Model&&, const SampleInfo&)>& fn, FromWire from_wire) {
  constexpr int kBatch = 64;
  int total = 0;
  for (;;) {
    void* samples[kBatch] = {nullptr};
    dds_sample_info_t infos[kBatch];
    const int n = dds_take(reader, samples, infos, kBatch, kBatch);
    if (n <= 0) break;
    for (int i = 0; i < n; ++i) {
      const SampleInfo info{infos[i].valid_data, infos[i].instance_state == DDS_IST_ALIVE, infos[i].source_timestamp,
                            infos[i].publication_handle};
      // Invalid samples carry only the key fields; the conversion tolerates empty strings.
      fn(from_wire(*static_cast<const Wire*>(samples[i])), info);
    }
    dds_return_loan(reader, samples, n);
    total += n;
    if (n < kBatch) break;
  }
  return total;
}

// --- per-type conversions ----------------------------------------------------------------------

fleet_msg_ServerInfo to_wire(const model::ServerInfo& v, Scratch& s) {
  return {borrow(v.server_id),
          borrow(v.site),
          s.string_seq(v.loading_areas),
          s.string_seq(v.robots),
          s.string_seq(v.obstacles),
          s.string_seq(v.maps),
          v.time_scale,
          v.started_unix_ms,
          s.string_seq(v.homes),
          v.refused_samples,
          s.string_seq(v.refused_senders)};
}
model::ServerInfo from_wire(const fleet_msg_ServerInfo& w) {
  return {text(w.server_id),
          text(w.site),
          strings_of(w.loading_areas),
          strings_of(w.robots),
          strings_of(w.obstacles),
          strings_of(w.maps),
          w.time_scale,
          w.started_unix_ms,
          strings_of(w.homes),
          w.refused_samples,
          strings_of(w.refused_senders)};
}

fleet_msg_OrderRequest to_wire(const model::OrderRequest& v, Scratch&) {
  return {borrow(v.request_id), borrow(v.pick_area), borrow(v.drop_area), borrow(v.fleet_id), borrow(v.robot_id),
          v.priority,           borrow(v.kind),      borrow(v.lines),     borrow(v.handling)};
}
model::OrderRequest from_wire(const fleet_msg_OrderRequest& w) {
  return {text(w.request_id), text(w.pick_area), text(w.drop_area), text(w.fleet_id), text(w.robot_id),
          w.priority,         text(w.kind),      text(w.lines),     text(w.handling)};
}

fleet_msg_Command to_wire(const model::Command& v, Scratch&) {
  return {borrow(v.request_id), borrow(v.verb), borrow(v.target), borrow(v.value), v.update_id};
}
model::Command from_wire(const fleet_msg_Command& w) {
  return {text(w.request_id), text(w.verb), text(w.target), text(w.value), w.update_id};
}

fleet_msg_RequestReply to_wire(const model::RequestReply& v, Scratch&) {
  return {borrow(v.request_id), v.accepted, v.order_id, borrow(v.error), v.order_count};
}
model::RequestReply from_wire(const fleet_msg_RequestReply& w) {
  return {text(w.request_id), w.accepted, w.order_id, text(w.error), w.order_count};
}

fleet_msg_Order to_wire(const model::OrderAssignment& v, Scratch&) {
  return {v.order_id,
          borrow(v.robot_id),
          borrow(v.pick_area),
          wire_pose(v.pick_pose),
          borrow(v.drop_area),
          wire_pose(v.drop_pose),
          v.update_id,
          v.cancelled,
          borrow(v.kind),
          borrow(v.lines),
          v.loader,
          v.released_stops,
          v.approach_stops,
          v.pallet,
          v.stand.has_value(),
          wire_pose(v.stand.value_or(geometry::Pose2{}))};
}
model::OrderAssignment from_wire(const fleet_msg_Order& w) {
  return {w.order_id,
          text(w.robot_id),
          text(w.pick_area),
          model_pose(w.pick_pose),
          text(w.drop_area),
          model_pose(w.drop_pose),
          w.update_id,
          w.cancelled,
          text(w.kind),
          text(w.lines),
          w.loader,
          w.released_stops,
          w.approach_stops,
          w.pallet,
          w.standing ? std::optional(model_pose(w.stand_pose)) : std::nullopt};
}

fleet_msg_OrderState to_wire(const model::OrderReport& v, Scratch&) {
  return {v.order_id, borrow(v.robot_id), borrow(v.status), borrow(v.reason),        v.update_id,
          v.sim_time, v.carrying_pallet,  v.pallet_id,      wire_pose(v.pallet_pose)};
}
model::OrderReport from_wire(const fleet_msg_OrderState& w) {
  return {w.order_id, text(w.robot_id),  text(w.status), text(w.reason),           w.update_id,
          w.sim_time, w.carrying_pallet, w.pallet_id,    model_pose(w.pallet_pose)};
}

fleet_msg_PalletTruth to_wire(const model::PalletTruth& v, Scratch&) {
  return {v.pallet_id, wire_pose(v.pose), borrow(v.area_id), borrow(v.carried_by)};
}
model::PalletTruth from_wire(const fleet_msg_PalletTruth& w) {
  return {w.pallet_id, model_pose(w.pose), text(w.area_id), text(w.carried_by)};
}

fleet_msg_OrderInfo to_wire(const model::OrderInfo& v, Scratch& s) {
  auto& events = s.events.emplace_back();
  // The IDL bounds the history; keep the newest entries.
  const std::size_t first = v.history.size() > model::kMaxOrderHistory ? v.history.size() - model::kMaxOrderHistory : 0;
  for (std::size_t i = first; i < v.history.size(); ++i) {
    const auto& e = v.history[i];
    events.push_back(
        {e.sim_time, borrow(e.state), borrow(e.phase), borrow(e.robot_id), borrow(e.reason), e.robot_x, e.robot_y});
  }
  return {v.order_id,
          borrow(v.request_id),
          borrow(v.pick_area),
          borrow(v.drop_area),
          borrow(v.fleet_id),
          borrow(v.robot_id),
          borrow(v.state),
          borrow(v.phase),
          borrow(v.reason),
          v.priority,
          v.created_sim,
          v.updated_sim,
          {static_cast<uint32_t>(events.size()), static_cast<uint32_t>(events.size()), events.data(), false},
          borrow(v.kind),
          borrow(v.cause),
          s.text(model::ids_text(v.caused_by)),
          borrow(v.lines),
          v.robot_requested,
          v.update_id,
          v.assigned_sim,
          v.finished_sim,
          v.loader};
}
model::OrderInfo from_wire(const fleet_msg_OrderInfo& w) {
  model::OrderInfo v{w.order_id,
                     text(w.request_id),
                     text(w.pick_area),
                     text(w.drop_area),
                     text(w.fleet_id),
                     text(w.robot_id),
                     text(w.state),
                     text(w.phase),
                     text(w.reason),
                     w.priority,
                     w.created_sim,
                     w.updated_sim,
                     {},
                     text(w.kind),
                     text(w.cause),
                     model::parse_ids(text(w.caused_by)).value_or(std::vector<std::int64_t>{}),
                     text(w.lines),
                     w.robot_requested,
                     w.update_id,
                     w.assigned_sim,
                     w.finished_sim,
                     w.loader};
  for (uint32_t i = 0; i < w.history._length; ++i) {
    const auto& e = w.history._buffer[i];
    v.history.push_back(
        {e.sim_time, text(e.state), text(e.phase), text(e.robot_id), text(e.reason), e.robot_x, e.robot_y});
  }
  return v;
}

fleet_msg_RobotState to_wire(const model::RobotState& v, Scratch& s) {
  fleet_msg_RobotState w{};
  w.robot_id = borrow(v.robot_id);
  w.fleet_id = borrow(v.fleet_id);
  w.map_id = borrow(v.map_id);
  w.pose = wire_pose(v.pose);
  for (std::size_t i = 0; i < 9; ++i) w.covariance[i] = v.covariance[i];
  w.localization_score = v.localization_score;
  w.speed = v.speed;
  w.yaw_rate = v.yaw_rate;
  w.task_state = borrow(v.task_state);
  w.detail = borrow(v.detail);
  w.order_id = v.order_id;
  w.carrying_pallet = v.carrying_pallet;
  w.sim_time = v.sim_time;
  w.walk_stop = v.walk_stop;
  w.boxes_loaded = v.boxes_loaded;
  // The IDL bounds the targets at two: target 1 and target 2.
  constexpr std::size_t kMaxDockingTargets = 2;
  const std::size_t targets = std::min(v.docking_targets.size(), kMaxDockingTargets);
  w.docking_targets =
      s.point_seq(std::vector<geometry::Vec2>(v.docking_targets.begin(), v.docking_targets.begin() + targets));
  w.detected_pallet = s.pose_seq(v.detected_pallet);
  w.control_lag_p50 = v.control_lag_p50;
  w.control_lag_p99 = v.control_lag_p99;
  w.control_period = v.control_period;
  w.control_steps_skipped = v.control_steps_skipped;
  return w;
}
model::RobotState from_wire(const fleet_msg_RobotState& w) {
  model::RobotState v;
  v.robot_id = text(w.robot_id);
  v.fleet_id = text(w.fleet_id);
  v.map_id = text(w.map_id);
  v.pose = model_pose(w.pose);
  for (std::size_t i = 0; i < 9; ++i) v.covariance[i] = w.covariance[i];
  v.localization_score = w.localization_score;
  v.speed = w.speed;
  v.yaw_rate = w.yaw_rate;
  v.task_state = text(w.task_state);
  v.detail = text(w.detail);
  v.order_id = w.order_id;
  v.carrying_pallet = w.carrying_pallet;
  v.sim_time = w.sim_time;
  v.walk_stop = w.walk_stop;
  v.boxes_loaded = w.boxes_loaded;
  v.docking_targets = points_of(w.docking_targets);
  v.detected_pallet = pose_of(w.detected_pallet);
  v.control_lag_p50 = w.control_lag_p50;
  v.control_lag_p99 = w.control_lag_p99;
  v.control_period = w.control_period;
  v.control_steps_skipped = w.control_steps_skipped;
  return v;
}

fleet_msg_RobotPath to_wire(const model::RobotPath& v, Scratch& s) {
  return {borrow(v.robot_id), s.point_seq(v.points), v.sim_time};
}
model::RobotPath from_wire(const fleet_msg_RobotPath& w) {
  return {text(w.robot_id), points_of(w.points), w.sim_time};
}

fleet_msg_MapAssignment to_wire(const model::MapAssignment& v, Scratch&) {
  return {borrow(v.robot_id), borrow(v.map_id)};
}
model::MapAssignment from_wire(const fleet_msg_MapAssignment& w) {
  return {text(w.robot_id), text(w.map_id)};
}

fleet_msg_RobotControl to_wire(const model::RobotControl& v, Scratch&) {
  return {borrow(v.robot_id), v.paused};
}
model::RobotControl from_wire(const fleet_msg_RobotControl& w) {
  return {text(w.robot_id), w.paused};
}

fleet_msg_StaticObstacle to_wire(const model::StaticObstacleState& v, Scratch& s) {
  return {borrow(v.obstacle_id), borrow(v.map_id), v.enabled, s.point_seq(v.polygon)};
}
model::StaticObstacleState from_wire(const fleet_msg_StaticObstacle& w) {
  return {text(w.obstacle_id), text(w.map_id), w.enabled, points_of(w.polygon)};
}

dds_sequence_fleet_msg_RobotSnapshot snapshot_seq(Scratch& s, const std::vector<model::RobotSnapshot>& items) {
  auto& robots = s.snapshots.emplace_back();
  for (const auto& r : items) {
    robots.push_back({borrow(r.robot_id), borrow(r.fleet_id), wire_pose(r.pose), r.footprint.length, r.footprint.width,
                      r.speed, borrow(r.task_state), r.sim_time, s.point_seq(r.path)});
  }
  return {static_cast<uint32_t>(robots.size()), static_cast<uint32_t>(robots.size()), robots.data(), false};
}
std::vector<model::RobotSnapshot> snapshots_of(const dds_sequence_fleet_msg_RobotSnapshot& w) {
  std::vector<model::RobotSnapshot> out;
  for (uint32_t i = 0; i < w._length; ++i) {
    const auto& r = w._buffer[i];
    out.push_back({text(r.robot_id),
                   text(r.fleet_id),
                   model_pose(r.pose),
                   {r.length, r.width},
                   r.speed,
                   text(r.task_state),
                   r.sim_time,
                   points_of(r.path)});
  }
  return out;
}

fleet_msg_FleetView to_wire(const model::FleetView& v, Scratch& s) {
  return {borrow(v.map_id), v.sim_time, snapshot_seq(s, v.robots)};
}
model::FleetView from_wire(const fleet_msg_FleetView& w) {
  return {text(w.map_id), w.sim_time, snapshots_of(w.robots)};
}

fleet_msg_SimTruth to_wire(const model::SimTruth& v, Scratch&) {
  return {borrow(v.robot_id), wire_pose(v.pose), v.footprint.length, v.footprint.width, v.carrying_pallet, v.sim_time};
}
model::SimTruth from_wire(const fleet_msg_SimTruth& w) {
  return {text(w.robot_id), model_pose(w.pose), {w.length, w.width}, w.carrying_pallet, w.sim_time};
}

fleet_msg_NeighbourView to_wire(const model::NeighbourView& v, Scratch& s) {
  auto& bodies = s.truths.emplace_back();
  for (const auto& b : v.bodies) bodies.push_back(to_wire(b, s));
  return {borrow(v.robot_id),
          borrow(v.map_id),
          v.sim_time,
          v.radius,
          v.complete,
          snapshot_seq(s, v.robots),
          {static_cast<uint32_t>(bodies.size()), static_cast<uint32_t>(bodies.size()), bodies.data(), false}};
}
model::NeighbourView from_wire(const fleet_msg_NeighbourView& w) {
  model::NeighbourView v{text(w.robot_id), text(w.map_id),         w.sim_time, w.radius,
                         w.complete,       snapshots_of(w.robots), {}};
  for (uint32_t i = 0; i < w.bodies._length; ++i) v.bodies.push_back(from_wire(w.bodies._buffer[i]));
  return v;
}

fleet_msg_TrafficRequest to_wire(const model::TrafficRequest& v, Scratch& s) {
  return {borrow(v.robot_id),          v.version,       int_seq(s, v.points),     v.progress,
          s.string_seq(v.stopped_for), v.sim_time,      s.point_seq(v.work_area), s.point_seq(v.arrival_area),
          s.point_seq(v.keep_clear),   borrow(v.map_id)};
}
model::TrafficRequest from_wire(const fleet_msg_TrafficRequest& w) {
  return {text(w.robot_id),          w.version,     ints_of(w.points),      w.progress,
          strings_of(w.stopped_for), w.sim_time,    points_of(w.work_area), points_of(w.arrival_area),
          points_of(w.keep_clear),   text(w.map_id)};
}

fleet_msg_TrafficProgress to_wire(const model::TrafficProgress& v, Scratch& s) {
  return {borrow(v.robot_id), v.version, v.progress, s.string_seq(v.stopped_for), v.sim_time, borrow(v.map_id)};
}
model::TrafficProgress from_wire(const fleet_msg_TrafficProgress& w) {
  return {text(w.robot_id), w.version, w.progress, strings_of(w.stopped_for), w.sim_time, text(w.map_id)};
}

fleet_msg_TrafficGrant to_wire(const model::TrafficGrant& v, Scratch& s) {
  return {borrow(v.robot_id),
          v.version,
          v.granted_index,
          v.granted_distance,
          borrow(v.status),
          v.waited_s,
          s.string_seq(v.blocked_by),
          borrow(v.instruction),
          int_seq(s, v.route),
          v.sim_time};
}
model::TrafficGrant from_wire(const fleet_msg_TrafficGrant& w) {
  return {text(w.robot_id), w.version,  w.granted_index,          w.granted_distance,
          text(w.status),   w.waited_s, strings_of(w.blocked_by), text(w.instruction),
          ints_of(w.route), w.sim_time};
}

fleet_msg_ServerLoad to_wire(const model::ServerLoad& v, Scratch&) {
  return {borrow(v.server_id),
          v.sim_time,
          v.robots,
          v.traffic_cycles,
          v.traffic_cycle_p50_ms,
          v.traffic_cycle_p99_ms,
          v.traffic_cycle_max_ms,
          v.traffic_update_p50_ms,
          v.traffic_update_p99_ms,
          v.traffic_update_max_ms,
          v.dispatches,
          v.dispatch_p50_ms,
          v.dispatch_p99_ms,
          v.dispatch_max_ms,
          v.term,
          v.active,
          v.took_over,
          v.since_unix_ms,
          v.active_heard_s_ago};
}
fleet_msg_SiteStateDocument to_wire(const model::SiteStateDocument& v, Scratch&) {
  return {borrow(v.site), borrow(v.json)};
}
model::SiteStateDocument from_wire(const fleet_msg_SiteStateDocument& w) {
  return {text(w.site), text(w.json)};
}

model::ServerLoad from_wire(const fleet_msg_ServerLoad& w) {
  return {text(w.server_id),
          w.sim_time,
          w.robots,
          w.traffic_cycles,
          w.traffic_cycle_p50_ms,
          w.traffic_cycle_p99_ms,
          w.traffic_cycle_max_ms,
          w.traffic_update_p50_ms,
          w.traffic_update_p99_ms,
          w.traffic_update_max_ms,
          w.dispatches,
          w.dispatch_p50_ms,
          w.dispatch_p99_ms,
          w.dispatch_max_ms,
          w.term,
          w.active,
          w.took_over,
          w.since_unix_ms,
          w.active_heard_s_ago};
}

}  // namespace

#define FLEET_DDS_TOPIC_IMPL(Type, Wire, TopicName)                                                     \
  const char* const TopicTraits<model::Type>::name = TopicName;                                         \
  const dds_topic_descriptor_t* TopicTraits<model::Type>::descriptor() {                                \
    return &Wire##_desc;                                                                                \
  }                                                                                                     \
  dds_return_t TopicTraits<model::Type>::write(dds_entity_t writer, const model::Type& value) {         \
    Scratch scratch;                                                                                    \
    const Wire wire = to_wire(value, scratch);                                                          \
    return dds_write(writer, &wire);                                                                    \
  }                                                                                                     \
  dds_return_t TopicTraits<model::Type>::unregister(dds_entity_t writer, const model::Type& value) {    \
    Scratch scratch;                                                                                    \
    const Wire wire = to_wire(value, scratch);                                                          \
    return dds_unregister_instance(writer, &wire);                                                      \
  }                                                                                                     \
  dds_return_t TopicTraits<model::Type>::dispose(dds_entity_t writer, const model::Type& value) {       \
    Scratch scratch;                                                                                    \
    const Wire wire = to_wire(value, scratch);                                                          \
    return dds_dispose(writer, &wire);                                                                  \
  }                                                                                                     \
  int TopicTraits<model::Type>::take(dds_entity_t reader,                                               \
                                     const std::function<void(model::Type&&, const SampleInfo&)>& fn) { \
    return take_samples<Wire, model::Type>(reader, fn, [](const Wire& w) { return from_wire(w); });     \
  }                                                                                                     \
  dds_return_t TopicTraits<model::Type>::key_of(dds_entity_t entity, dds_instance_handle_t instance,    \
                                                model::Type& out) {                                     \
    Wire wire{};                                                                                        \
    const dds_return_t rc = dds_instance_get_key(entity, instance, &wire);                              \
    if (rc >= 0) out = from_wire(wire);                                                                 \
    dds_sample_free(&wire, &Wire##_desc, DDS_FREE_CONTENTS);                                            \
    return rc;                                                                                          \
  }

FLEET_DDS_TOPIC_IMPL(ServerInfo, fleet_msg_ServerInfo, "fleet/ServerInfo")
FLEET_DDS_TOPIC_IMPL(OrderRequest, fleet_msg_OrderRequest, "fleet/OrderRequest")
FLEET_DDS_TOPIC_IMPL(Command, fleet_msg_Command, "fleet/Command")
FLEET_DDS_TOPIC_IMPL(RequestReply, fleet_msg_RequestReply, "fleet/RequestReply")
FLEET_DDS_TOPIC_IMPL(OrderAssignment, fleet_msg_Order, "fleet/Order")
FLEET_DDS_TOPIC_IMPL(OrderReport, fleet_msg_OrderState, "fleet/OrderState")
FLEET_DDS_TOPIC_IMPL(OrderInfo, fleet_msg_OrderInfo, "fleet/OrderInfo")
FLEET_DDS_TOPIC_IMPL(OrderHandover, fleet_msg_OrderInfo, "fleet/OrderHandover")
FLEET_DDS_TOPIC_IMPL(RobotState, fleet_msg_RobotState, "fleet/RobotState")
FLEET_DDS_TOPIC_IMPL(RobotPath, fleet_msg_RobotPath, "fleet/RobotPath")
FLEET_DDS_TOPIC_IMPL(MapAssignment, fleet_msg_MapAssignment, "fleet/MapAssignment")
FLEET_DDS_TOPIC_IMPL(RobotControl, fleet_msg_RobotControl, "fleet/RobotControl")
FLEET_DDS_TOPIC_IMPL(PalletTruth, fleet_msg_PalletTruth, "fleet/PalletTruth")
FLEET_DDS_TOPIC_IMPL(StaticObstacleState, fleet_msg_StaticObstacle, "fleet/StaticObstacles")
FLEET_DDS_TOPIC_IMPL(FleetView, fleet_msg_FleetView, "fleet/FleetView")
FLEET_DDS_TOPIC_IMPL(NeighbourView, fleet_msg_NeighbourView, "fleet/NeighbourView")
FLEET_DDS_TOPIC_IMPL(SimTruth, fleet_msg_SimTruth, "fleet/SimTruth")
FLEET_DDS_TOPIC_IMPL(TrafficRequest, fleet_msg_TrafficRequest, "fleet/TrafficRequest")
FLEET_DDS_TOPIC_IMPL(TrafficProgress, fleet_msg_TrafficProgress, "fleet/TrafficProgress")
FLEET_DDS_TOPIC_IMPL(TrafficGrant, fleet_msg_TrafficGrant, "fleet/TrafficGrant")
FLEET_DDS_TOPIC_IMPL(ServerLoad, fleet_msg_ServerLoad, "fleet/ServerLoad")
FLEET_DDS_TOPIC_IMPL(SiteStateDocument, fleet_msg_SiteStateDocument, "fleet/SiteState")

}  // namespace fleet::dds
