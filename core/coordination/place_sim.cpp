#include "coordination/place_sim.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "geometry/polygon.hpp"

namespace fleet::coordination {

PlaceSim::PlaceSim(const map::RoadGraph& graph, const traffic::ConflictZones& zones, const PlaceSimParams& params,
                   const std::vector<int>& goal_points, const std::vector<int>& start_points)
    : zones_(zones),
      graph_(graph, zones),
      planner_(graph_, params.seed),
      order_(zones),
      params_(params),
      rng_(params.seed) {
  for (const int point : goal_points) {
    const int place = zones.place_of(point);
    if (std::find(goal_places_.begin(), goal_places_.end(), place) == goal_places_.end()) goal_places_.push_back(place);
  }
  for (const auto& type : zones.vehicle_types()) {
    for (const auto& v : type.footprint) reach_ = std::max(reach_, 2.0 * std::hypot(v.x, v.y));
  }
  if (const double move = graph_.mean_move_length(); move > 0.0) plan_period_s_ = move / params_.speed;
  for (std::size_t i = 0; i < start_points.size(); ++i) {
    Body body;
    body.type = i < params_.robot_types.size() ? params_.robot_types[i] : 0;
    const int at = zones.place_of(start_points[i]);
    order_.add_robot(body.type, at);
    // A robot stands along its lane, not across it.
    if (const auto& next = graph_.successors(body.type, at); !next.empty()) {
      const geometry::Vec2 d = zones.position(next.front()) - zones.position(at);
      body.yaw = std::atan2(d.y, d.x);
    }
    bodies_.push_back(body);
  }
  overlapping_.assign(bodies_.size() * bodies_.size(), 0);
  report_.robots = static_cast<int>(bodies_.size());
}

void PlaceSim::start_next_goal(std::size_t robot) {
  if (goal_places_.size() < 2) return;
  Body& body = bodies_[robot];
  std::uniform_int_distribution<std::size_t> pick(0, goal_places_.size() - 1);
  const int at = order_.current(static_cast<int>(robot));
  int next = at;
  while (next == at) next = goal_places_[pick(rng_)];
  if (!body.carrying) body.trip_start = time_;
  body.goal = next;
  body.still_since = time_;
}

geometry::Pose2 PlaceSim::pose_of(std::size_t robot) const {
  const Body& body = bodies_[robot];
  const int next = order_.next(static_cast<int>(robot));
  const geometry::Vec2 a = zones_.position(order_.current(static_cast<int>(robot)));
  if (next < 0 || body.length <= 0.0) return {a.x, a.y, body.yaw};
  const geometry::Vec2 b = zones_.position(next);
  const double f = std::min(1.0, body.progress / body.length);
  return {a.x + f * (b.x - a.x), a.y + f * (b.y - a.y), std::atan2(b.y - a.y, b.x - a.x)};
}

void PlaceSim::plan_step() {
  // The plan runs ahead of the robots: each is planned from the last place planned for it.
  std::vector<PlaceRobot> robots;
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Body& body = bodies_[i];
    const int planned = order_.last_planned(static_cast<int>(i));
    const bool behind = order_.pending(static_cast<int>(i)) >= params_.plan_ahead;
    const bool errand = body.goal >= 0 && planned != body.goal;
    robots.push_back({body.type, planned, errand ? body.goal : -1, !errand || behind});
  }
  const auto start = std::chrono::steady_clock::now();
  const std::vector<int> next = planner_.plan(robots);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  report_.planning_ms_max = std::max(report_.planning_ms_max, ms);
  planning_ms_sum_ += ms;
  report_.planning_ms_mean = planning_ms_sum_ / static_cast<double>(++report_.plan_steps);
  const std::string broken = broken_step_rule(zones_, robots, next);
  if (!broken.empty() && report_.plan_conflicts++ == 0) {
    std::ostringstream out;
    out << "t=" << time_ << " s: " << broken;
    report_.first_plan_conflict = out.str();
  }
  ++plan_step_;
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    if (next[i] == robots[i].place) continue;
    order_.plan(static_cast<int>(i), next[i], plan_step_);
    if (order_.pending(static_cast<int>(i)) == 1) begin_move(i);
    if (next[i] == bodies_[i].goal) planner_.reached_goal(static_cast<int>(i));
  }
}

void PlaceSim::begin_move(std::size_t robot) {
  Body& body = bodies_[robot];
  body.progress = 0.0;
  body.length = graph_.step_length(order_.current(static_cast<int>(robot)), order_.next(static_cast<int>(robot)));
  body.pause_at = -1.0;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  if (params_.delay_probability > 0.0 && unit(rng_) < params_.delay_probability) {
    body.pause_at = unit(rng_) * body.length;
    body.pause_s = params_.delay_min_s + unit(rng_) * (params_.delay_max_s - params_.delay_min_s);
    ++report_.delays;
  }
}

void PlaceSim::drive(std::size_t robot) {
  Body& body = bodies_[robot];
  const int self = static_cast<int>(robot);
  if (order_.next(self) < 0) return;
  double step = params_.speed * params_.dt;
  if (body.pause_at >= 0.0 && body.progress + step >= body.pause_at) {
    if (body.progress < body.pause_at) {
      step = body.pause_at - body.progress;
    } else if (body.pause_s > 0.0) {
      body.pause_s -= params_.dt;
      return;
    }
  }
  // Up to the midpoint the body is inside the place it leaves; past it, inside the next one.
  const double midpoint = 0.5 * body.length;
  if (!order_.has_left(self) && body.progress + step >= midpoint) {
    if (order_.waits_for(self) >= 0) {
      body.progress = std::max(body.progress, std::nextafter(midpoint, 0.0));
      return;
    }
    order_.leave(self);
  }
  body.progress = std::min(body.length, body.progress + step);
  if (body.progress >= body.length) arrive(robot);
}

void PlaceSim::note_wait_cycle() {
  // The monitor of the order's promise: robots never wait for one another in a cycle.
  const std::vector<int> cycle = order_.wait_cycle();
  if (cycle.empty() || report_.wait_cycles++ > 0) return;
  std::ostringstream out;
  out << "t=" << time_ << " s: robots";
  for (const int robot : cycle) out << " " << robot + 1;
  out << " wait in a cycle";
  report_.first_wait_cycle = out.str();
}

void PlaceSim::check_collisions() {
  const std::size_t n = bodies_.size();
  const auto& types = zones_.vehicle_types();
  std::vector<geometry::Pose2> poses(n);
  for (std::size_t i = 0; i < n; ++i) poses[i] = pose_of(i);
  auto body = [&](std::size_t i) {
    geometry::Polygon polygon;
    for (const auto& v : types[static_cast<std::size_t>(bodies_[i].type)].footprint) {
      polygon.push_back(geometry::body_to_map(poses[i], v));
    }
    return polygon;
  };
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      auto& was = overlapping_[i * n + j];
      const bool near = std::hypot(poses[i].x - poses[j].x, poses[i].y - poses[j].y) < reach_;
      const bool overlap = near && geometry::polygons_overlap(body(i), body(j));
      if (overlap && !was && report_.collisions++ == 0) {
        std::ostringstream out;
        out << "t=" << time_ << " s: robots " << i + 1 << " and " << j + 1 << " at places "
            << place(static_cast<int>(i)) << " and " << place(static_cast<int>(j));
        report_.first_collision = out.str();
      }
      was = overlap ? 1 : 0;
    }
  }
}

std::string PlaceSim::stall_note(std::size_t robot) const {
  // The stalled robot and every robot near it: a jam is read from where they all stand.
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(2);
  out << "t=" << time_ << " s:";
  const geometry::Vec2 at = zones_.position(place(static_cast<int>(robot)));
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Body& b = bodies_[i];
    const geometry::Vec2 p = zones_.position(place(static_cast<int>(i)));
    if (geometry::distance(p, at) > 4.0) continue;
    out << "\n      robot " << i + 1 << " (type " << b.type << ") at place " << place(static_cast<int>(i)) << " ("
        << p.x << ", " << p.y << ")";
    if (b.goal >= 0) {
      const geometry::Vec2 g = zones_.position(b.goal);
      out << " to place " << b.goal << " (" << g.x << ", " << g.y << "), still for " << time_ - b.still_since << " s";
    } else {
      out << " working";
    }
    if (const std::vector<int> ahead = order_.places_ahead(static_cast<int>(i)); ahead.size() > 1) {
      out << ", planned on to place";
      for (std::size_t k = 1; k < ahead.size(); ++k) out << " " << ahead[k];
      if (const int other = order_.waits_for(static_cast<int>(i)); other >= 0) out << ", waits for robot " << other + 1;
    }
  }
  // What keeps the stalled robot from each of its moves: the robots whose bodies are in the way.
  const Body& stalled = bodies_[robot];
  const int from = place(static_cast<int>(robot));
  for (const int next : graph_.successors(stalled.type, from)) {
    out << "\n      move to place " << next << ":";
    for (std::size_t j = 0; j < bodies_.size(); ++j) {
      const Body& b = bodies_[j];
      if (j != robot && zones_.conflict(stalled.type, next, b.type, place(static_cast<int>(j))))
        out << " robot " << j + 1;
    }
  }
  return out.str();
}

void PlaceSim::arrive(std::size_t robot) {
  Body& body = bodies_[robot];
  const int self = static_cast<int>(robot);
  body.yaw = pose_of(robot).yaw;
  order_.arrive(self);
  if (order_.pending(self) > 0) begin_move(robot);
  body.still_since = time_;
  body.deadlocked = false;
  ++report_.moves;
  if (body.goal >= 0 && order_.pending(self) == 0 && order_.current(self) == body.goal) {
    ++report_.goals_reached;
    if (body.carrying) {
      ++report_.trips;
      trip_time_sum_ += time_ + params_.dwell - body.trip_start;
      report_.mean_trip_s = trip_time_sum_ / static_cast<double>(report_.trips);
    }
    body.carrying = !body.carrying;
    body.goal = -1;
    body.dwell_until = time_ + params_.dwell;
  }
}

void PlaceSim::note_stall(std::size_t robot) {
  Body& body = bodies_[robot];
  if (body.goal < 0) return;
  report_.max_wait_s = std::max(report_.max_wait_s, time_ - body.still_since);
  if (!body.deadlocked && time_ - body.still_since >= params_.deadlock_timeout) {
    body.deadlocked = true;
    ++report_.deadlocks;
    report_.stall_notes.push_back(stall_note(robot));
  }
}

void PlaceSim::step() {
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Body& body = bodies_[i];
    if (body.goal < 0 && order_.pending(static_cast<int>(i)) == 0 && time_ >= body.dwell_until) start_next_goal(i);
  }
  if (time_ + 1e-9 >= next_plan_) {
    plan_step();
    next_plan_ += plan_period_s_;
  }
  note_wait_cycle();
  time_ += params_.dt;
  for (std::size_t i = 0; i < bodies_.size(); ++i) drive(i);
  for (std::size_t i = 0; i < bodies_.size(); ++i) note_stall(i);
  check_collisions();
  report_.sim_seconds = time_;
}

const PlaceSimReport& PlaceSim::run_until(double seconds) {
  while (time_ + 0.5 * params_.dt < seconds) step();
  return report_;
}

}  // namespace fleet::coordination
