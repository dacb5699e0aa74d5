#pragma once

#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "geometry/polygon.hpp"

namespace fleet::monitor {

struct Collision {
  double sim_time = 0.0;
  std::string robot_a;
  std::string robot_b;
  geometry::Pose2 pose_a;
  geometry::Pose2 pose_b;
};

/// Ground truth collision monitor (simulation only): any overlap of two robots' true footprints
/// is a collision. A pair that stays in contact counts once, until it separates.
class CollisionMonitor {
 public:
  /// `max_skew` is how far apart in sim time two truths may be and still be compared.
  explicit CollisionMonitor(double max_skew = 0.1) : max_skew_(max_skew) {}

  /// Records a robot's true pose; returns the collisions this update starts.
  std::vector<Collision> update(const std::string& robot_id, const geometry::Pose2& pose,
                                const geometry::Footprint& footprint, double sim_time);
  /// The same for a footprint polygon in the body frame (a vehicle profile's).
  std::vector<Collision> update(const std::string& robot_id, const geometry::Pose2& pose,
                                const geometry::Polygon& body, double sim_time);

  /// Forgets a robot (its process ended).
  void remove(const std::string& robot_id);

  const std::vector<Collision>& collisions() const { return collisions_; }

 private:
  struct Truth {
    geometry::Pose2 pose;
    geometry::Polygon body;  ///< body frame
    double radius = 0.0;     ///< of the circle round the body origin that holds the body
    double sim_time = 0.0;
  };
  double max_skew_;
  std::map<std::string, Truth> truths_;
  std::set<std::pair<std::string, std::string>> in_contact_;
  std::vector<Collision> collisions_;
};

}  // namespace fleet::monitor
