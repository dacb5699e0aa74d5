#include "vehicle/factsheet.hpp"

namespace fleet::vehicle {

namespace {

std::string vda_kinematic(Kinematics k) {
  switch (k) {
    case Kinematics::kOmni:
      return "OMNI";
    case Kinematics::kDifferential:
      return "DIFF";
    case Kinematics::kTricycle:
      return "THREEWHEEL";
  }
  return "OMNI";
}

}  // namespace

nlohmann::json factsheet(const std::string& fleet_id, const std::string& robot_type, const VehicleProfile& profile,
                         const std::vector<std::string>& robot_ids) {
  using nlohmann::json;
  const geometry::Footprint extent = profile.extent();
  json type_specification{{"seriesName", fleet_id},
                          {"seriesDescription", robot_type},
                          {"agvKinematic", vda_kinematic(profile.kinematics)},
                          {"agvClass", profile.load.load_type == "pallet" ? "FORKLIFT" : "CARRIER"},
                          {"maxLoadMass", profile.load.max_mass},
                          {"localizationTypes", json::array({"NATURAL"})},
                          {"navigationTypes", json::array({"VIRTUAL_LINE_GUIDED"})}};
  json physical{{"speedMin", 0.0},
                {"speedMax", profile.max_speed},
                {"accelerationMax", profile.max_acceleration},
                {"decelerationMax", profile.max_acceleration},
                {"angularSpeedMax", profile.max_yaw_rate},
                {"length", extent.length},
                {"width", extent.width}};
  if (profile.kinematics == Kinematics::kTricycle) {
    physical["wheelbase"] = profile.wheelbase;
    physical["maxSteeringAngle"] = profile.max_steering_angle;
  }
  json actions = json::array();
  for (const std::string& a : profile.actions) actions.push_back({{"actionType", a}, {"actionScopes", {"NODE"}}});
  json points = json::array();
  for (const auto& p : profile.footprint) points.push_back({{"x", p.x}, {"y", p.y}});
  json load_sets = json::array();
  if (profile.load.load_type != "none") {
    load_sets.push_back({{"setName", profile.load.load_type},
                         {"loadType", profile.load.load_type},
                         {"maxWeight", profile.load.max_mass},
                         {"maxLoadhandlingHeight", profile.load.lift_height}});
  }
  return json{{"fleet", fleet_id},
              {"robotType", robot_type},
              {"robots", robot_ids},
              {"typeSpecification", type_specification},
              {"physicalParameters", physical},
              {"protocolFeatures", {{"agvActions", actions}}},
              {"agvGeometry", {{"envelopes2d", json::array({{{"set", "footprint"}, {"polyPoints", points}}})}}},
              {"loadSpecification", {{"loadSets", load_sets}}}};
}

}  // namespace fleet::vehicle
