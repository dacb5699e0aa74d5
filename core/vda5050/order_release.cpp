#include "vda5050/order_release.hpp"

#include <algorithm>

namespace fleet::vda5050 {

namespace {
/// A grant ends at a graph point; its metres and the node's may differ by rounding.
constexpr double kNodeTolerance = 1e-3;
}  // namespace

ReleasedOrder::ReleasedOrder(std::string order_id, std::string map_id, std::string version,
                             std::vector<OrderNode> nodes, std::vector<double> node_s, std::uint32_t first_sequence)
    : order_id_(std::move(order_id)),
      map_id_(std::move(map_id)),
      version_(std::move(version)),
      nodes_(std::move(nodes)),
      node_s_(std::move(node_s)),
      first_sequence_(first_sequence) {}

std::optional<OrderMessage> ReleasedOrder::release(double granted_s) {
  if (nodes_.empty()) return std::nullopt;
  std::size_t through = 0;
  while (through + 1 < nodes_.size() && node_s_[through + 1] <= granted_s + kNodeTolerance) ++through;
  if (sent_ && through <= released_through_) return std::nullopt;
  OrderMessage message;
  message.order_id = order_id_;
  message.map_id = map_id_;
  message.version = version_;
  message.first_sequence = first_sequence_;
  message.nodes = &nodes_;
  if (sent_) {
    ++update_id_;
    message.first = released_through_;  // stitched at the previous base's last node
  }
  message.update_id = update_id_;
  message.released_through = through;
  released_through_ = through;
  sent_ = true;
  return message;
}

bool ReleasedOrder::finished_by(const VehicleState& state) const {
  return sent_ && is_run_by(state) && state.node_sequence_ids.empty() &&
         state.last_node_sequence_id == first_sequence_ + 2 * (nodes_.size() - 1);
}

std::optional<ActionStatus> ReleasedOrder::goal_action(const VehicleState& state) const {
  if (nodes_.empty() || nodes_.back().actions.empty() || !is_run_by(state)) return std::nullopt;
  const std::string& id = nodes_.back().actions.front().id;
  for (const ActionStatus& a : state.actions) {
    if (a.id == id) return a;
  }
  return std::nullopt;
}

}  // namespace fleet::vda5050
