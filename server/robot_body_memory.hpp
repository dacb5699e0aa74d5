#pragma once

#include <map>
#include <string>

#include "geometry/pose.hpp"
#include "server/order_store.hpp"

namespace fleet::server {

/// Where each robot was last heard standing, kept in the order database. A restarted server
/// holds the bodies of the robots it has not heard from yet where they last stood, so that no
/// robot is granted a place another stands on while the other's messages are still on their way
/// (a secured participant's handshake over a lossy link takes seconds).
class RobotBodyMemory {
 public:
  /// A pose is stored again once it moved this far from the stored one.
  static constexpr double kMovedM = 0.02;
  static constexpr double kMovedRad = 0.05;
  /// Stored at most this often (wall seconds): one transaction for every robot that moved.
  static constexpr double kEveryS = 0.1;

  explicit RobotBodyMemory(OrderStore& store);

  /// The poses stored before this server started.
  const std::map<std::string, geometry::Pose2>& before_start() const { return before_start_; }

  /// Whether `remember` stores anything at `now_wall` (at most every kEveryS).
  bool due(double now_wall) const { return now_wall >= next_store_wall_; }

  /// Stores the poses of `heard` that moved since they were last stored.
  void remember(const std::map<std::string, geometry::Pose2>& heard, double now_wall);

 private:
  OrderStore& store_;
  std::map<std::string, geometry::Pose2> before_start_;
  std::map<std::string, geometry::Pose2> stored_;
  double next_store_wall_ = 0.0;
};

}  // namespace fleet::server
