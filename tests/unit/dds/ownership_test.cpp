// The topics the server owns take exclusive ownership from their topic: a reader takes each
// instance from its strongest live writer, so robots follow the server of the highest term.

#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "dds/environment.hpp"
#include "dds/qos.hpp"
#include "dds/topics.hpp"

using namespace fleet;

namespace {

constexpr std::uint32_t kDomain = 195;  // no other test uses it

dds_ownership_kind_t ownership_of(dds_entity_t entity) {
  dds::Qos qos;
  EXPECT_EQ(dds_get_qos(entity, qos.get()), DDS_RETCODE_OK);
  dds_ownership_kind_t kind = DDS_OWNERSHIP_SHARED;
  EXPECT_TRUE(dds_qget_ownership(qos.get(), &kind));
  return kind;
}

TEST(Ownership, ServerOwnedTopicsAreExclusiveForEveryReaderAndWriterOthersShared) {
  dds::use_fleet_dds_config();
  dds::Participant participant(kDomain);
  dds::Reader<model::TrafficGrant> grants(participant, dds::qos::live_state());
  dds::Reader<model::OrderInfo> orders(participant, dds::qos::latched_state());
  dds::Writer<model::SiteStateDocument> site_state(participant, dds::qos::latched_state());
  dds::Reader<model::RobotState> states(participant, dds::qos::robot_state());
  dds::Reader<model::ServerLoad> loads(participant, dds::qos::live_state());
  EXPECT_EQ(ownership_of(grants.handle()), DDS_OWNERSHIP_EXCLUSIVE);
  EXPECT_EQ(ownership_of(orders.handle()), DDS_OWNERSHIP_EXCLUSIVE);
  EXPECT_EQ(ownership_of(site_state.handle()), DDS_OWNERSHIP_EXCLUSIVE);
  EXPECT_EQ(ownership_of(states.handle()), DDS_OWNERSHIP_SHARED) << "robots write their own state";
  EXPECT_EQ(ownership_of(loads.handle()), DDS_OWNERSHIP_SHARED) << "every server writes its own load";
}

// Two servers write the same order: the reader takes only the stronger writer's samples, whatever
// the weaker one writes after it.
TEST(Ownership, AReaderTakesAnInstanceFromTheStrongerServerOnly) {
  dds::use_fleet_dds_config();
  dds::Participant weaker(kDomain, 1);
  dds::Participant stronger(kDomain, 2);
  dds::Participant robot(kDomain);
  dds::Writer<model::OrderInfo> weak_writer(weaker, dds::qos::latched_state());
  dds::Writer<model::OrderInfo> strong_writer(stronger, dds::qos::latched_state());
  dds::Reader<model::OrderInfo> reader(robot, dds::qos::latched_state());
  ASSERT_TRUE(weak_writer.wait_for_readers(1, std::chrono::seconds(5)));
  ASSERT_TRUE(strong_writer.wait_for_readers(1, std::chrono::seconds(5)));
  model::OrderInfo info;
  info.order_id = 7;
  info.state = "QUEUED";
  info.robot_id = "from-the-stronger";
  ASSERT_TRUE(strong_writer.write(info));
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  info.robot_id = "from-the-weaker";
  ASSERT_TRUE(weak_writer.write(info));
  std::vector<std::string> taken;
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  while (std::chrono::steady_clock::now() < end) {
    reader.take_data([&](model::OrderInfo&& order) { taken.push_back(order.robot_id); });
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_FALSE(taken.empty());
  for (const std::string& robot_named : taken) EXPECT_EQ(robot_named, "from-the-stronger");
}

}  // namespace
