#pragma once
// The vehicle's side of VDA 5050 orders: what a vehicle makes of the orders a master control
// sends it [VDA 5050, sections 6.6 and 6.10], free of MQTT and of the robot it drives.

#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "vda5050/messages.hpp"

namespace fleet::vda5050 {

struct ReceivedAction {
  std::string id;
  std::string type;
  std::string blocking;  ///< NONE, SOFT or HARD
  std::vector<std::pair<std::string, std::string>> parameters;
};

struct ReceivedNode {
  std::string id;
  std::uint32_t sequence = 0;
  bool released = true;
  bool has_position = false;
  double x = 0.0, y = 0.0;
  std::optional<double> theta;
  std::string map_id;
  double allowed_deviation = 0.0;  ///< allowedDeviationXy (2.0.0) or allowedDeviationXY (2.1.0); 0: none given
  std::vector<ReceivedAction> actions;
};

struct ReceivedEdge {
  std::string id;
  std::uint32_t sequence = 0;
  bool released = true;
  std::string start_node;
  std::string end_node;
  std::vector<ReceivedAction> actions;
};

struct ReceivedOrder {
  std::uint32_t header_id = 0;
  std::string order_id;
  std::uint32_t update_id = 0;
  std::vector<ReceivedNode> nodes;
  std::vector<ReceivedEdge> edges;
};

/// Reads an order and checks the rules of its graph [VDA 5050, section 6.6.2]: at least one node,
/// one edge fewer than nodes, each edge joining the nodes beside it, sequence ids counting up by
/// one from node to edge to node starting even, the first node released, no released element
/// after an unreleased one, action ids unique. MessageError naming the key otherwise.
ReceivedOrder read_order(const nlohmann::json& message);

/// The actions of an instantActions message, under `actions` (the schemas) or `instantActions`
/// (what some 2.0 masters send), both when it has both, each id once. MessageError naming the key.
std::vector<ReceivedAction> read_instant_actions(const nlohmann::json& message);

/// An error as the vehicle reports it in its state's `errors`, with the references the
/// specification asks for (topic, headerId, orderId, orderUpdateId and what else names the cause).
VehicleError order_error(const std::string& type, const std::string& description, const nlohmann::json& message,
                         std::vector<std::pair<std::string, std::string>> more = {});
nlohmann::json error_json(const VehicleError& error);

enum class OrderIntake {
  kNew,     ///< a new order, the vehicle at its first node
  kUpdate,  ///< the same order, extended from the base end it stands at
  kStitch,  ///< extends the base still being driven (same or new orderId)
  kRepeat,  ///< the update the vehicle has already: discarded, state sent again
};

/// What the vehicle decides about an order: taken (how), or an error to report.
struct OrderVerdict {
  std::optional<OrderIntake> intake;
  std::optional<VehicleError> error;
};

/// A vehicle's current order: the nodes and edges it has still to pass (base and horizon), the
/// last node it passed, and its actions' states; what its `state` message reports of the order.
class VehicleOrder {
 public:
  /// Decides about `order` (read by read_order from `message`) without taking it.
  /// `at_first_node`: the vehicle stands within the deviation range of the order's first node
  /// (only asked of a new order while none is active). Rejections follow section 6.6.4 of the
  /// specification: a lower orderUpdateId, or an update or stitch that does not begin at the
  /// current base end, is an orderUpdateError; a first node the vehicle is not at, a noRouteError.
  OrderVerdict check(const ReceivedOrder& order, const nlohmann::json& message, bool at_first_node) const;
  /// The nodes ahead of the vehicle once it takes `order` as `intake` says (check()).
  std::vector<ReceivedNode> nodes_taking(const ReceivedOrder& order, OrderIntake intake) const;
  /// Takes `order` as check() decided (kRepeat changes nothing).
  void take(const ReceivedOrder& order, OrderIntake intake);

  /// Nodes of the base still to pass, or actions not ended.
  bool active() const;
  const std::string& order_id() const { return order_id_; }
  std::uint32_t update_id() const { return update_id_; }
  const std::string& last_node_id() const { return last_node_.id; }
  std::uint32_t last_node_sequence() const { return last_node_.sequence; }
  /// Nodes after the last one passed: released first (the base), then the horizon.
  const std::vector<ReceivedNode>& nodes_ahead() const { return nodes_; }
  /// The last released node, the last one passed when the vehicle stands at it: where it must
  /// stop and wait for an update.
  const ReceivedNode& base_end() const;

  /// The vehicle passed the node of `sequence` (and every node and edge before it).
  void passed(std::uint32_t sequence);
  /// Sets an action's status (RUNNING, FINISHED, FAILED, ...); unknown ids are ignored.
  void set_action_status(const std::string& action_id, const std::string& status, const std::string& result = "");
  /// The type of an action of the current order, empty when it has none of that id.
  std::string action_type(const std::string& action_id) const;
  /// cancelOrder [VDA 5050, section 6.7]: nodes and edges dropped, actions not ended FAILED.
  /// False when there is no order to cancel.
  bool cancel();
  /// An instant action's state, kept beside the order's.
  void add_instant_action(const ActionStatus& action);

  nlohmann::json node_states() const;
  nlohmann::json edge_states() const;
  nlohmann::json action_states_json() const;

 private:
  std::string order_id_;
  std::uint32_t update_id_ = 0;
  ReceivedNode last_node_;
  std::vector<ReceivedNode> nodes_;
  std::vector<ReceivedEdge> edges_;
  std::vector<ActionStatus> actions_;          ///< of the order's nodes and edges
  std::vector<ActionStatus> instant_actions_;  ///< the latest few
};

}  // namespace fleet::vda5050
