#pragma once
// A forklift's task executor in a small world for its tests: a straight-line planner that
// answers every plan request (or refuses, or ends short), a pallet world, a marker camera, and
// the robot's true pose integrated from the executor's commands at 70 Hz.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "perception/marker_camera.hpp"
#include "perception/pallet_world.hpp"
#include "task/task_executor.hpp"

namespace fleet::task::test_world {

using geometry::Pose2;
using Kind = TaskReport::Kind;
using orders::OrderPhase;

constexpr double kDt = 1.0 / 70.0;
// table_a: areas A1 and A2 below the lower road (y = 0.4), home H1 on it.
const Pose2 kA1{0.90, 0.12, std::numbers::pi / 2};
const Pose2 kA2{2.10, 0.12, std::numbers::pi / 2};
const Pose2 kHome{0.60, 0.40, 0.0};

/// A straight-line "planner": samples every 10 cm from the start to the goal's position.
inline std::vector<Pose2> straight(const Pose2& from, const Pose2& to) {
  const double len = geometry::distance(from.position(), to.position());
  const int n = std::max(1, static_cast<int>(std::ceil(len / 0.1)));
  std::vector<Pose2> path;
  for (int i = 0; i <= n; ++i) {
    const double t = static_cast<double>(i) / n;
    path.push_back({from.x + t * (to.x - from.x), from.y + t * (to.y - from.y), to.yaw});
  }
  return path;
}

struct World {
  ExecutorParams params;
  TaskExecutor exec{params, kHome};
  perception::PalletWorld pallets;
  perception::MarkerCamera camera;
  Pose2 truth = kHome;
  double t = 0.0;
  std::vector<TaskReport> reports;
  std::vector<Transition> transitions;
  int plan_requests = 0;
  bool answer_plans = true;
  int plans_short = 0;  ///< this many plans end 0.3 m short of their goal

  explicit World(ExecutorParams executor_params = {})
      : params(executor_params),
        pallets([] {
          perception::PalletWorldParams p;
          p.carry_x = ExecutorParams{}.geometry.carry_x;
          p.marker_offset = ExecutorParams{}.geometry.marker_offset;
          return p;
        }()),
        camera(
            [] {
              perception::MarkerCameraParams p;
              p.camera_x = ExecutorParams{}.geometry.camera_x;
              return p;
            }(),
            9) {}

  void step() {
    std::vector<perception::MarkerDetection> dets;
    if (camera.frame_due(t)) {
      const auto markers = pallets.markers();
      dets = camera.capture(t, truth, markers);
    }
    const TaskOutput out = exec.step({t, truth, dets});
    pallets.update(0, truth, out.fork_up);
    truth = control::integrate_twist(truth, out.twist, kDt);
    if (auto req = exec.take_plan_request()) {
      ++plan_requests;
      if (answer_plans && plans_short > 0) {
        --plans_short;
        const double len = geometry::distance(truth.position(), req->goal.position());
        const double keep = std::max(0.0, len - 0.3) / std::max(len, 1e-9);
        const Pose2 short_goal{truth.x + keep * (req->goal.x - truth.x), truth.y + keep * (req->goal.y - truth.y),
                               req->goal.yaw};
        exec.path_received(req->id, straight(truth, short_goal));
      } else if (answer_plans) {
        exec.path_received(req->id, straight(truth, req->goal));
      } else {
        exec.plan_failed(req->id);
      }
    }
    for (auto& r : exec.take_reports()) reports.push_back(r);
    for (auto& tr : exec.take_transitions()) transitions.push_back(tr);
    t += kDt;
  }

  template <typename Pred>
  bool run_until(Pred pred, double max_time) {
    const double end = t + max_time;
    while (t < end) {
      if (pred()) return true;
      step();
    }
    return pred();
  }

  std::vector<Kind> kinds() const {
    std::vector<Kind> k;
    for (const auto& r : reports) k.push_back(r.kind);
    return k;
  }
};

}  // namespace fleet::task::test_world
