#pragma once
// The robots as the server last heard them, and where their bodies stand: the server fills the
// entries from RobotState and marks them lost; dispatch, intake and commands ask the roster who
// has reported, whose body covers an area and whose stands on a place.

#include <map>
#include <set>
#include <string>

#include "config/fleet_config.hpp"
#include "geometry/polygon.hpp"
#include "map/site.hpp"
#include "model/messages.hpp"

namespace fleet::orders {

/// A robot as the server knows it: registered with its first RobotState.
struct RobotEntry {
  std::string id;
  std::string fleet_id;
  model::RobotState last;
  double last_seen_wall = 0.0;  ///< wall seconds of the last RobotState
  bool lost = false;
  bool registered = false;
  bool stalled = false;  ///< missed its RobotState deadline (DDS) and not heard from since
};

class RobotRoster {
 public:
  /// `config` names each robot's fleet and footprint; it must outlive the roster.
  explicit RobotRoster(const config::FleetConfig& config) : config_(config) {}

  /// Every robot heard of by id, registered or not (a robot of a restored order that has not
  /// reported since the restart is entered unregistered).
  std::map<std::string, RobotEntry>& entries() { return entries_; }
  const std::map<std::string, RobotEntry>& entries() const { return entries_; }

  /// Whether `robot_id` has reported (a lost robot too).
  bool registered(const std::string& robot_id) const;
  /// The robots that have reported (lost ones too).
  std::set<std::string> registered_ids() const;
  /// Their number.
  int registered_count() const;

  /// The robot's body where it last reported: its fleet's footprint, as a convex hull since the
  /// traffic regions are convex (a hull covers every concave body); the default footprint for a
  /// robot the configuration does not name.
  geometry::Polygon body_of(const RobotEntry& robot) const;
  /// A registered robot whose body overlaps `area`, or "".
  std::string robot_under(const geometry::Polygon& area) const;
  /// Whether a registered robot's body stands on loading area `area` (body_stands_on): on its
  /// load's point or where a vehicle stands `approach_distance` out from it to handle the load.
  bool someone_stands_on(const map::LoadingArea& area, double approach_distance) const;

 private:
  const config::FleetConfig& config_;
  std::map<std::string, RobotEntry> entries_;
};

}  // namespace fleet::orders
