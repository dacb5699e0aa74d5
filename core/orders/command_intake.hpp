#pragma once
// Operator commands (fleetctl and the web view): whether one is taken, and what it asks for. The
// server hands over what it knows at the moment of the command and carries out the decision
// (the book, DDS, a map switch); the checks need no DDS, so they are tested on plain values.

#include <cstdint>
#include <string>
#include <vector>

#include "config/fleet_config.hpp"
#include "map/site.hpp"
#include "model/messages.hpp"
#include "orders/order_book.hpp"
#include "orders/robot_roster.hpp"

namespace fleet::orders {

/// What the command intake reads of the server's state; it changes none of it.
struct CommandView {
  const OrderBook& book;
  const map::Site& site;                 ///< the map served now
  const std::vector<std::string>& maps;  ///< the maps robots can be switched to
  const config::FleetConfig& config;     ///< the robots there are
  const RobotRoster& robots;             ///< as last heard
  bool traffic_on = false;               ///< traffic control needs every robot on one map
};

enum class CommandAction {
  kNone,            ///< refused, or nothing to do (a map switch onto the map served)
  kCancelOrder,     ///< cancel `order_id`
  kSwitchObstacle,  ///< switch obstacle `target` on (`on`) or off
  kMapOneRobot,     ///< tell robot `target` to use map `value` (traffic off only)
  kSwitchMap,       ///< switch every robot onto map `value`, a revision of the site
  kAutoOrders,      ///< automatic orders on or off
  kPauseRobot,      ///< pause robot `target` (`on`) or let it resume
};

struct CommandDecision {
  std::string error;  ///< why it is refused, naming the value at fault; empty when taken
  CommandAction action = CommandAction::kNone;
  std::int64_t order_id = 0;  ///< kCancelOrder
  bool on = false;            ///< kSwitchObstacle: on; kAutoOrders: on; kPauseRobot: pause
};

/// Checks `command` (verbs cancel-order, obstacle, map, auto-orders, pause, resume) against `view`.
/// An obstacle is never switched on over a robot's body (every way out would start inside it, and
/// a real robot cannot stand where a real obstacle is); one robot alone changes maps only with
/// traffic control off; a robot is paused only once it has reported.
CommandDecision decide_command(const model::Command& command, const CommandView& view);

}  // namespace fleet::orders
