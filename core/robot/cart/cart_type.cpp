// The cart as data: what the server, traffic and config read of the type (its half of the type
// table, core/robot/robot_types.def; compiled into fleet_vehicle).
#include "vehicle/vehicle_types.hpp"

namespace fleet::vehicle {

RobotType cart_type() {
  RobotType t;
  t.name = "cart";
  t.description = "differential-drive cart that carries what is put on its deck from place to place (move orders)";
  // No handling of its own: people or other robots load and unload it; it takes move orders.
  t.possible_actions = {};
  VehicleProfile& p = t.defaults;
  p.footprint = rectangle(0.60, 0.40);
  p.kinematics = Kinematics::kDifferential;
  p.max_speed = 0.8;
  p.max_acceleration = 0.5;
  p.max_yaw_rate = 1.2;
  p.load = {"deck", 50.0, 0.0};
  p.actions = t.possible_actions;
  return t;
}

}  // namespace fleet::vehicle
