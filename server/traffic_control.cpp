#include "server/traffic_control.hpp"

#include <algorithm>
#include <cmath>

namespace fleet::server {

namespace {
constexpr double kGrantRepeatWall = 1.0;  // seconds: unchanged grants are repeated for late joiners

const char* status_name(traffic::GrantStatus s) {
  switch (s) {
    case traffic::GrantStatus::kMoving: return "MOVING";
    case traffic::GrantStatus::kWaiting: return "WAITING";
    case traffic::GrantStatus::kArrived: return "ARRIVED";
  }
  return "MOVING";
}

const char* instruction_name(traffic::Instruction i) {
  switch (i) {
    case traffic::Instruction::kNone: return "";
    case traffic::Instruction::kReroute: return "REROUTE";
    case traffic::Instruction::kSiding: return "SIDING";
  }
  return "";
}

bool same_grant(const model::TrafficGrant& a, const model::TrafficGrant& b) {
  return a.version == b.version && a.granted_index == b.granted_index && a.status == b.status &&
         a.blocked_by == b.blocked_by && a.instruction == b.instruction && a.route == b.route;
}
}  // namespace

TrafficControl::TrafficControl(const map::RoadGraph& graph, const traffic::TrafficConfiguration& configuration,
                               dds::Participant& participant, Logger log)
    : manager_(graph, configuration),
      log_(std::move(log)),
      grant_writer_(participant, dds::qos::live_state()),
      request_reader_(participant, dds::qos::live_state()) {
  log_->info("traffic control on: {} places, lookahead {:.2f} m, one-way corridors {}",
             manager_.zones().place_count(), configuration.lookahead, configuration.one_way ? "on" : "off");
}

int TrafficControl::number_of(const std::string& robot_id) {
  auto it = numbers_.find(robot_id);
  if (it != numbers_.end()) return it->second;
  const int number = static_cast<int>(numbers_.size()) + 1;
  numbers_[robot_id] = number;
  names_[number] = robot_id;
  return number;
}

void TrafficControl::handle_requests(double now_sim, double now_wall) {
  request_reader_.take_data([&](model::TrafficRequest&& request) {
    if (request.robot_id.empty() || !std::isfinite(request.progress)) {
      log_->warn("traffic request from '{}' ignored: progress {} is not a number", request.robot_id, request.progress);
      return;
    }
    const auto bad_point = std::find_if(request.points.begin(), request.points.end(), [&](int point) {
      return point < 0 || static_cast<std::size_t>(point) >= manager_.zones().point_count();
    });
    if (bad_point != request.points.end()) {
      log_->warn("traffic request from '{}' ignored: graph point {} does not exist ({} points)", request.robot_id,
                 *bad_point, manager_.zones().point_count());
      return;
    }
    const int id = number_of(request.robot_id);
    if (request.points.empty()) {
      // Parked beside the road (home, or done): it holds nothing any more.
      manager_.drop_entry(id);
      if (manager_.remove_robot(id, now_sim)) log_->debug("{} left the roads", request.robot_id);
      status_.erase(request.robot_id);
      return;
    }
    if (manager_.frozen(id)) {
      // Lost, and answering again: it enters anew where it has got to on its route (the places
      // under its body were kept for it, so its entry is free).
      manager_.remove_robot(id, now_sim);
      log_->info("traffic: {} answers again and re-enters at {:.2f} m along route {}", request.robot_id, request.progress,
                 request.version);
    }
    if (!manager_.has_robot(id) || request.version > manager_.version(id)) {
      traffic::RouteRequest route{id, request.version, request.points};
      auto result = traffic::SubmitStatus::kInvalid;
      if (manager_.has_robot(id)) {
        result = manager_.submit_route(route, now_sim);
        if (result == traffic::SubmitStatus::kInvalid) {
          // The route starts somewhere the robot does not hold (it drove off the graph and came
          // back elsewhere, e.g. from a loading area): it enters afresh there.
          manager_.remove_robot(id, now_sim);
        }
      }
      if (!manager_.has_robot(id)) {
        // A robot already part-way along its route (the server restarted under it, or it was
        // lost and came back) enters where it is: the points behind it are cut off, and its
        // progress and grants are shifted by what was cut (trims_).
        std::size_t skip = 0;
        double offset = 0.0;
        for (std::size_t k = 1; k < request.points.size(); ++k) {
          const double step = manager_.search().edge_length(request.points[k - 1], request.points[k]);
          if (offset + step > request.progress) break;
          offset += step;
          skip = k;
        }
        route.points.erase(route.points.begin(), route.points.begin() + static_cast<std::ptrdiff_t>(skip));
        if (skip > 0) {
          trims_[request.robot_id] = {request.version, static_cast<int>(skip), offset};
        } else {
          trims_.erase(request.robot_id);
        }
        // Entering the roads: only where no one holds a place in conflict with the entry; until
        // then the robot waits beside the road (granted_index -1).
        const auto holders = manager_.holders_in_conflict(route.points.front(), id);
        if (!holders.empty()) {
          manager_.claim_entry(id, route.points.front(), now_sim);
          model::TrafficGrant wait;
          wait.robot_id = request.robot_id;
          wait.version = request.version;
          wait.granted_index = -1;
          wait.status = "WAITING";
          for (int h : holders) wait.blocked_by.push_back(names_[h]);
          wait.sim_time = now_sim;
          status_[request.robot_id] = {"WAITING", 0.0, wait.blocked_by, {}};
          publish(std::move(wait), now_wall);
          return;
        }
        result = manager_.submit_route(route, now_sim);
      }
      if (result != traffic::SubmitStatus::kAccepted) {
        log_->warn("route {} of {} refused ({} points from {})", request.version, request.robot_id,
                   request.points.size(), request.points.front());
        return;
      }
    }
    log_->debug("traffic request {} v{} {} points progress {:.3f} (manager v{})", request.robot_id, request.version,
                request.points.size(), request.progress, manager_.version(id));
    double progress = request.progress;
    if (auto t = trims_.find(request.robot_id); t != trims_.end() && t->second.version == request.version) {
      progress -= t->second.offset;
    }
    manager_.report_progress({id, request.version, progress}, now_sim);
  });
}

void TrafficControl::robot_lost(const std::string& robot_id, const geometry::Polygon& body, double now_sim) {
  auto it = numbers_.find(robot_id);
  if (it != numbers_.end()) manager_.drop_entry(it->second);
  if (it != numbers_.end() && manager_.freeze_robot(it->second, body, now_sim)) {
    log_->warn("traffic: {} lost; it keeps the places its body stands on ({}), the rest is freed", robot_id,
               manager_.held_places(it->second).size());
  }
  status_.erase(robot_id);
}

void TrafficControl::update(double now_sim, double now_wall) {
  const traffic::UpdateResult result = manager_.update(now_sim);
  for (const auto& e : result.events) {
    std::string others;
    for (int o : e.others) others += (others.empty() ? "" : ", ") + names_[o];
    const std::string& robot = names_[e.robot_id];
    switch (e.kind) {
      case traffic::TrafficEvent::Kind::kDeadlockResolved:
        log_->info("traffic: wait cycle [{}] broken by re-routing {}", others, robot);
        break;
      case traffic::TrafficEvent::Kind::kRerouted:
        log_->info("traffic: {} re-routed around {}", robot, others);
        break;
      case traffic::TrafficEvent::Kind::kSidingSent:
        log_->info("traffic: {} yields on a siding to {}", robot, others);
        break;
      case traffic::TrafficEvent::Kind::kResumed:
        log_->info("traffic: {} leaves its siding", robot);
        break;
      case traffic::TrafficEvent::Kind::kRobotRemoved:
        break;
      case traffic::TrafficEvent::Kind::kUnresolvedDeadlock:
        log_->debug("traffic: wait cycle [{}] has no way out yet", others);
        break;
    }
  }
  for (const traffic::Grant& g : result.grants) {
    const std::string& robot = names_[g.robot_id];
    model::TrafficGrant grant;
    grant.robot_id = robot;
    grant.version = g.version;
    grant.granted_index = g.granted_index;
    grant.granted_distance = g.granted_distance;
    if (auto t = trims_.find(robot); t != trims_.end() && t->second.version == g.version) {
      // In the robot's terms: along the whole route it reported.
      grant.granted_index += t->second.skipped;
      grant.granted_distance += t->second.offset;
    }
    grant.status = status_name(g.status);
    grant.waited_s = g.waited_s;
    for (int b : g.blocked_by) grant.blocked_by.push_back(names_[b]);
    grant.instruction = instruction_name(g.instruction);
    if (g.instruction != traffic::Instruction::kNone) grant.route = g.route;
    grant.sim_time = now_sim;
    auto& status = status_[robot];
    status.status = grant.status;
    status.waited_s = grant.waited_s;
    status.blocked_by = grant.blocked_by;
    status.held.clear();
    for (int place : manager_.held_places(g.robot_id)) status.held.push_back(manager_.zones().position(place));
    publish(std::move(grant), now_wall);
  }
}

void TrafficControl::publish(model::TrafficGrant grant, double now_wall) {
  // Written when it changed, and repeated now and then for an agent that (re)started.
  auto sent = sent_.find(grant.robot_id);
  if (sent != sent_.end() && same_grant(sent->second, grant) && now_wall - sent_wall_[grant.robot_id] < kGrantRepeatWall) {
    return;
  }
  grant_writer_.write(grant);
  sent_wall_[grant.robot_id] = now_wall;
  sent_[grant.robot_id] = std::move(grant);
}

}  // namespace fleet::server
