#include "vehicle/vehicle_types.hpp"

#include <algorithm>

namespace fleet::vehicle {

// Each robot type's data lives in its folder (core/robot/<type>/<type>_type.cpp).
#define FLEET_ROBOT_TYPE(name) RobotType name##_type();
#include "robot/robot_types.def"
#undef FLEET_ROBOT_TYPE
RobotType vda5050_type();

const std::vector<RobotType>& robot_types() {
  static const std::vector<RobotType> types{
#define FLEET_ROBOT_TYPE(name) name##_type(),
#include "robot/robot_types.def"
#undef FLEET_ROBOT_TYPE
      vda5050_type(),
  };
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
