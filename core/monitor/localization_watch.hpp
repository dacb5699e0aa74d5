#pragma once

#include <map>
#include <string>
#include <vector>

#include "geometry/pose.hpp"

namespace fleet::monitor {

/// How far each robot's estimate (RobotState) is from where the simulation has it (SimTruth).
/// An agent stamps both with the same simulated time when it publishes them, so an estimate is
/// compared with the truth of the same stamp, whichever arrives first.
class LocalizationWatch {
 public:
  /// An estimate `off_after` metres or more from the truth is reported once (take_far_off) until
  /// the error has come back under `back_under`.
  explicit LocalizationWatch(double off_after = 1.0, double back_under = 0.5)
      : off_after_(off_after), back_under_(back_under) {}

  void note_estimate(const std::string& robot_id, const geometry::Pose2& estimate, double sim_time);
  void note_truth(const std::string& robot_id, const geometry::Pose2& truth, double sim_time);

  /// Position errors (metres) compared so far, per robot.
  const std::map<std::string, std::vector<double>>& errors() const { return errors_; }

  /// The largest error of a robot: how large, when, and where the robot truly was.
  struct Worst {
    double error = 0.0;
    double sim_time = 0.0;
    geometry::Pose2 truth;
    geometry::Pose2 estimate;
  };
  const std::map<std::string, Worst>& worst() const { return worst_; }

  /// A robot whose estimate went `off_after` metres or more from the truth since the last call.
  struct FarOff {
    std::string robot_id;
    Worst at;
  };
  std::vector<FarOff> take_far_off();

 private:
  struct Stamped {
    geometry::Pose2 pose;
    double sim_time = -1.0;
  };
  void compare(const std::string& robot_id);

  std::map<std::string, Stamped> estimates_;
  std::map<std::string, Stamped> truths_;
  std::map<std::string, std::vector<double>> errors_;
  std::map<std::string, Worst> worst_;
  double off_after_;
  double back_under_;
  std::map<std::string, bool> far_off_;  ///< by robot: reported off, not back yet
  std::vector<FarOff> new_far_off_;
};

/// p95 and maximum of the position errors of each group of robots (a fleet, say), metres.
struct ErrorFigures {
  double p95 = 0.0;
  double max = 0.0;
  long samples = 0;
};
std::map<std::string, ErrorFigures> error_figures(const std::map<std::string, std::vector<double>>& errors,
                                                  const std::map<std::string, std::string>& group_of);

}  // namespace fleet::monitor
