#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>

#include "vda5050/messages.hpp"
#include "vehicle/profile.hpp"

namespace fleet::vda5050 {

/// The factsheet [VDA 5050 2.1.0, section 6.14] of one of Fleet's robots from its vehicle profile:
/// kinematics, size, top speed (`speed_max`, what the robot drives at), load handling, and the
/// actions it performs (pick and drop at nodes when it carries loads; the instant actions it
/// answers). The same message for a 2.0.0 master, which has no schema for it.
nlohmann::json factsheet_json(const VehicleAddress& vehicle, const vehicle::VehicleProfile& profile, double speed_max,
                              std::uint32_t header_id, double unix_time);

/// The instant actions a Fleet robot as a VDA 5050 vehicle carries out.
inline constexpr const char* kVehicleInstantActions[] = {"cancelOrder", "startPause", "stopPause", "stateRequest",
                                                         "factsheetRequest"};

}  // namespace fleet::vda5050
