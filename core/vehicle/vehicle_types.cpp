#include "vehicle/vehicle_types.hpp"

#include <algorithm>

namespace fleet::vehicle {

namespace {

RobotType forklift() {
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

RobotType stacker() {
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

RobotType picker() {
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

}  // namespace

const std::vector<RobotType>& robot_types() {
  static const std::vector<RobotType> types{forklift(), stacker(), picker()};
  return types;
}

const RobotType* find_robot_type(std::string_view name) {
  for (const RobotType& t : robot_types()) {
    if (t.name == name) return &t;
  }
  return nullptr;
}

std::string robot_type_names() {
  std::string out;
  for (const RobotType& t : robot_types()) out += (out.empty() ? "" : ", ") + t.name;
  return out;
}

std::vector<std::string> known_actions() {
  std::vector<std::string> out;
  for (const RobotType& t : robot_types()) {
    for (const std::string& a : t.possible_actions) {
      if (std::find(out.begin(), out.end(), a) == out.end()) out.push_back(a);
    }
  }
  // VDA 5050 names the next robot types bring: orders may already name them (and are refused
  // as no fleet's action until a fleet offers them).
  for (const char* a : {"pickItem", "dropItem", "dock"}) {
    if (std::find(out.begin(), out.end(), a) == out.end()) out.emplace_back(a);
  }
  return out;
}

bool is_known_action(std::string_view action) {
  const auto all = known_actions();
  return std::find(all.begin(), all.end(), action) != all.end();
}

}  // namespace fleet::vehicle
