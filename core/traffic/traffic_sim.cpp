#include "traffic/traffic_sim.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "map/road_graph_builder.hpp"

namespace fleet::traffic {

SimScenario site_scenario(const map::SiteMap& site, const ConflictZones& zones, int robots, double approach_distance,
                          const std::vector<int>& robot_types) {
  const auto type_of = [&](std::size_t robot) { return robot < robot_types.size() ? robot_types[robot] : 0; };
  const map::RoadGraph& graph = site.graph.graph;
  SimScenario scenario;
  for (const auto& area : site.site.loading_areas) {
    const geometry::Pose2 stand = area.approach_pose(approach_distance);
    const double x = stand.x;
    const double y = stand.y;
    const int p = map::nearest_point(graph, x, y);
    if (p >= 0 &&
        std::find(scenario.goal_points.begin(), scenario.goal_points.end(), p) == scenario.goal_points.end()) {
      scenario.goal_points.push_back(p);
    }
  }
  std::vector<int> candidates;
  for (const auto& home : site.site.homes) {
    const int p = map::nearest_point(graph, home.pose.x, home.pose.y);
    if (p >= 0) candidates.push_back(p);
  }
  candidates.insert(candidates.end(), scenario.goal_points.begin(), scenario.goal_points.end());
  for (std::size_t i = 0; i < graph.points.size(); ++i) candidates.push_back(static_cast<int>(i));
  // Stoppable places first: a robot should not start inside a junction.
  for (int pass = 0; pass < 2 && static_cast<int>(scenario.start_points.size()) < robots; ++pass) {
    for (int p : candidates) {
      if (static_cast<int>(scenario.start_points.size()) >= robots) break;
      const int place = zones.place_of(p);
      const std::size_t robot = scenario.start_points.size();
      if (pass == 0 && !zones.stoppable(place)) continue;
      bool free = true;
      for (std::size_t other = 0; other < scenario.start_points.size(); ++other) {
        if (zones.conflict(type_of(robot), place, type_of(other), zones.place_of(scenario.start_points[other]))) {
          free = false;
          break;
        }
      }
      if (free) scenario.start_points.push_back(p);
    }
  }
  return scenario;
}

TrafficSim::TrafficSim(const map::RoadGraph& graph, const TrafficConfiguration& configuration, const SimParams& params,
                       const std::vector<int>& goal_points, const std::vector<int>& start_points)
    : graph_(graph),
      params_(params),
      manager_(graph_, configuration),
      search_(manager_.route_graph(), manager_.zones()),
      goal_points_(goal_points),
      rng_(params.seed) {
  for (std::size_t t = 0; t < manager_.zones().type_count(); ++t) {
    type_search_.push_back(std::make_unique<RouteSearch>(manager_.route_graph(static_cast<int>(t)), manager_.zones()));
  }
  bodies_.resize(start_points.size());
  for (std::size_t i = 0; i < start_points.size(); ++i) {
    Body& body = bodies_[i];
    body.id = static_cast<int>(i) + 1;
    if (i < params_.robot_types.size() && !manager_.set_robot_type(body.id, params_.robot_types[i])) {
      throw std::invalid_argument("traffic sim: robot " + std::to_string(body.id) + " has unknown vehicle type " +
                                  std::to_string(params_.robot_types[i]));
    }
    set_route(body, {start_points[i]}, 1);
    // A robot stands along its lane, not across it: beside a parked neighbour a body turned
    // across the lane would overlap it.
    if (const auto& next = graph_.successors[static_cast<std::size_t>(start_points[i])]; !next.empty()) {
      const auto& a = graph_.points[static_cast<std::size_t>(start_points[i])];
      const auto& b = graph_.points[static_cast<std::size_t>(next.front())];
      body.pose.yaw = std::atan2(b.y - a.y, b.x - a.x);
    }
    body.dwell_until = 0.0;
    if (params_.traffic) manager_.submit_route({body.id, body.version, body.route}, 0.0);
  }
  overlapping_.assign(bodies_.size() * bodies_.size(), 0);
  report_.robots = static_cast<int>(bodies_.size());
}

TrafficSim::Body* TrafficSim::find(int robot_id) {
  for (auto& b : bodies_) {
    if (b.id == robot_id) return &b;
  }
  return nullptr;
}

const TrafficSim::Body* TrafficSim::find(int robot_id) const {
  for (const auto& b : bodies_) {
    if (b.id == robot_id) return &b;
  }
  return nullptr;
}

geometry::Pose2 TrafficSim::pose(int robot_id) const {
  const Body* b = find(robot_id);
  return b ? b->pose : geometry::Pose2{};
}

bool TrafficSim::idle(int robot_id) const {
  const Body* b = find(robot_id);
  return b && b->goal < 0 && b->goals.empty() && b->dwell_until < 0.0 && b->distance >= b->cum.back() - 1e-9;
}

std::size_t TrafficSim::goals_reached(int robot_id) const {
  const Body* b = find(robot_id);
  return b ? b->reached : 0;
}

void TrafficSim::add_goal(int robot_id, int point) {
  if (Body* b = find(robot_id)) b->goals.push_back(point);
}

void TrafficSim::remove_robot(int robot_id) {
  Body* b = find(robot_id);
  if (!b || !b->active) return;
  b->active = false;
  if (params_.traffic) manager_.remove_robot(robot_id, time_);
}

void TrafficSim::set_route(Body& body, std::vector<int> route, std::uint64_t version) {
  body.route = std::move(route);
  body.cum.assign(body.route.size(), 0.0);
  for (std::size_t i = 1; i < body.route.size(); ++i)
    body.cum[i] = body.cum[i - 1] + search_.edge_length(body.route[i - 1], body.route[i]);
  body.version = version;
  body.distance = 0.0;
  body.granted = 0.0;
  body.segment = 0;
  const auto& p = graph_.points[static_cast<std::size_t>(body.route.front())];
  body.pose.x = p.x;
  body.pose.y = p.y;
}

void TrafficSim::start_next_goal(Body& body) {
  const int here = body.route.back();
  if (body.goals.empty() && params_.random_trips && goal_points_.size() >= 2) {
    std::uniform_int_distribution<std::size_t> pick(0, goal_points_.size() - 1);
    int next = here;
    while (manager_.zones().place_of(next) == manager_.zones().place_of(here)) next = goal_points_[pick(rng_)];
    if (!body.carrying) body.trip_start = time_;
    body.goals.push_back(next);
  }
  if (body.goals.empty()) {
    body.goal = -1;
    return;
  }
  const int next = body.goals.front();
  body.goals.pop_front();
  std::vector<int> path = type_search_[static_cast<std::size_t>(type_of(body.id))]->shortest(here, next);
  if (path.empty()) return;  // unreachable goal: skip it
  const std::uint64_t version = std::max(body.version, manager_.version(body.id)) + 1;
  set_route(body, std::move(path), version);
  body.goal = next;
  body.last_progress = time_;
  if (params_.traffic) manager_.submit_route({body.id, body.version, body.route}, time_);
}

void TrafficSim::advance(Body& body) {
  if (body.dwell_until >= 0.0) {
    if (time_ < body.dwell_until) return;
    body.dwell_until = -1.0;
    start_next_goal(body);
  } else if (body.goal < 0 && (!body.goals.empty() || params_.random_trips)) {
    start_next_goal(body);
  }
  const double end = body.cum.back();
  const double limit = params_.traffic ? body.granted : end;
  const double next =
      std::min(body.distance + params_.speed * params_.dt, std::max(body.distance, std::min(limit, end)));
  if (next > body.distance + 1e-12) {
    body.total += next - body.distance;
    body.last_progress = time_;
    body.deadlocked = false;
  }
  body.distance = next;
  // Pose along the route; the heading follows the edge being driven.
  const std::size_t n = body.route.size();
  while (body.segment + 2 < n && body.distance > body.cum[body.segment + 1]) ++body.segment;
  if (n >= 2) {
    const auto& a = graph_.points[static_cast<std::size_t>(body.route[body.segment])];
    const auto& b = graph_.points[static_cast<std::size_t>(body.route[body.segment + 1])];
    const double len = body.cum[body.segment + 1] - body.cum[body.segment];
    if (len > 1e-9) {
      const double t = std::clamp((body.distance - body.cum[body.segment]) / len, 0.0, 1.0);
      body.pose.x = a.x + t * (b.x - a.x);
      body.pose.y = a.y + t * (b.y - a.y);
      body.pose.yaw = std::atan2(b.y - a.y, b.x - a.x);
    } else {
      body.pose.x = b.x;
      body.pose.y = b.y;
    }
  }
  if (params_.traffic) manager_.report_progress({body.id, body.version, body.distance, {}}, time_);

  const auto& zones = manager_.zones();
  if (body.goal >= 0 && body.distance >= end - 1e-9 && zones.place_of(body.route.back()) == zones.place_of(body.goal)) {
    ++body.reached;
    ++report_.goals_reached;
    if (params_.random_trips) {
      if (body.carrying) {
        ++report_.trips;
        trip_time_sum_ += time_ + params_.dwell - body.trip_start;
        report_.mean_trip_s = trip_time_sum_ / static_cast<double>(report_.trips);
      }
      body.carrying = !body.carrying;
    }
    body.goal = -1;
    body.dwell_until = time_ + params_.dwell;
    body.last_progress = time_;
  }
  const bool has_task = body.goal >= 0;
  if (has_task && !body.deadlocked && time_ - body.last_progress >= params_.deadlock_timeout) {
    body.deadlocked = true;
    ++report_.deadlocks;
    // Where it stalled: the route point it stands nearest.
    std::size_t at = body.segment;
    if (at + 1 < body.route.size() && body.cum[at + 1] - body.distance < body.distance - body.cum[at]) ++at;
    report_.stalled_at.push_back(body.route[at]);
    report_.stall_notes.push_back(stall_note(body));
  }
}

std::string TrafficSim::describe(const Body& body) const {
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(2);
  out << "robot " << body.id << " (type " << type_of(body.id) << ") at (" << body.pose.x << ", " << body.pose.y << ")";
  if (body.dwell_until >= 0.0) out << " dwelling";
  if (body.goal >= 0) {
    const auto& g = graph_.points[static_cast<std::size_t>(body.goal)];
    out << " to point " << body.goal << " (" << g.x << ", " << g.y << ")";
  } else {
    out << " without a goal";
  }
  out << ", driven " << body.distance << " of " << body.cum.back() << " m";
  return out.str();
}

std::string TrafficSim::stall_note(const Body& body) const {
  // Down the line of who waits for whom, each robot once: a jam is read from its whole chain.
  std::ostringstream out;
  out << "t=" << time_ << " s:";
  std::vector<int> seen;
  std::vector<std::pair<int, int>> todo{{body.id, 0}};
  while (!todo.empty()) {
    const auto [id, depth] = todo.back();
    todo.pop_back();
    const Body* b = find(id);
    if (!b) continue;
    out << "\n      " << std::string(static_cast<std::size_t>(2 * depth), ' ') << describe(*b);
    if (std::find(seen.begin(), seen.end(), id) != seen.end()) {
      out << " (above)";
      continue;
    }
    seen.push_back(id);
    for (const Grant& grant : last_update_.grants) {
      if (grant.robot_id != id) continue;
      out << ", granted " << grant.granted_distance << " m";
      if (grant.status == GrantStatus::kWaiting) out << ", waits " << grant.waited_s << " s";
      if (!grant.blocked_by.empty()) out << " for";
      for (auto it = grant.blocked_by.rbegin(); it != grant.blocked_by.rend(); ++it) todo.push_back({*it, depth + 1});
    }
  }
  return out.str();
}

int TrafficSim::type_of(int robot_id) const {
  const auto i = static_cast<std::size_t>(robot_id - 1);
  return i < params_.robot_types.size() ? params_.robot_types[i] : 0;
}

void TrafficSim::check_collisions() {
  const std::size_t n = bodies_.size();
  const double reach = std::hypot(params_.footprint.length, params_.footprint.width);
  const auto& types = manager_.zones().vehicle_types();
  const auto body_of = [&](const Body& body) {
    geometry::Polygon out;
    for (const auto& v : types[static_cast<std::size_t>(type_of(body.id))].footprint) {
      out.push_back(geometry::body_to_map(body.pose, v));
    }
    return out;
  };
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      bool overlap = false;
      const bool active = bodies_[i].active && bodies_[j].active;
      if (active && !params_.robot_types.empty()) {
        overlap = geometry::polygons_overlap(body_of(bodies_[i]), body_of(bodies_[j]));
      } else if (active && geometry::distance(bodies_[i].pose.position(), bodies_[j].pose.position()) < reach) {
        overlap = geometry::convex_polygons_overlap(geometry::footprint_polygon(bodies_[i].pose, params_.footprint),
                                                    geometry::footprint_polygon(bodies_[j].pose, params_.footprint));
      }
      auto& was = overlapping_[i * n + j];
      if (overlap && !was) {
        ++report_.collisions;
        if (report_.first_collision.empty()) {
          std::ostringstream out;
          out << "t=" << time_ << " s: robots " << bodies_[i].id << " (" << bodies_[i].pose.x << ", "
              << bodies_[i].pose.y << ") and " << bodies_[j].id << " (" << bodies_[j].pose.x << ", "
              << bodies_[j].pose.y << ")";
          report_.first_collision = out.str();
        }
      }
      was = overlap ? 1 : 0;
    }
  }
}

void TrafficSim::step() {
  time_ += params_.dt;
  for (Body& body : bodies_) {
    if (body.active) advance(body);
  }
  if (params_.traffic) {
    last_update_ = manager_.update(time_);
    const UpdateResult& result = last_update_;
    for (const Grant& grant : result.grants) {
      Body* body = find(grant.robot_id);
      if (!body) continue;
      if (grant.version > body->version && grant.instruction != Instruction::kNone && !grant.route.empty()) {
        set_route(*body, grant.route, grant.version);
        manager_.report_progress({body->id, body->version, 0.0, {}}, time_);
      }
      if (grant.version == body->version) body->granted = grant.granted_distance;
      report_.max_wait_s = std::max(report_.max_wait_s, grant.waited_s);
    }
    for (const TrafficEvent& event : result.events) {
      switch (event.kind) {
        case TrafficEvent::Kind::kRerouted:
        case TrafficEvent::Kind::kDeadlockResolved:
          ++report_.reroutes;
          break;
        case TrafficEvent::Kind::kSidingSent:
          ++report_.sidings;
          break;
        case TrafficEvent::Kind::kUnresolvedDeadlock:
          ++report_.unresolved_cycles;
          break;
        default:
          break;
      }
    }
    if (params_.check_invariant) {
      const std::string violation = manager_.check_invariant();
      if (!violation.empty()) {
        ++report_.invariant_violations;
        if (report_.first_violation.empty()) report_.first_violation = "t=" + std::to_string(time_) + ": " + violation;
      }
    }
  }
  check_collisions();
  report_.sim_seconds = time_;
}

const SimReport& TrafficSim::run_until(double seconds) {
  while (time_ + 0.5 * params_.dt < seconds) step();
  return report_;
}

}  // namespace fleet::traffic
