#include "perception/pallet_world.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace fleet::perception {

using geometry::Pose2;
using geometry::Vec2;

int PalletWorld::add(const Pose2& pose) {
  SimPallet p;
  int next = 1;
  for (const SimPallet& q : pallets_) next = std::max(next, q.id + 1);
  p.id = next;
  p.pose = pose;
  pallets_.push_back(p);
  return p.id;
}

bool PalletWorld::place(int id, const Pose2& pose) {
  for (SimPallet& p : pallets_) {
    if (p.id != id) continue;
    if (p.carried) return false;
    p.pose = pose;
    return true;
  }
  SimPallet p;
  p.id = id;
  p.pose = pose;
  pallets_.push_back(p);
  return true;
}

bool PalletWorld::remove(int id) {
  for (std::size_t i = 0; i < pallets_.size(); ++i) {
    if (pallets_[i].id != id) continue;
    if (pallets_[i].carried) return false;
    pallets_.erase(pallets_.begin() + static_cast<long>(i));
    // Forks hold indices into pallets_: those past the erased one move down by one.
    for (Forks& f : forks_) {
      if (f.carrying > static_cast<int>(i)) --f.carrying;
    }
    return true;
  }
  return false;
}

std::vector<Marker> PalletWorld::markers() const {
  std::vector<Marker> out;
  for (const SimPallet& p : pallets_) {
    if (p.carried) continue;
    Marker m;
    m.id = p.id;
    const Vec2 c = geometry::body_to_map(p.pose, {params_.marker_offset, 0.0});
    m.pose = {c.x, c.y, p.pose.yaw};
    out.push_back(m);
  }
  return out;
}

const SimPallet* PalletWorld::find(int id) const {
  for (const SimPallet& p : pallets_) {
    if (p.id == id) return &p;
  }
  return nullptr;
}

const SimPallet* PalletWorld::standing_near(Vec2 q, double radius) const {
  const SimPallet* best = nullptr;
  double best_d = radius;
  for (const SimPallet& p : pallets_) {
    if (p.carried) continue;
    const double d = geometry::distance(p.pose.position(), q);
    if (d <= best_d) {
      best_d = d;
      best = &p;
    }
  }
  return best;
}

PalletWorld::Forks& PalletWorld::forks(int robot) {
  for (Forks& f : forks_) {
    if (f.robot == robot) return f;
  }
  forks_.push_back({robot, false, -1});
  return forks_.back();
}

ForkEvent PalletWorld::update(int robot, const Pose2& robot_truth, bool fork_up) {
  Forks& f = forks(robot);
  ForkEvent ev;
  if (fork_up && !f.up) {
    // Rising: the pallet whose centre is nearest the seated position, if its pockets line up.
    const Vec2 seat = geometry::body_to_map(robot_truth, {params_.carry_x, 0.0});
    double best = std::numeric_limits<double>::infinity();
    int best_i = -1;
    for (std::size_t i = 0; i < pallets_.size(); ++i) {
      if (pallets_[i].carried) continue;
      const double d = geometry::distance(pallets_[i].pose.position(), seat);
      if (d < best) {
        best = d;
        best_i = static_cast<int>(i);
      }
    }
    ev.kind = ForkEvent::Kind::kLiftMissed;
    if (best_i >= 0) {
      SimPallet& p = pallets_[static_cast<std::size_t>(best_i)];
      const Vec2 rel = geometry::map_to_body(robot_truth, p.pose.position());
      // Seated, the pallet's marker face looks back at the forklift: pallet yaw = robot yaw + pi.
      const double dyaw = geometry::angle_diff(p.pose.yaw, robot_truth.yaw + std::numbers::pi);
      if (std::abs(rel.x - params_.carry_x) <= params_.lift_depth_tol && std::abs(rel.y) <= params_.lift_lateral_tol &&
          std::abs(dyaw) <= params_.lift_yaw_tol) {
        p.carried = true;
        p.offset = geometry::map_pose_to_body(robot_truth, p.pose);
        f.carrying = best_i;
        ev.kind = ForkEvent::Kind::kLifted;
        ev.pallet_id = p.id;
        ev.offset = p.offset;
      }
    }
  } else if (!fork_up && f.up && f.carrying >= 0) {
    SimPallet& p = pallets_[static_cast<std::size_t>(f.carrying)];
    p.carried = false;
    ev.kind = ForkEvent::Kind::kPutDown;
    ev.pallet_id = p.id;
    f.carrying = -1;
  }
  f.up = fork_up;
  if (f.carrying >= 0) {
    SimPallet& p = pallets_[static_cast<std::size_t>(f.carrying)];
    p.pose = geometry::body_pose_to_map(robot_truth, p.offset);
  }
  return ev;
}

}  // namespace fleet::perception
