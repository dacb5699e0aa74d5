// The forklift as data: what the server, traffic and config read of the type (its half of the
// type table, core/robot/robot_types.def; compiled into fleet_vehicle).
#include "vehicle/vehicle_types.hpp"

namespace fleet::vehicle {

RobotType forklift_type() {
  RobotType t;
  t.name = "forklift";
  t.description = "mecanum forklift with UWB, gyro and a marker camera on the forks [Forklift thesis]";
  // pick and drop a pallet; finePositioning is the marker-camera search that centres the forks.
  t.possible_actions = {"pick", "drop", "finePositioning"};
  VehicleProfile& p = t.defaults;
  p.footprint = rectangle(0.25, 0.16);  // about 25 x 16 cm [Forklift thesis, section 3]
  p.kinematics = Kinematics::kOmni;
  p.max_speed = 0.3;
  p.max_acceleration = 0.5;
  p.max_yaw_rate = 1.5;
  p.load = {"pallet", 1.0, 0.0};
  p.actions = t.possible_actions;
  return t;
}

}  // namespace fleet::vehicle
