#pragma once

#include <map>
#include <string>
#include <vector>

#include "geometry/pose.hpp"

namespace fleet::monitor {

/// A robot that worked on an order without progress for the monitor's timeout.
struct Deadlock {
  std::string robot_id;
  std::string task;                      ///< what it was working on: order id and phase
  double since = 0.0;                    ///< sim time of its last progress
  double detected = 0.0;                 ///< sim time the timeout passed
  geometry::Pose2 pose;                  ///< where it stood (truth)
  std::vector<std::string> waiting_for;  ///< the robots its traffic grant said it waited for
};

/// Ground-truth progress watch for demo and soak runs: a robot with an order that has
/// neither moved `move_threshold` metres nor changed its order or phase for `timeout_s` sim
/// seconds counts as deadlocked, once per episode. A robot queued behind robots that move (the
/// robots it waits for, as traffic reports them, and the ones they wait for) waits its turn: it
/// counts only after `queue_bound_s` without progress. A robot whose order stays in one phase for
/// `phase_bound_s` counts too, however it moves meanwhile (robots pushed back and forth, re-routed
/// round and round, never getting anywhere). Also keeps the longest continuous WAITING.
class ProgressMonitor {
 public:
  explicit ProgressMonitor(double timeout_s = 60.0, double move_threshold = 0.02, double queue_bound_s = 180.0,
                           double phase_bound_s = 900.0);

  /// The robot's true pose at sim time `t`; `task` is its open order and phase, empty when it has
  /// none. `working`: it stands by design (an arm at work, a loader's transporter holding its
  /// pallet, a loader waiting for it): that is progress, though its phase stays bounded. Returns
  /// true when this update detected a new deadlock (see deadlocks()).
  bool update(const std::string& robot_id, const geometry::Pose2& pose, const std::string& task, double t,
              bool working = false);
  /// The robots `robot_id` waits for, from its latest traffic grant; empty when none.
  void note_waiting_for(const std::string& robot_id, std::vector<std::string> robots);
  /// The robot's reported task state, for the longest wait.
  void note_state(const std::string& robot_id, const std::string& task_state, double t);
  /// The robot left the run (killed, lost): its watch restarts when it comes back.
  void forget(const std::string& robot_id);

  const std::vector<Deadlock>& deadlocks() const { return deadlocks_; }
  /// Longest continuous WAITING of any robot so far, sim seconds (ongoing waits included at `now`).
  double max_wait_s(double now) const;

 private:
  struct Watch {
    geometry::Pose2 anchor;  ///< where it was at its last progress
    std::string task;
    double since = 0.0;
    bool reported = false;
    geometry::Pose2 moved_from;  ///< where it was when it last moved, order or not
    double moved_at = 0.0;
    double queue_moved = 0.0;    ///< the latest move of a robot it waited for since its own progress
    double task_since = 0.0;     ///< sim time its order entered its current phase
    bool task_reported = false;  ///< this phase has been counted (standing or getting nowhere)
  };
  /// When a robot that `robot_id` waits for, directly or through others, last moved; -infinity
  /// when it waits for nobody.
  double queue_moved_at(const std::string& robot_id) const;

  double timeout_s_;
  double move_threshold_;
  double queue_bound_s_;
  double phase_bound_s_;
  std::map<std::string, Watch> watches_;
  std::map<std::string, std::vector<std::string>> waiting_for_;
  std::map<std::string, double> waiting_since_;
  double max_wait_s_ = 0.0;
  std::vector<Deadlock> deadlocks_;
};

}  // namespace fleet::monitor
