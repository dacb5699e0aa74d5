#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "vda5050/messages.hpp"

namespace fleet::vda5050 {

/// One VDA 5050 order along a leg of a robot's path, released node by node as traffic control
/// grants the road: the granted part is the order's base, the rest its horizon [VDA 5050, section
/// 6.6.1]. Every further grant is an order update with the same order id, the next update id, and
/// the previous base's last node as its first [VDA 5050, section 6.6.2].
class ReleasedOrder {
 public:
  /// `node_s`: metres along the path to each node (the first 0). The first node takes sequence id
  /// `first_sequence`: a vehicle waiting at the end of a base takes a new order only when it
  /// starts at that node with its sequence id.
  ReleasedOrder(std::string order_id, std::string map_id, std::string version, std::vector<OrderNode> nodes,
                std::vector<double> node_s, std::uint32_t first_sequence);

  /// The message that releases every node at or before `granted_s` metres along the path, when
  /// that is a node further than the base's end (or the first message); nothing otherwise.
  std::optional<OrderMessage> release(double granted_s);

  const std::string& order_id() const { return order_id_; }
  const std::vector<OrderNode>& nodes() const { return nodes_; }
  bool sent() const { return sent_; }
  std::uint32_t update_id() const { return update_id_; }
  std::size_t released_through() const { return released_through_; }
  /// The sequence id of the base's last node.
  std::uint32_t base_end_sequence() const {
    return first_sequence_ + 2 * static_cast<std::uint32_t>(released_through_);
  }
  bool fully_released() const { return sent_ && released_through_ + 1 == nodes_.size(); }
  /// The vehicle reports this order with its last node passed and no node left to pass.
  bool finished_by(const VehicleState& state) const;
  /// The vehicle reports this order (any update of it).
  bool is_run_by(const VehicleState& state) const { return state.order_id == order_id_; }
  /// The status of the action on the order's last node, as the vehicle reports it.
  std::optional<ActionStatus> goal_action(const VehicleState& state) const;

 private:
  std::string order_id_;
  std::string map_id_;
  std::string version_;
  std::vector<OrderNode> nodes_;
  std::vector<double> node_s_;
  std::uint32_t first_sequence_ = 0;
  bool sent_ = false;
  std::uint32_t update_id_ = 0;
  std::size_t released_through_ = 0;
};

}  // namespace fleet::vda5050
