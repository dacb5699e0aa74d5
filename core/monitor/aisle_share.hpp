#pragma once
// Two pickers working one rack aisle at the same time, one along each face [Picker thesis,
// section 4.3.3.1]: how often and how long it happens in a run.

#include <map>
#include <string>
#include <vector>

#include "geometry/polygon.hpp"

namespace fleet::monitor {

/// The free space between two racks facing each other across it.
struct Aisle {
  std::string name;  ///< "R1|R2": the two racks
  geometry::Bounds box;
};

/// The aisles between `racks` (id, outline): each pair whose bounding boxes face each other along
/// at least `min_length` metres across a gap of at most `max_width` metres with no other rack in
/// it. Racks smaller than `min_length` on both sides (uprights) are passed over.
std::vector<Aisle> rack_aisles(const std::vector<std::pair<std::string, geometry::Polygon>>& racks,
                               double max_width = 4.0, double min_length = 2.0);

/// Watches where some robots (the pickers) are and counts the time two or more of them stand in
/// one aisle together. Poses come one robot at a time, each stamped with sim time; the time
/// between two stamps counts as shared when the aisle was shared at the first.
class AisleShareWatch {
 public:
  AisleShareWatch(std::vector<Aisle> aisles, std::vector<std::string> robots);

  void note(const std::string& robot_id, geometry::Vec2 position, double sim_time);

  double shared_seconds() const { return shared_s_; }
  int times() const { return times_; }  ///< separate spells of sharing
  double longest_seconds() const { return longest_s_; }
  const std::string& longest_aisle() const { return longest_aisle_; }
  /// Who shared it in the longest spell, sorted.
  const std::vector<std::string>& longest_robots() const { return longest_robots_; }

 private:
  /// The aisle two or more watched robots stand in now, and who; empty name when none.
  std::pair<std::string, std::vector<std::string>> shared_now() const;

  std::vector<Aisle> aisles_;
  std::map<std::string, geometry::Vec2> where_;  ///< watched robots' last positions
  double last_time_ = -1.0;
  std::string sharing_;  ///< the aisle shared since the last stamp, empty when none
  std::vector<std::string> sharing_robots_;
  double spell_s_ = 0.0;
  double shared_s_ = 0.0;
  int times_ = 0;
  double longest_s_ = 0.0;
  std::string longest_aisle_;
  std::vector<std::string> longest_robots_;
};

}  // namespace fleet::monitor
