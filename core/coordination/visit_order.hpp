#pragma once

#include <cstddef>
#include <deque>
#include <vector>

#include "traffic/conflict_zones.hpp"

namespace fleet::coordination {

/// The order in which robots pass the places of a road site, kept however late each robot runs:
/// each robot's visits, the one it is in first, then those planned, each with the plan step at
/// which it begins. A robot passes into its next visit (the midpoint of its move, up to which its
/// body is inside the place it leaves and past which inside the one it goes to) only once every
/// visit of a place conflicting with it, for the two robots' vehicle types, that the plan begins
/// at an earlier step has ended. Every such dependency points to an earlier plan step, or,
/// within one step, along the robots' follow relation, which PlacePibt keeps acyclic: so some robot
/// can always move, and no robot waits for one that waits for it [Hönig 2019, section IV]. The
/// grid's ExecutionGraph is the same order for places that conflict only with themselves.
class VisitOrder {
 public:
  explicit VisitOrder(const traffic::ConflictZones& zones) : zones_(zones), open_(zones.place_count()) {}

  /// A robot of vehicle type `type` standing at `place`; returns its number (0, 1, ...).
  int add_robot(int type, int place);
  int robots() const { return static_cast<int>(robots_.size()); }
  /// Plans the robot's next visit after its last: of `place`, beginning at plan step `step`.
  void plan(int robot, int place, std::size_t step);
  /// The robot stands at `place` from now on, its plan dropped: its visit there begins before any
  /// other's, so every visit planned of a place conflicting with it waits until it leaves. Place -1:
  /// it is off the roads and in nobody's way (it has no visits until it stands somewhere again).
  void stand(int robot, int place);
  /// Drops the robot's visits from its `k`-th on (0: the current one; at least the one it is in
  /// is kept).
  void drop_from(int robot, int k);
  /// Whether the robot is on the roads (has a visit).
  bool present(int robot) const { return !at(robot).visits.empty(); }
  /// The place the robot's body is in: its current visit's, or the next one's once it has left;
  /// -1 off the roads.
  int place(int robot) const;
  /// The place of its current visit (the one it leaves while moving).
  int current(int robot) const { return present(robot) ? at(robot).visits.front().place : -1; }
  /// The place of its next visit, -1 when none is planned.
  int next(int robot) const;
  /// The place of its last planned visit (its current one when none is planned).
  int last_planned(int robot) const { return present(robot) ? at(robot).visits.back().place : -1; }
  /// Visits planned after its current one.
  int pending(int robot) const { return present(robot) ? static_cast<int>(at(robot).visits.size()) - 1 : 0; }
  /// The places of its visits from the one it is in on.
  std::vector<int> places_ahead(int robot) const;
  /// Whether the robot has left its current visit (passed the midpoint into the next).
  bool has_left(int robot) const { return at(robot).left; }
  /// A robot whose visit of a place conflicting with robot's next one, planned to begin earlier,
  /// has not ended; -1 when none (robot may pass into its next visit) or when none is planned.
  int waits_for(int robot) const { return waits_for(robot, 1); }
  /// The same for its `visit`-th visit (1: the next): a robot whose visit this one must wait for,
  /// -1 when none. Visits ended stay ended, so a visit waiting for none may be granted ahead.
  int waits_for(int robot, int visit) const;
  /// The place of its `k`-th visit (0: the current one).
  int visit_place(int robot, int k) const { return at(robot).visits[static_cast<std::size_t>(k)].place; }
  /// The robot passed into its next visit: its current one has ended. std::logic_error when it
  /// waits for a robot or has no next visit.
  void leave(int robot);
  /// The robot reached its next visit's place; it leaves the current one first if it has not.
  void arrive(int robot);
  /// The robots of a wait-for cycle (each waits for the next), empty when there is none: a
  /// monitor of the order's promise.
  std::vector<int> wait_cycle() const;

 private:
  struct Visit {
    int place = 0;
    std::size_t step = 0;
  };
  struct Robot {
    int type = 0;
    std::deque<Visit> visits;  ///< empty only off the roads
    bool left = false;
  };
  const Robot& at(int robot) const { return robots_[static_cast<std::size_t>(robot)]; }
  /// A visit not yet ended, listed under its place: who may have to be waited for there.
  struct Open {
    int robot = 0;
    std::size_t step = 0;
  };
  void open(int robot, const Visit& visit);
  void close(int robot, const Visit& visit);

  const traffic::ConflictZones& zones_;
  std::vector<Robot> robots_;
  std::vector<std::vector<Open>> open_;  ///< by place: the visits of it not yet ended
};

}  // namespace fleet::coordination
