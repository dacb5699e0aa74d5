#include "server/grant_publisher.hpp"

#include "model/names.hpp"

namespace fleet::server {

namespace {
constexpr double kGrantRepeatWall = 1.0;  // seconds: unchanged grants are repeated for late joiners

bool same_grant(const model::TrafficGrant& a, const model::TrafficGrant& b) {
  return a.version == b.version && a.granted_index == b.granted_index && a.status == b.status &&
         a.blocked_by == b.blocked_by && a.instruction == b.instruction && a.route == b.route;
}
}  // namespace

GrantPublisher::GrantPublisher(dds::Participant& participant, Logger log)
    : log_(std::move(log)), writers_(participant, dds::qos::live_state()) {}

void GrantPublisher::open(const std::string& robot_id) {
  writers_.open(model::robot_partition(robot_id));
}

void GrantPublisher::publish(model::TrafficGrant grant, double now_wall) {
  auto sent = sent_.find(grant.robot_id);
  if (sent != sent_.end() && same_grant(sent->second, grant) &&
      now_wall - sent_wall_[grant.robot_id] < kGrantRepeatWall) {
    return;
  }
  if (log_->should_log(spdlog::level::debug) &&
      (sent == sent_.end() || sent->second.status != grant.status || sent->second.blocked_by != grant.blocked_by)) {
    // Who waits for whom, as it changes: what a jam is read back from.
    std::string blockers;
    for (const auto& b : grant.blocked_by) blockers += (blockers.empty() ? "" : ", ") + b;
    log_->debug("traffic: {} {} v{} up to point {} ({:.2f} m){}{}", grant.robot_id, grant.status, grant.version,
                grant.granted_index, grant.granted_distance, blockers.empty() ? "" : ", waits for ", blockers);
  }
  // Into the robot's own partition: its agent alone hears it (and the watchers of every robot),
  // not every agent every other robot's grant.
  writers_.write(model::robot_partition(grant.robot_id), grant);
  sent_wall_[grant.robot_id] = now_wall;
  sent_[grant.robot_id] = std::move(grant);
}

}  // namespace fleet::server
