#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace fleet::vda5050 {

/// A message that breaks the VDA 5050 rules Fleet relies on: what names the key and why.
class MessageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Who a message is from or for, and the protocol version it speaks [VDA 5050, section 6.2].
struct VehicleAddress {
  std::string interface_name;
  std::string version;  ///< "2.0.0" or "2.1.0"
  std::string manufacturer;
  std::string serial_number;
};

/// `{interfaceName}/v{major}/{manufacturer}/{serialNumber}/{topic}` [VDA 5050, section 6.2].
std::string topic(const VehicleAddress& vehicle, const std::string& name);
/// The header every message starts with: headerId, timestamp (ISO 8601, UTC, milliseconds),
/// version, manufacturer, serialNumber.
nlohmann::json header(const VehicleAddress& vehicle, std::uint32_t header_id, double unix_time);
std::string iso_timestamp(double unix_time);

struct NodeAction {
  std::string type;  ///< pick, drop, ...
  std::string id;
  std::string blocking = "HARD";
  std::vector<std::pair<std::string, std::string>> parameters;
};

/// One node of an order's path: a point of the site's road graph (`p<id>`), a place beside the
/// roads (its id), or where the vehicle stood when the order began.
struct OrderNode {
  std::string id;
  double x = 0.0;
  double y = 0.0;
  std::optional<double> theta;  ///< the yaw to arrive with, at a place only
  std::vector<NodeAction> actions;
};

/// An order or order update [VDA 5050, section 6.6]: nodes `first`..end of `nodes`, node k with
/// sequence id first_sequence + 2k and the edge from k to k+1 with one more; nodes up to
/// `released_through` (and the edges between them) are base, the rest horizon.
struct OrderMessage {
  std::string order_id;
  std::uint32_t update_id = 0;
  std::string map_id;
  /// The protocol version: 2.0.0's schema spells allowedDeviationXy, 2.1.0's allowedDeviationXY.
  std::string version = "2.0.0";
  std::uint32_t first_sequence = 0;
  double allowed_deviation_xy = 0.1;
  const std::vector<OrderNode>* nodes = nullptr;
  std::size_t first = 0;
  std::size_t released_through = 0;
};
nlohmann::json order_json(const OrderMessage& order);

/// An instant action [VDA 5050, section 6.7]: cancelOrder, startPause, stopPause, stateRequest,
/// factsheetRequest, initPosition (with `parameters`). Written under `actions` (the 2.0 and 2.1 schemas) and
/// `instantActions` (what some 2.0 vehicles read); for 2.0.0 each action carries its type as `actionType` (the
/// text, 2.1 and vehicles) and `actionName` (what the 2.0.0 schema requires).
nlohmann::json instant_action_json(const std::string& type, const std::string& action_id, const std::string& version,
                                   const std::vector<std::pair<std::string, nlohmann::json>>& parameters = {});

struct ActionStatus {
  std::string id;
  std::string type;
  std::string status;  ///< WAITING, INITIALIZING, RUNNING, PAUSED, FINISHED, FAILED
  std::string result;
};

struct VehicleError {
  std::string type;
  std::string level;  ///< WARNING or FATAL
  std::string description;
  std::vector<std::pair<std::string, std::string>> references;  ///< referenceKey, referenceValue
};

/// What Fleet reads of a vehicle's `state` [VDA 5050, section 6.10].
struct VehicleState {
  std::string order_id;
  std::uint32_t update_id = 0;
  std::string last_node_id;
  std::uint32_t last_node_sequence_id = 0;
  std::vector<std::uint32_t> node_sequence_ids;  ///< nodeStates still to pass
  std::size_t released_nodes_left = 0;           ///< of them released (base); the rest is horizon
  bool driving = false;
  bool paused = false;
  bool has_position = false;
  /// It reports a position it says is not initialised (positionInitialized false): it does not
  /// know where it is (has_position is false then).
  bool position_uninitialized = false;
  double x = 0.0, y = 0.0, theta = 0.0;
  std::string map_id;
  double speed = 0.0;  ///< |velocity|, m/s, 0 when not reported
  std::vector<ActionStatus> actions;
  std::vector<VehicleError> errors;
  bool loaded = false;
};

/// What Fleet checks of a vehicle's `factsheet` [VDA 5050, section 6.14]: its size and top speed.
struct FactsheetFigures {
  std::optional<double> length;     ///< physicalParameters.length, metres
  std::optional<double> width;      ///< physicalParameters.width
  std::optional<double> speed_max;  ///< physicalParameters.speedMax, m/s
};
/// MessageError when it is not an object or a figure is not a positive number.
FactsheetFigures parse_factsheet(const nlohmann::json& message);
/// How the factsheet differs from the profile Fleet plans with (`length` x `width` footprint
/// extent, `speed_max`), one sentence each; "gives no physicalParameters" when it has none of them.
std::vector<std::string> factsheet_differences(const FactsheetFigures& sheet, double length, double width,
                                               double speed_max);

/// Reads the position of a `visualization` message [VDA 5050, section 6.12] into `state`; false
/// when it has none. MessageError as parse_state.
bool read_visualization(const nlohmann::json& message, VehicleState& state);

/// Reads a state message. MessageError naming the key when a required one is missing, of the
/// wrong type, or a position is not finite.
VehicleState parse_state(const nlohmann::json& message);
/// ONLINE, OFFLINE or CONNECTIONBROKEN of a `connection` message; MessageError otherwise.
std::string parse_connection(const nlohmann::json& message);

}  // namespace fleet::vda5050
