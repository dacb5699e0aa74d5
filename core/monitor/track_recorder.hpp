#pragma once

#include <deque>
#include <istream>
#include <map>
#include <ostream>
#include <string>
#include <vector>

#include "geometry/pose.hpp"

namespace fleet::monitor {

/// One robot's track read back: poses in time order, sim seconds from the run's start.
struct Track {
  std::string robot_id;
  std::vector<double> sim_s;
  std::vector<geometry::Pose2> poses;
};

/// Reads what TrackRecorder::write_csv wrote. Throws std::runtime_error naming `source` and the
/// line of the first row that is not `robot,sim_s,x,y,yaw` with finite numbers.
std::vector<Track> read_tracks_csv(std::istream& in, const std::string& source);

/// The recent true tracks of every robot: what a soak writes next to a collision or a deadlock
/// report, so the minutes before it can be read back (who drove where, facing which way).
class TrackRecorder {
 public:
  /// Keeps `window_s` sim seconds per robot, one pose every `period_s` at most.
  explicit TrackRecorder(double window_s = 90.0, double period_s = 0.1) : window_s_(window_s), period_s_(period_s) {}

  void add(const std::string& robot_id, const geometry::Pose2& pose, double sim_time);

  /// Writes `robot,sim_s,x,y,yaw` rows of every robot from `since` on, sim time taken from
  /// `origin` (the run's start), oldest first per robot.
  void write_csv(std::ostream& out, double since, double origin) const;

 private:
  struct Sample {
    double sim_time;
    geometry::Pose2 pose;
  };
  double window_s_;
  double period_s_;
  std::map<std::string, std::deque<Sample>> tracks_;
};

}  // namespace fleet::monitor
