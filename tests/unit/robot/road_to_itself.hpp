#pragma once

#include <vector>

#include "geometry/polygon.hpp"
#include "robot/navigation.hpp"
#include "robot/robot.hpp"

namespace fleet::test {

/// A traffic manager with the road to itself: the whole route granted, an asked-for work area clear.
inline robot::TrafficPermit all_it_asks_for(const robot::TrafficRoute& route) {
  robot::TrafficPermit permit;
  if (!route.work_area.empty() && route.points.size() < 2) {
    permit.area = robot::TrafficPermit::Area::kClear;
  } else {
    permit.version = route.version;
    permit.granted_index = static_cast<int>(route.points.size()) - 1;
    permit.granted_distance = 1e6;
  }
  return permit;
}

/// Grants the robot every point of whatever route it drives now, as a manager with no other robot would.
inline void grant_everything(robot::Robot& robot) {
  robot::TrafficPermit all_of_it;
  all_of_it.version = robot.navigation().follower().version();
  all_of_it.granted_index = 1000;
  all_of_it.granted_distance = 1e9;
  robot.set_traffic_grant(all_of_it);
}

/// One control step among robots standing still: the robot hears of them (`neighbours`) and its
/// simulated sensors see their bodies.
inline void step_among(robot::Robot& robot, const std::vector<robot::Neighbour>& neighbours,
                       const std::vector<geometry::Polygon>& bodies) {
  robot.navigation().set_neighbours(neighbours);
  robot.navigation().set_true_neighbours(bodies);
  robot.step();
}

}  // namespace fleet::test
