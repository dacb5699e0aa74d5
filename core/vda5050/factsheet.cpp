#include "vda5050/factsheet.hpp"

#include <algorithm>

namespace fleet::vda5050 {

using nlohmann::json;

json factsheet_json(const VehicleAddress& vehicle, const vehicle::VehicleProfile& profile, double speed_max,
                    std::uint32_t header_id, double unix_time) {
  json message = header(vehicle, header_id, unix_time);
  const geometry::Footprint extent = profile.extent();
  const bool carries = profile.can("pick") && profile.can("drop");
  const char* kinematic = profile.kinematics == vehicle::Kinematics::kOmni           ? "OMNI"
                          : profile.kinematics == vehicle::Kinematics::kDifferential ? "DIFF"
                                                                                     : "THREEWHEEL";
  message["typeSpecification"] = {{"seriesName", "Fleet"},
                                  {"agvKinematic", kinematic},
                                  {"agvClass", carries ? "FORKLIFT" : "CARRIER"},
                                  {"maxLoadMass", profile.load.max_mass},
                                  {"localizationTypes", json::array({"NATURAL"})},
                                  {"navigationTypes", json::array({"VIRTUAL_LINE_GUIDED"})}};
  message["physicalParameters"] = {{"speedMin", 0.0},
                                   {"speedMax", speed_max},
                                   {"accelerationMax", profile.max_acceleration},
                                   {"decelerationMax", profile.max_acceleration},
                                   {"heightMax", std::max(profile.load.lift_height, 0.0)},
                                   {"width", extent.width},
                                   {"length", extent.length}};
  message["protocolLimits"] = {{"maxStringLens", json::object()},
                               {"maxArrayLens", json::object()},
                               {"timing", {{"minOrderInterval", 0.0}, {"minStateInterval", 0.0}}}};
  json actions = json::array();
  if (carries) {
    for (const char* type : {"pick", "drop"}) {
      actions.push_back({{"actionType", type}, {"actionScopes", json::array({"NODE"})}});
    }
  }
  for (const char* type : kVehicleInstantActions) {
    actions.push_back({{"actionType", type}, {"actionScopes", json::array({"INSTANT"})}});
  }
  message["protocolFeatures"] = {{"optionalParameters", json::array()}, {"agvActions", actions}};
  json polygon = json::array();
  for (const geometry::Vec2& p : profile.footprint) polygon.push_back({{"x", p.x}, {"y", p.y}});
  message["agvGeometry"] = {{"envelopes2d", json::array({{{"set", "base"}, {"polygonPoints", polygon}}})}};
  message["loadSpecification"] = json::object();
  if (carries) {
    message["loadSpecification"]["loadPositions"] = json::array({"forks"});
    message["loadSpecification"]["loadSets"] =
        json::array({{{"setName", "default"}, {"loadType", profile.load.load_type}}});
  }
  return message;
}

}  // namespace fleet::vda5050
