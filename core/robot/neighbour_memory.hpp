#pragma once

#include <map>
#include <string>
#include <vector>

#include "robot/robot.hpp"

namespace fleet::robot {

/// The other robots as the FleetViews listed them. A robot missing from one view has not gone:
/// a server that just restarted lists robots as they report in, and for that moment an agent
/// trusting only the latest view would be blind to the others but for its lidar. A missing
/// robot stays where it was last listed, as every robot does while no view comes at all, until
/// views have gone without it for `forget_after_s`.
class NeighbourMemory {
 public:
  /// Sim seconds a robot no view lists is remembered (the default of the constructor). A view
  /// counts as complete only from a server that has run this long: a robot it has not heard from
  /// (frozen while the server restarted) would be forgotten by now from an incomplete view too.
  static constexpr double kForgetAfterS = 20.0;

  explicit NeighbourMemory(double forget_after_s = kForgetAfterS) : forget_after_s_(forget_after_s) {}

  /// The robots of a view that arrived at sim time `now` (this robot left out by the caller).
  void update(const std::vector<Neighbour>& listed, double now);
  /// The same for a view that lists every robot within `radius` of `centre` (a NeighbourView of
  /// a server that has heard from every robot): one remembered well inside that circle and not
  /// listed has left it, and is forgotten at once. Near the edge (within `edge` of it) it may
  /// have been listed from a pose a step older than ours; there it is kept as by update().
  void update_within(const std::vector<Neighbour>& listed, double now, geometry::Vec2 centre, double radius,
                     double edge = 1.0);
  /// Everyone remembered, by id.
  std::vector<Neighbour> current() const;

 private:
  struct Entry {
    Neighbour neighbour;
    double listed_at = 0.0;
  };
  double forget_after_s_;
  std::map<std::string, Entry> known_;
};

}  // namespace fleet::robot
