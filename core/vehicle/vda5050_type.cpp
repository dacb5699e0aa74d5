// Vehicles of other makers, driven over VDA 5050 by fleet-vda5050 (docs/vda5050.md): the type as
// data. No agent builds it; the vehicle runs its own software.
#include "vehicle/vehicle_types.hpp"

namespace fleet::vehicle {

RobotType vda5050_type() {
  RobotType t;
  t.name = "vda5050";
  t.description = "a vehicle of another maker that Fleet drives as VDA 5050 master control over MQTT";
  t.possible_actions = {"pick", "drop"};
  t.agent_driven = false;
  VehicleProfile& p = t.defaults;
  // A small AGV of a pallet's size; the fleet's profile gives the vehicle's own.
  p.footprint = rectangle(1.0, 0.7);
  p.kinematics = Kinematics::kOmni;
  p.max_speed = 1.0;
  p.max_acceleration = 0.5;
  p.max_yaw_rate = 1.0;
  p.load = {"pallet", 1000.0, 0.0};
  p.actions = t.possible_actions;
  return t;
}

}  // namespace fleet::vehicle
