#pragma once

#include <string>

namespace fleet::dds {

/// Points CYCLONEDDS_URI at the shipped config/cyclonedds.xml (loopback only; multicast for
/// discovery, unicast for data)
/// unless the user set it. Every binary calls this before creating a participant. Returns the
/// configuration in effect.
std::string use_fleet_dds_config();

}  // namespace fleet::dds
