#include "security/access_documents.hpp"

#include <gtest/gtest.h>

#include <algorithm>

namespace fleet::security {
namespace {

bool grants(const std::vector<TopicGrant>& all, bool publish, const std::string& topic, const std::string& partition) {
  return std::any_of(all.begin(), all.end(), [&](const TopicGrant& g) {
    return g.publish == publish && std::count(g.topics.begin(), g.topics.end(), topic) > 0 &&
           std::count(g.partitions.begin(), g.partitions.end(), partition) > 0;
  });
}

TEST(AccessDocuments, ARobotPublishesItsOwnMessagesInItsOwnPartitionAlone) {
  const auto robot = grants_of(Role::kRobot, {"fl-1"});
  for (const char* topic : {"fleet/RobotState", "fleet/RobotPath", "fleet/OrderState", "fleet/TrafficRequest",
                            "fleet/TrafficProgress", "fleet/SimTruth"}) {
    EXPECT_TRUE(grants(robot, true, topic, "robot.fl-1")) << topic;
    EXPECT_FALSE(grants(robot, true, topic, "")) << topic;
    EXPECT_FALSE(grants(robot, true, topic, "robot.*")) << topic;
  }
  for (const char* topic : {"fleet/OrderRequest", "fleet/Command", "fleet/Order", "fleet/TrafficGrant"}) {
    EXPECT_FALSE(grants(robot, true, topic, "robot.fl-1")) << topic;
    EXPECT_FALSE(grants(robot, true, topic, "")) << topic;
  }
  // It hears its grants and neighbours in its own partition, not another robot's.
  EXPECT_TRUE(grants(robot, false, "fleet/TrafficGrant", "robot.fl-1"));
  EXPECT_FALSE(grants(robot, false, "fleet/TrafficGrant", "robot.*"));
  EXPECT_TRUE(grants(robot, false, "fleet/Order", ""));
  EXPECT_FALSE(grants(robot, false, "fleet/OrderRequest", ""));
}

TEST(AccessDocuments, TheVda5050BridgeSpeaksForItsVehiclesEachInItsOwnPartition) {
  const auto bridge = grants_of(Role::kBridge, {"v1", "v2"});
  for (const char* topic :
       {"fleet/RobotState", "fleet/RobotPath", "fleet/OrderState", "fleet/TrafficRequest", "fleet/SimTruth"}) {
    EXPECT_TRUE(grants(bridge, true, topic, "robot.v1")) << topic;
    EXPECT_TRUE(grants(bridge, true, topic, "robot.v2")) << topic;
    EXPECT_FALSE(grants(bridge, true, topic, "robot.fl1")) << topic;
    EXPECT_FALSE(grants(bridge, true, topic, "")) << topic;
    EXPECT_FALSE(grants(bridge, true, topic, "robot.*")) << topic;
  }
  EXPECT_TRUE(grants(bridge, false, "fleet/TrafficGrant", "robot.v2"));
  EXPECT_FALSE(grants(bridge, false, "fleet/TrafficGrant", "robot.fl1"));
  EXPECT_TRUE(grants(bridge, false, "fleet/Order", ""));
  EXPECT_FALSE(grants(bridge, true, "fleet/OrderRequest", ""));
  EXPECT_FALSE(grants(bridge, false, "fleet/SimTruth", "robot.*")) << "its vehicles report their bodies";
}

TEST(AccessDocuments, OnlyTheServerPublishesWhatTheServerOwnsAndOnlyTheOperatorOrders) {
  const auto server = grants_of(Role::kServer);
  const auto operator_ = grants_of(Role::kOperator);
  const auto robot = grants_of(Role::kRobot, {"r"});
  for (const char* topic : {"fleet/Order", "fleet/TrafficGrant", "fleet/NeighbourView", "fleet/MapAssignment",
                            "fleet/StaticObstacles", "fleet/OrderInfo", "fleet/PalletTruth"}) {
    EXPECT_TRUE(grants(server, true, topic, "*")) << topic;
    EXPECT_FALSE(grants(operator_, true, topic, "")) << topic;
    EXPECT_FALSE(grants(robot, true, topic, "robot.r")) << topic;
  }
  EXPECT_TRUE(grants(operator_, true, "fleet/OrderRequest", ""));
  EXPECT_TRUE(grants(operator_, true, "fleet/Command", ""));
  EXPECT_FALSE(grants(server, true, "fleet/OrderRequest", "*"));
  for (const std::string& topic : every_topic()) EXPECT_TRUE(grants(operator_, false, topic, "*")) << topic;
}

TEST(AccessDocuments, PermissionsNameTheSubjectTheValidityAndDenyTheRest) {
  const std::string doc =
      permissions_document("fl-1", grants_of(Role::kRobot, {"fl-1"}), "2026-12-06T00:00:00", "2027-12-06T00:00:00");
  EXPECT_NE(doc.find("<subject_name>CN=fl-1,O=Fleet</subject_name>"), std::string::npos);
  EXPECT_NE(doc.find("<not_before>2026-12-06T00:00:00</not_before>"), std::string::npos);
  EXPECT_NE(doc.find("<not_after>2027-12-06T00:00:00</not_after>"), std::string::npos);
  EXPECT_NE(doc.find("<partition>robot.fl-1</partition>"), std::string::npos);
  EXPECT_NE(doc.find("<default>DENY</default>"), std::string::npos);
}

TEST(AccessDocuments, GovernanceRefusesStrangersAndEncryptsEverything) {
  const std::string doc = governance_document();
  EXPECT_NE(doc.find("<allow_unauthenticated_participants>false</allow_unauthenticated_participants>"),
            std::string::npos);
  EXPECT_NE(doc.find("<discovery_protection_kind>ENCRYPT</discovery_protection_kind>"), std::string::npos);
  EXPECT_NE(doc.find("<liveliness_protection_kind>ENCRYPT</liveliness_protection_kind>"), std::string::npos);
  EXPECT_NE(doc.find("<data_protection_kind>ENCRYPT</data_protection_kind>"), std::string::npos);
  EXPECT_NE(doc.find("<enable_write_access_control>true</enable_write_access_control>"), std::string::npos);
}

}  // namespace
}  // namespace fleet::security
