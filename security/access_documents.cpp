#include "security/access_documents.hpp"

#include <sstream>

namespace fleet::security {

namespace {

/// The domain ids the documents cover: all that Cyclone DDS reads in them (0 to 230).
constexpr int kFirstDomain = 0;
constexpr int kLastDomain = 230;

const std::vector<std::string> kServerPublishes{
    "fleet/ServerInfo",   "fleet/RequestReply", "fleet/Order",           "fleet/OrderInfo",    "fleet/MapAssignment",
    "fleet/RobotControl", "fleet/PalletTruth",  "fleet/StaticObstacles", "fleet/FleetView",    "fleet/NeighbourView",
    "fleet/TrafficGrant", "fleet/ServerLoad",   "fleet/SiteState",       "fleet/OrderHandover"};
const std::vector<std::string> kRobotPublishes{"fleet/RobotState",     "fleet/RobotPath",       "fleet/OrderState",
                                               "fleet/TrafficRequest", "fleet/TrafficProgress", "fleet/SimTruth"};
const std::vector<std::string> kOperatorPublishes{"fleet/OrderRequest", "fleet/Command"};

std::string domains() {
  std::ostringstream out;
  out << "<domains><id_range><min>" << kFirstDomain << "</min><max>" << kLastDomain << "</max></id_range></domains>";
  return out.str();
}

}  // namespace

const std::vector<std::string>& every_topic() {
  static const std::vector<std::string> topics = [] {
    std::vector<std::string> all = kServerPublishes;
    all.insert(all.end(), kRobotPublishes.begin(), kRobotPublishes.end());
    all.insert(all.end(), kOperatorPublishes.begin(), kOperatorPublishes.end());
    return all;
  }();
  return topics;
}

std::vector<TopicGrant> grants_of(Role role, const std::vector<std::string>& robots) {
  std::vector<std::string> own;
  for (const std::string& id : robots) own.push_back("robot." + id);
  switch (role) {
    case Role::kServer:
      return {{true, kServerPublishes, {"*"}},
              {false,
               {"fleet/OrderRequest", "fleet/Command", "fleet/RobotState", "fleet/RobotPath", "fleet/OrderState",
                "fleet/TrafficRequest", "fleet/TrafficProgress", "fleet/SimTruth",
                // A standby server mirrors the active one; every server hears the others.
                "fleet/OrderInfo", "fleet/SiteState", "fleet/ServerLoad", "fleet/OrderHandover"},
               {"*"}}};
    case Role::kBridge:
    case Role::kRobot: {
      // A robot's agent, or a bridge for each of its vehicles: their messages in their own
      // partitions, what the server sends them there and to everyone.
      std::vector<TopicGrant> grants{
          {true, kRobotPublishes, own},
          {false, {"fleet/TrafficGrant", "fleet/NeighbourView"}, own},
          {false,
           {"fleet/Order", "fleet/MapAssignment", "fleet/StaticObstacles", "fleet/RobotControl", "fleet/PalletTruth"},
           {""}}};
      // An agent's simulated sensors see the other robots' true bodies; a bridge's vehicles report
      // theirs, sensing none.
      if (role == Role::kRobot) grants.push_back({false, {"fleet/SimTruth"}, {"", "robot.*"}});
      return grants;
    }
    case Role::kOperator:
      return {{true, kOperatorPublishes, {""}}, {false, every_topic(), {"*"}}};
  }
  return {};
}

std::string subject_name(const std::string& identity) {
  return "CN=" + identity + ",O=Fleet";
}

std::string governance_document() {
  std::ostringstream out;
  out << R"(<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"
     xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_governance.xsd">
  <domain_access_rules>
    <domain_rule>
      )"
      << domains() << R"(
      <allow_unauthenticated_participants>false</allow_unauthenticated_participants>
      <enable_join_access_control>true</enable_join_access_control>
      <discovery_protection_kind>ENCRYPT</discovery_protection_kind>
      <liveliness_protection_kind>ENCRYPT</liveliness_protection_kind>
      <rtps_protection_kind>NONE</rtps_protection_kind>
      <topic_access_rules>
        <topic_rule>
          <topic_expression>*</topic_expression>
          <enable_discovery_protection>true</enable_discovery_protection>
          <enable_liveliness_protection>true</enable_liveliness_protection>
          <enable_read_access_control>true</enable_read_access_control>
          <enable_write_access_control>true</enable_write_access_control>
          <metadata_protection_kind>ENCRYPT</metadata_protection_kind>
          <data_protection_kind>ENCRYPT</data_protection_kind>
        </topic_rule>
      </topic_access_rules>
    </domain_rule>
  </domain_access_rules>
</dds>
)";
  return out.str();
}

std::string permissions_document(const std::string& identity, const std::vector<TopicGrant>& grants,
                                 const std::string& not_before, const std::string& not_after) {
  std::ostringstream out;
  out << R"(<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"
     xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_permissions.xsd">
  <permissions>
    <grant name=")"
      << identity << R"(">
      <subject_name>)"
      << subject_name(identity) << R"(</subject_name>
      <validity><not_before>)"
      << not_before << "</not_before><not_after>" << not_after << R"(</not_after></validity>
      <allow_rule>
        )"
      << domains() << "\n";
  for (const TopicGrant& grant : grants) {
    const char* kind = grant.publish ? "publish" : "subscribe";
    out << "        <" << kind << ">\n          <topics>";
    for (const std::string& topic : grant.topics) out << "<topic>" << topic << "</topic>";
    out << "</topics>\n          <partitions>";
    for (const std::string& partition : grant.partitions) out << "<partition>" << partition << "</partition>";
    out << "</partitions>\n        </" << kind << ">\n";
  }
  out << R"(      </allow_rule>
      <default>DENY</default>
    </grant>
  </permissions>
</dds>
)";
  return out.str();
}

}  // namespace fleet::security
