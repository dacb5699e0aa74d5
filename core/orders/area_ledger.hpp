#pragma once
// What stands where: every load on the site (a pallet, a box, a cart) and the places that hold
// one. The server keeps its load truth here and stores and publishes each change the ledger
// computes; orders ask it which places hold a load.

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "geometry/pose.hpp"

namespace fleet::orders {

/// A place a load can stand on (a loading area), where a load put back there stands.
struct Place {
  std::string id;
  geometry::Pose2 pose;
};

/// One load and where it is.
struct Load {
  int id = 0;
  std::string kind;  ///< "pallet", "box", "cart", ...
  geometry::Pose2 pose;
  std::string place;       ///< the place it stands on; empty when carried or astray
  std::string carried_by;  ///< robot id; empty when standing

  bool standing_on(const std::string& place_id) const { return place == place_id && carried_by.empty(); }
};

/// Loads by place. A place may be known to hold a load no record names (a robot put one down
/// without naming it), so holding is kept per place beside the records.
class AreaLedger {
 public:
  /// The site's places in their order (the order matters where a load goes back to).
  explicit AreaLedger(std::vector<Place> places = {});

  /// Records a load's new truth: the place it left no longer holds a load, the place it stands
  /// on does.
  void record(Load load);

  const Load* find(int load_id) const;
  /// The recorded load standing on `place_id`, if any.
  const Load* standing_on(const std::string& place_id) const;
  const Load* carried_by(const std::string& robot_id) const;
  /// Whether `place_id` holds a load (false for a place the site does not have).
  bool holds_load(const std::string& place_id) const;

  /// A robot put a load down on `place_id` without naming it: the place holds one.
  void record_unnamed_drop(const std::string& place_id);
  /// A robot found `place_id` empty. A search that finds no load where one is recorded is a miss
  /// of the robot's camera or estimate, not news that the place is free: taking it for free would
  /// let a later order put a second load on the first. So the recorded load is returned and the
  /// place stays occupied; only a place without a recorded load is marked free (nullptr).
  const Load* found_empty(const std::string& place_id);

  /// The truth once `robot_id` lifted a load at `pick_place`: the load it names, or else the one
  /// recorded there. Nothing when no such load is known or the robot carries it already.
  std::optional<Load> lifted(const std::string& robot_id, int reported_load_id, const std::string& pick_place) const;
  /// The truth once load `load_id` was put down at `pose` on `place_id`; nothing for an unknown
  /// load.
  std::optional<Load> put_down(int load_id, const geometry::Pose2& pose, const std::string& place_id) const;
  /// Where the load `robot_id` carries goes back when the robot restarted empty: onto
  /// `preferred_place` when it is free, else onto the first free place, standing exactly on it.
  /// Nothing when the robot carries none, or no place is free.
  std::optional<Load> returned_from(const std::string& robot_id, const std::string& preferred_place) const;

  /// Place id -> holds a load, for every place.
  const std::map<std::string, bool>& occupancy() const { return holds_; }
  const std::map<int, Load>& loads() const { return loads_; }
  const std::vector<Place>& places() const { return places_; }

 private:
  std::vector<Place> places_;
  std::map<std::string, bool> holds_;
  std::map<int, Load> loads_;
};

}  // namespace fleet::orders
