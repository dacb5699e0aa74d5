#pragma once

#include <span>
#include <vector>

#include "geometry/polygon.hpp"
#include "geometry/pose.hpp"

namespace fleet::planning {

/// A planar scanning range finder, fixed per instance.
struct LidarConfiguration {
  int beams = 360;          ///< evenly spaced over a full turn
  double max_range = 4.0;   ///< metres; beams without a return report +infinity
  double min_range = 0.02;  ///< returns closer than this are dropped (the sensor's own housing)
};

/// One scan: beam i points at `pose.yaw + angle_min + i * angle_increment`.
struct LidarScan {
  geometry::Pose2 pose;  ///< sensor pose in the map frame at the time of the scan
  double angle_min = 0.0;
  double angle_increment = 0.0;
  double max_range = 0.0;
  std::vector<double> ranges;  ///< metres; +infinity for no return within max_range
};

/// The onboard range sensor the thesis's conclusion asks for, simulated by casting rays against
/// polygons: static obstacles and the other robots' true footprints (SimTruth). No noise here;
/// a sensor model adds it where needed.
class LidarSim {
 public:
  explicit LidarSim(const LidarConfiguration& configuration = {});
  LidarScan scan(const geometry::Pose2& pose, std::span<const geometry::Polygon> polygons) const;
  const LidarConfiguration& configuration() const { return configuration_; }

 private:
  LidarConfiguration configuration_;
};

}  // namespace fleet::planning
