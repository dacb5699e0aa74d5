#pragma once

#include <string>
#include <vector>

namespace fleet::security {

/// What a process may do on Fleet's DDS domain: each role publishes and subscribes its own topics
/// and no others [DDS Security, section 9.4.1.3].
enum class Role {
  kServer,    ///< fleet-server: orders, grants, maps, views out; robot reports and requests in
  kRobot,     ///< one robot's agent: its reports, in its own partition alone
  kOperator,  ///< fleetctl: order requests and commands out; every topic in
  kBridge,    ///< fleet-vda5050: its vehicles' reports, each in its robot's partition alone
};

/// Topics a role may publish or subscribe in the given partitions (patterns as DDS partitions
/// take them, `*` for any).
struct TopicGrant {
  bool publish = true;
  std::vector<std::string> topics;
  std::vector<std::string> partitions;
};

/// The grants of `role`; `robots` names the robot of a kRobot, the vehicles of a kBridge.
std::vector<TopicGrant> grants_of(Role role, const std::vector<std::string>& robots = {});

/// The subject name of an identity's certificate: `CN=<identity>,O=Fleet`.
std::string subject_name(const std::string& identity);

/// The governance document: authentication required, unauthenticated participants refused,
/// discovery, liveliness and data encrypted on every topic [DDS Security, section 9.4.1.2].
std::string governance_document();

/// The permissions document of one identity, valid between two instants written as
/// `YYYY-MM-DDTHH:MM:SS` (UTC) [DDS Security, section 9.4.1.3]; everything not granted is denied.
std::string permissions_document(const std::string& identity, const std::vector<TopicGrant>& grants,
                                 const std::string& not_before, const std::string& not_after);

/// Every topic of Fleet's wire (fleet/...), for the operator's reading and the tests.
const std::vector<std::string>& every_topic();

}  // namespace fleet::security
