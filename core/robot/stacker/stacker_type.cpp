// The stacker as data: what the server, traffic and config read of the type (its half of the
// type table, core/robot/robot_types.def; compiled into fleet_vehicle).
#include "vehicle/vehicle_types.hpp"

namespace fleet::vehicle {

RobotType stacker_type() {
  RobotType t;
  t.name = "stacker";
  t.description =
      "tricycle pedestrian stacker that docks to EPAL pallets in reverse with depth cameras [Stacker thesis]";
  // pick and drop a pallet; finePositioning is the camera-guided final approach of the docking.
  t.possible_actions = {"pick", "drop", "finePositioning"};
  VehicleProfile& p = t.defaults;
  // BT Staxio SPE200DN as modified [Stacker thesis, section 4.2.3]: 1.700 m x 0.748 m.
  p.footprint = rectangle(1.7, 0.748);
  p.kinematics = Kinematics::kTricycle;
  p.wheelbase = 1.30;
  p.max_steering_angle = 1.5707963267948966;
  // The rear axle sits 0.10 m ahead of the fork tips (sim::TricycleGeometry): 0.75 m behind the
  // footprint's centre.
  p.rear_axle_x = -0.75;
  p.max_speed = 1.2;
  p.max_acceleration = 0.5;
  p.max_yaw_rate = 0.6;
  p.load = {"pallet", 2000.0, 1.6};
  p.actions = t.possible_actions;
  // Target 1 of the docking lies 1.8 m out from the pallet's centre and the pivot swings the
  // chassis front 1.6 m from the rear axle: the thesis's 2.98 m corridor [Stacker thesis, section 4.1.2] is room
  // enough, a single lane is not.
  t.handling_road_width = 2.9;
  return t;
}

}  // namespace fleet::vehicle
