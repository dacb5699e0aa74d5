#include "coordination/place_sim.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "geometry/polygon.hpp"

namespace fleet::coordination {

PlaceSim::PlaceSim(const map::RoadGraph& graph, const traffic::ConflictZones& zones, const PlaceSimParams& params,
                   const std::vector<int>& goal_points, const std::vector<int>& start_points)
    : zones_(zones), graph_(graph, zones), planner_(graph_, params.seed), params_(params), rng_(params.seed) {
  for (const int point : goal_points) {
    const int place = zones.place_of(point);
    if (std::find(goal_places_.begin(), goal_places_.end(), place) == goal_places_.end()) goal_places_.push_back(place);
  }
  double length_sum = 0.0;
  int lengths = 0;
  for (int place = 0; place < graph_.place_count(); ++place) {
    for (const int next : graph_.successors(0, place)) {
      length_sum += graph_.step_length(place, next);
      ++lengths;
    }
  }
  if (lengths > 0) idle_step_s_ = length_sum / lengths / params_.speed;
  for (std::size_t i = 0; i < start_points.size(); ++i) {
    Body body;
    body.type = i < params_.robot_types.size() ? params_.robot_types[i] : 0;
    body.place = zones.place_of(start_points[i]);
    // A robot stands along its lane, not across it.
    if (const auto& next = graph_.successors(body.type, body.place); !next.empty()) {
      const geometry::Vec2 d = zones.position(next.front()) - zones.position(body.place);
      body.yaw = std::atan2(d.y, d.x);
    }
    bodies_.push_back(body);
  }
  overlapping_.assign(bodies_.size() * bodies_.size(), 0);
  report_.robots = static_cast<int>(bodies_.size());
}

void PlaceSim::start_next_goal(Body& body) {
  if (goal_places_.size() < 2) return;
  std::uniform_int_distribution<std::size_t> pick(0, goal_places_.size() - 1);
  int next = body.place;
  while (next == body.place) next = goal_places_[pick(rng_)];
  if (!body.carrying) body.trip_start = time_;
  body.goal = next;
  body.still_since = time_;
}

geometry::Pose2 PlaceSim::pose_at(const Body& body, int next, double fraction) const {
  const geometry::Vec2 a = zones_.position(body.place);
  const geometry::Vec2 b = zones_.position(next);
  geometry::Pose2 pose{a.x + fraction * (b.x - a.x), a.y + fraction * (b.y - a.y), body.yaw};
  if (next != body.place) pose.yaw = std::atan2(b.y - a.y, b.x - a.x);
  return pose;
}

void PlaceSim::check_plan(const std::vector<PlaceRobot>& robots, const std::vector<int>& next) {
  const std::string broken = broken_step_rule(zones_, robots, next);
  if (broken.empty()) return;
  ++report_.plan_conflicts;
  if (report_.first_plan_conflict.empty()) {
    std::ostringstream out;
    out << "t=" << time_ << " s: " << broken;
    report_.first_plan_conflict = out.str();
  }
}

void PlaceSim::check_collisions(const std::vector<int>& next, double dt) {
  const std::size_t n = bodies_.size();
  const auto& types = zones_.vehicle_types();
  std::vector<geometry::Polygon> bodies(n);
  for (const double fraction : {0.25, 0.5, 0.75, 1.0}) {
    for (std::size_t i = 0; i < n; ++i) {
      const geometry::Pose2 pose = pose_at(bodies_[i], next[i], fraction);
      bodies[i].clear();
      for (const auto& v : types[static_cast<std::size_t>(bodies_[i].type)].footprint) {
        bodies[i].push_back(geometry::body_to_map(pose, v));
      }
    }
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t j = i + 1; j < n; ++j) {
        const bool overlap = geometry::polygons_overlap(bodies[i], bodies[j]);
        auto& was = overlapping_[i * n + j];
        if (overlap && !was) {
          ++report_.collisions;
          if (report_.first_collision.empty()) {
            std::ostringstream out;
            out << "t=" << time_ + fraction * dt << " s: robots " << i + 1 << " and " << j + 1 << " at places "
                << bodies_[i].place << " -> " << next[i] << " and " << bodies_[j].place << " -> " << next[j];
            report_.first_collision = out.str();
          }
        }
        was = overlap ? 1 : 0;
      }
    }
  }
}

std::string PlaceSim::stall_note(std::size_t robot) const {
  // The stalled robot and every robot near it: a jam is read from where they all stand.
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(2);
  out << "t=" << time_ << " s:";
  const geometry::Vec2 at = zones_.position(bodies_[robot].place);
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const Body& b = bodies_[i];
    const geometry::Vec2 p = zones_.position(b.place);
    if (geometry::distance(p, at) > 2.0) continue;
    out << "\n      robot " << i + 1 << " (type " << b.type << ") at place " << b.place << " (" << p.x << ", " << p.y
        << ")";
    if (b.goal >= 0) {
      const geometry::Vec2 g = zones_.position(b.goal);
      out << " to place " << b.goal << " (" << g.x << ", " << g.y << "), still for " << time_ - b.still_since << " s";
    } else {
      out << " working";
    }
  }
  return out.str();
}

void PlaceSim::arrive(std::size_t robot, int next) {
  Body& body = bodies_[robot];
  if (next != body.place) {
    body.yaw = pose_at(body, next, 1.0).yaw;
    body.place = next;
    body.still_since = time_;
    body.deadlocked = false;
  } else if (body.goal >= 0) {
    report_.max_wait_s = std::max(report_.max_wait_s, time_ - body.still_since);
    if (!body.deadlocked && time_ - body.still_since >= params_.deadlock_timeout) {
      body.deadlocked = true;
      ++report_.deadlocks;
      report_.stall_notes.push_back(stall_note(robot));
    }
  }
  if (body.goal >= 0 && body.place == body.goal) {
    ++report_.goals_reached;
    planner_.reached_goal(static_cast<int>(robot));
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

void PlaceSim::step() {
  for (Body& body : bodies_) {
    if (body.goal < 0 && time_ >= body.dwell_until) start_next_goal(body);
  }
  std::vector<PlaceRobot> robots;
  for (const Body& body : bodies_) robots.push_back({body.type, body.place, body.goal, body.goal < 0});
  const auto start = std::chrono::steady_clock::now();
  const std::vector<int> next = planner_.plan(robots);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  report_.planning_ms_max = std::max(report_.planning_ms_max, ms);
  planning_ms_sum_ += ms;
  report_.planning_ms_mean = planning_ms_sum_ / static_cast<double>(++plans_);
  check_plan(robots, next);
  double longest = 0.0;
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    longest = std::max(longest, graph_.step_length(bodies_[i].place, next[i]));
  }
  const double dt = longest > 0.0 ? longest / params_.speed : idle_step_s_;
  if (longest > 0.0) ++report_.moves;
  check_collisions(next, dt);
  time_ += dt;
  for (std::size_t i = 0; i < bodies_.size(); ++i) arrive(i, next[i]);
  report_.sim_seconds = time_;
}

const PlaceSimReport& PlaceSim::run_until(double seconds) {
  while (time_ < seconds) step();
  return report_;
}

}  // namespace fleet::coordination
