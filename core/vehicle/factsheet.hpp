#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "vehicle/profile.hpp"

namespace fleet::vehicle {

/// A fleet as a VDA 5050 factsheet (typeSpecification, physicalParameters,
/// protocolFeatures.agvActions, agvGeometry.envelopes2d, loadSpecification), with Fleet's own
/// `fleet`, `robotType` and `robots` beside them. `fleetctl fleets` and GET /api/fleets print it.
nlohmann::json factsheet(const std::string& fleet_id, const std::string& robot_type, const VehicleProfile& profile,
                         const std::vector<std::string>& robot_ids);

}  // namespace fleet::vehicle
