#include "robot/neighbour_memory.hpp"

namespace fleet::robot {

void NeighbourMemory::update(const std::vector<Neighbour>& listed, double now) {
  for (const auto& n : listed) known_[n.robot_id] = {n, now};
  std::erase_if(known_, [&](const auto& entry) { return now - entry.second.listed_at > forget_after_s_; });
}

void NeighbourMemory::update_within(const std::vector<Neighbour>& listed, double now, geometry::Vec2 centre,
                                    double radius, double edge) {
  update(listed, now);
  const double inside = radius - edge;
  std::erase_if(known_, [&](const auto& entry) {
    return entry.second.listed_at < now && geometry::distance(entry.second.neighbour.pose.position(), centre) < inside;
  });
}

std::vector<Neighbour> NeighbourMemory::current() const {
  std::vector<Neighbour> out;
  out.reserve(known_.size());
  for (const auto& [id, entry] : known_) out.push_back(entry.neighbour);
  return out;
}

}  // namespace fleet::robot
