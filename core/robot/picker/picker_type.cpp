// The picker as data: what the server, traffic and config read of the type (its half of the
// type table, core/robot/robot_types.def; compiled into fleet_vehicle).
#include "vehicle/vehicle_types.hpp"

namespace fleet::vehicle {

RobotType picker_type() {
  RobotType t;
  t.name = "picker";
  t.description =
      "mecanum base with a UR5 arm and a vacuum gripper for boxes in rack aisles, localised by AR markers "
      "[Picker thesis]";
  // The base drives the forklift software without forks; its arm picks boxes at rack places and
  // puts them down at packing places [Picker thesis, section 4.4].
  t.possible_actions = {"pickItem", "dropItem"};
  VehicleProfile& p = t.defaults;
  p.footprint = rectangle(0.65, 0.50);  // Robotnik Summit-XLS [Picker thesis, section 3.1.1]
  p.kinematics = Kinematics::kOmni;
  p.max_speed = 1.0;  // the fastest the thesis tested markers and the controller at
                      // [Picker thesis, sections 4.2.9, 4.3.2]
  p.max_acceleration = 0.5;
  p.max_yaw_rate = 1.0;
  // Boxes of at most 5 kg [Picker thesis, sections 3.2-3.3]; the UR5's base stands 0.80 m above the floor and reaches
  // about 0.85 m, so boxes up to about 1.5 m.
  p.load = {"box", 5.0, 1.5};
  p.actions = t.possible_actions;
  return t;
}

}  // namespace fleet::vehicle
