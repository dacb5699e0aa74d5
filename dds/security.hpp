#pragma once

#include <dds/dds.h>

#include <cstdint>
#include <string>

namespace fleet::dds {

/// Every participant this process creates from now on joins the domain with DDS Security,
/// presenting the credentials of `identity` from the security folder `folder` (made by
/// `fleetctl security init`). The files are checked here first: security::SecurityError names
/// the one that is missing, unreadable, expired or not from the folder's authorities. An empty
/// `folder`: participants created from now on join without security.
void use_security(const std::string& folder, const std::string& identity);

/// The identity the process presents; empty when it joins without security.
const std::string& security_identity();
/// The security folder in use; empty without security.
const std::string& security_folder();

/// Creates a participant on `domain`, with the credentials of use_security when it was called.
/// A refusal throws DdsError with Cyclone's own reason.
dds_entity_t create_participant(std::uint32_t domain);

/// A hint for an entity the access control refused (DDS_RETCODE_NOT_ALLOWED_BY_SECURITY): the
/// permissions file that does not grant it.
std::string refusal_hint(dds_return_t rc);

}  // namespace fleet::dds
