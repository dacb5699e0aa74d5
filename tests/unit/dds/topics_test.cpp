// What crosses the wire comes back as it was written: model values through the IDL's C structs
// (dds/topics.cpp) and Cyclone DDS, written and taken in one process on a domain of its own.

#include "dds/topics.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "dds/environment.hpp"
#include "dds/qos.hpp"

using namespace fleet;

namespace {

constexpr std::uint32_t kDomain = 194;  // no other test uses it

/// `sent` written with `qos`, and what a reader of the same participant takes of it.
template <typename Message>
std::optional<Message> round_trip(const Message& sent, const dds::Qos& qos) {
  dds::use_fleet_dds_config();
  dds::Participant participant(kDomain);
  dds::Writer<Message> writer(participant, qos);
  dds::Reader<Message> reader(participant, qos);
  if (!writer.wait_for_readers(1, std::chrono::seconds(5)) || !writer.write(sent)) return std::nullopt;
  std::optional<Message> taken;
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (!taken && std::chrono::steady_clock::now() < end) {
    reader.take_data([&](Message&& message) { taken = std::move(message); });
    if (!taken) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return taken;
}

std::optional<model::RobotState> round_trip(const model::RobotState& sent) {
  return round_trip(sent, dds::qos::robot_state());
}

model::RobotState docking_stacker() {
  model::RobotState s;
  s.robot_id = "st2";
  s.fleet_id = "stackers";
  s.map_id = "plant";
  s.pose = {10.5, 4.25, 1.5};
  s.covariance = {0.001, 0, 0, 0, 0.001, 0, 0, 0, 0.0003};
  s.speed = -0.3;
  s.task_state = "DOCKING";
  s.detail = "docking: reverse_to_target2";
  s.order_id = 42;
  s.sim_time = 123.45;
  s.docking_targets = {{11.0, 5.5}, {12.5, 5.0}};
  s.detected_pallet = geometry::Pose2{12.5, 3.7, 1.5708};
  return s;
}

}  // namespace

TEST(Topics, RobotStateComesBackWithItsDockingTargetsAndDetectedPallet) {
  const model::RobotState sent = docking_stacker();
  const auto taken = round_trip(sent);
  ASSERT_TRUE(taken) << "nothing came back";
  EXPECT_EQ(taken->robot_id, "st2");
  EXPECT_EQ(taken->task_state, "DOCKING");
  EXPECT_EQ(taken->detail, sent.detail);
  EXPECT_EQ(taken->order_id, 42);
  EXPECT_DOUBLE_EQ(taken->pose.yaw, 1.5);
  EXPECT_EQ(taken->covariance, sent.covariance);
  ASSERT_EQ(taken->docking_targets.size(), 2u);
  EXPECT_DOUBLE_EQ(taken->docking_targets[0].x, 11.0);
  EXPECT_DOUBLE_EQ(taken->docking_targets[0].y, 5.5);
  EXPECT_DOUBLE_EQ(taken->docking_targets[1].x, 12.5);
  EXPECT_DOUBLE_EQ(taken->docking_targets[1].y, 5.0);
  ASSERT_TRUE(taken->detected_pallet);
  EXPECT_DOUBLE_EQ(taken->detected_pallet->x, 12.5);
  EXPECT_DOUBLE_EQ(taken->detected_pallet->y, 3.7);
  EXPECT_DOUBLE_EQ(taken->detected_pallet->yaw, 1.5708);
}

TEST(Topics, RobotStateWithoutADockingComesBackWithoutOne) {
  model::RobotState sent = docking_stacker();
  sent.task_state = "TRACK_PATH";
  sent.docking_targets.clear();
  sent.detected_pallet.reset();
  const auto taken = round_trip(sent);
  ASSERT_TRUE(taken) << "nothing came back";
  EXPECT_EQ(taken->task_state, "TRACK_PATH");
  EXPECT_TRUE(taken->docking_targets.empty());
  EXPECT_FALSE(taken->detected_pallet);
}

TEST(Topics, RobotStateCarriesAtMostTheTwoTargetsTheIdlBounds) {
  model::RobotState sent = docking_stacker();
  sent.docking_targets.push_back({20.0, 20.0});
  const auto taken = round_trip(sent);
  ASSERT_TRUE(taken) << "nothing came back";
  ASSERT_EQ(taken->docking_targets.size(), 2u);
  EXPECT_DOUBLE_EQ(taken->docking_targets[1].x, 12.5);
}

TEST(Topics, NeighbourViewComesBackWithItsRobotsAndTrueBodiesInTheRobotsPartition) {
  dds::use_fleet_dds_config();
  dds::Participant participant(kDomain);
  const std::string partition = model::robot_partition("c7");
  dds::Writer<model::NeighbourView> writer(participant, dds::qos::live_state(), partition);
  dds::Reader<model::NeighbourView> reader(participant, dds::qos::live_state(), partition);
  model::NeighbourView sent{"c7", "mid_warehouse", 12.5, 8.0, true, {}, {}};
  sent.robots.push_back({"c8", "carts", {3.0, 4.0, 0.5}, {0.6, 0.4}, 0.8, "TRACK_PATH", 12.4, {}});
  sent.bodies.push_back({"c8", {3.02, 3.99, 0.51}, {0.6, 0.4}, true, 12.45});
  ASSERT_TRUE(writer.wait_for_readers(1, std::chrono::seconds(5)));
  ASSERT_TRUE(writer.write(sent));
  std::optional<model::NeighbourView> taken;
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (!taken && std::chrono::steady_clock::now() < end) {
    reader.take_data([&](model::NeighbourView&& view) { taken = std::move(view); });
    if (!taken) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_TRUE(taken) << "nothing came back";
  EXPECT_EQ(taken->robot_id, "c7");
  EXPECT_TRUE(taken->complete);
  ASSERT_EQ(taken->robots.size(), 1u);
  EXPECT_EQ(taken->robots[0].task_state, "TRACK_PATH");
  ASSERT_EQ(taken->bodies.size(), 1u);
  EXPECT_EQ(taken->bodies[0].robot_id, "c8");
  EXPECT_DOUBLE_EQ(taken->bodies[0].pose.x, 3.02);
  EXPECT_DOUBLE_EQ(taken->bodies[0].footprint.length, 0.6);
  EXPECT_TRUE(taken->bodies[0].carrying_pallet);
  EXPECT_DOUBLE_EQ(taken->bodies[0].sim_time, 12.45);
}

TEST(Topics, AnOrderReportItsWriterUnregistersIsNotReplayedToAServerThatJoinsLater) {
  // An agent unregisters the report of an order the server withdrew from it: a restarted server
  // hears the reports it still latches, and not that order running on it.
  dds::use_fleet_dds_config();
  dds::Participant participant(kDomain);
  dds::Writer<model::OrderReport> writer(participant, dds::qos::latched_state());
  model::OrderReport withdrawn;
  withdrawn.order_id = 14;
  withdrawn.robot_id = "rt3";
  withdrawn.status = "TO_PICK";
  model::OrderReport done = withdrawn;
  done.order_id = 21;
  done.status = "DONE";
  ASSERT_TRUE(writer.write(withdrawn));
  ASSERT_TRUE(writer.write(done));
  model::OrderReport key;
  key.order_id = 14;
  writer.unregister(key);
  dds::Reader<model::OrderReport> late(participant, dds::qos::latched_state());
  std::vector<std::int64_t> heard;
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  while (std::chrono::steady_clock::now() < end) {
    late.take_data([&](model::OrderReport&& report) { heard.push_back(report.order_id); });
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_EQ(heard, std::vector<std::int64_t>{21});
}

TEST(Topics, AnOrderComesBackWithItsLoaderWalkRelease) {
  model::OrderAssignment sent;
  sent.order_id = 7;
  sent.robot_id = "pk1";
  sent.kind = "pick";
  sent.lines = "RB1,A1,2\nRB3,A3,1\n";
  sent.update_id = 4;
  sent.loader = true;
  sent.released_stops = 2;
  sent.approach_stops = 3;
  sent.pallet = 3;
  const auto taken = round_trip(sent, dds::qos::latched_state());
  ASSERT_TRUE(taken);
  EXPECT_TRUE(taken->loader);
  EXPECT_EQ(taken->released_stops, 2u);
  EXPECT_EQ(taken->approach_stops, 3u);
  EXPECT_EQ(taken->pallet, 3);
  EXPECT_EQ(taken->lines, sent.lines);
  EXPECT_EQ(taken->update_id, 4u);
  EXPECT_FALSE(taken->stand);
}

TEST(Topics, AnOrderComesBackWithWhereItsTransportStands) {
  model::OrderAssignment sent;
  sent.order_id = 8;
  sent.robot_id = "st1";
  sent.kind = "transport";
  sent.pick_area = "FG5";
  sent.stand = geometry::Pose2{39.18, 10.6, 0.0};
  const auto taken = round_trip(sent, dds::qos::latched_state());
  ASSERT_TRUE(taken);
  ASSERT_TRUE(taken->stand);
  EXPECT_DOUBLE_EQ(taken->stand->x, 39.18);
  EXPECT_DOUBLE_EQ(taken->stand->y, 10.6);
  EXPECT_TRUE(taken->drop_area.empty());
}
