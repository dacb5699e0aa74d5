// The stream's frames and diffs (server/web_server.hpp), without a network: a client that applies
// every diff must end with exactly the frame the server holds.

#include <gtest/gtest.h>

#include <random>

#include "server/web_server.hpp"

using fleet::server::frame_apply;
using fleet::server::frame_diff;
using fleet::server::frame_json;
using fleet::server::LiveSnapshot;
using fleet::server::RobotView;
using nlohmann::json;

namespace {

RobotView robot(const std::string& id, double x, double y) {
  RobotView v;
  v.state.robot_id = id;
  v.state.fleet_id = "forklifts";
  v.state.pose = {x, y, 0.5};
  v.state.task_state = "TRACK_PATH";
  v.health = "alive";
  v.path = {{x, y}, {x + 0.5, y}};
  return v;
}

LiveSnapshot snapshot(int robots) {
  LiveSnapshot s;
  s.sim_time = 100.0;
  for (int i = 0; i < robots; ++i) {
    std::string id = "r";
    id += std::to_string(i);  // not "r" + to_string: GCC 12 at -O3 warns falsely (-Wrestrict) on it
    s.robots.push_back(robot(id, 0.1 * i, 0.2));
  }
  s.obstacle_enabled = {{"O1", false}, {"O2", true}};
  s.pallet_at = {{"A1", true}, {"A2", false}};
  fleet::model::OrderInfo order;
  order.order_id = 7;
  order.pick_area = "A1";
  order.drop_area = "A2";
  order.state = "ACTIVE";
  s.orders.push_back(order);
  return s;
}

}  // namespace

TEST(WebFrames, UnchangedRobotsAreNotSent) {
  LiveSnapshot a = snapshot(50);
  LiveSnapshot b = a;
  b.sim_time += 0.05;
  b.robots[3].state.pose.x += 0.01;
  const json diff = frame_diff(frame_json(a), frame_json(b));
  ASSERT_TRUE(diff.contains("robots")) << diff.dump();
  EXPECT_EQ(diff["robots"].size(), 1u) << diff.dump();
  // Only the field that moved, not the robot's path or state.
  EXPECT_EQ(diff["robots"]["r3"].size(), 1u) << diff.dump();
  EXPECT_TRUE(diff["robots"]["r3"].contains("x"));
  EXPECT_FALSE(diff.contains("orders")) << diff.dump();
  EXPECT_FALSE(diff.contains("obstacles")) << diff.dump();
  EXPECT_EQ(diff["globals"].size(), 1u) << diff.dump();  // sim_time only
}

TEST(WebFrames, SubMillimetreNoiseMakesNoDiff) {
  LiveSnapshot a = snapshot(3);
  LiveSnapshot b = a;
  b.robots[0].state.pose.x += 1e-6;
  EXPECT_TRUE(frame_diff(frame_json(a), frame_json(b)).empty());
}

TEST(WebFrames, NewRemovedAndChangedEntitiesRoundTrip) {
  const LiveSnapshot a = snapshot(4);
  LiveSnapshot b = a;
  b.robots.erase(b.robots.begin() + 1);          // r1 leaves
  b.robots.push_back(robot("new", 1.0, 1.0));    // a robot joins
  b.robots[0].truth = fleet::model::SimTruth{};  // r0 gains a true pose
  b.robots[0].health = "lost";
  b.obstacle_enabled["O1"] = true;
  b.obstacle_enabled.erase("O2");
  b.pallet_at["A1"] = false;
  b.orders[0].state = "DONE";
  b.auto_orders = true;
  json frame = frame_json(a);
  const json diff = frame_diff(frame, frame_json(b));
  EXPECT_EQ(diff["robots_removed"], json::array({"r1"})) << diff.dump();
  EXPECT_EQ(diff["obstacles_removed"], json::array({"O2"})) << diff.dump();
  EXPECT_TRUE(diff["robots"]["new"].contains("path")) << "a new robot comes whole";
  frame_apply(frame, diff);
  EXPECT_EQ(frame, frame_json(b));

  // And back: the true pose vanishes again, sent as null and removed by the client.
  const json back = frame_diff(frame, frame_json(a));
  EXPECT_TRUE(back["robots"]["r0"]["truth"].is_null()) << back.dump();
  frame_apply(frame, back);
  EXPECT_EQ(frame, frame_json(a));
}

TEST(WebFrames, RandomSequencesOfSnapshotsRoundTrip) {
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> step(-0.02, 0.02);
  std::bernoulli_distribution coin(0.1);
  LiveSnapshot s = snapshot(20);
  json client = frame_json(s);
  json server = client;
  for (int i = 0; i < 200; ++i) {
    for (auto& r : s.robots) {
      r.state.pose.x += step(rng);
      if (coin(rng)) r.path.push_back({step(rng), step(rng)});
      if (coin(rng)) r.health = r.health == "alive" ? "stale" : "alive";
    }
    if (coin(rng)) s.pallet_at["A2"] = !s.pallet_at["A2"];
    if (coin(rng)) s.robots.push_back(robot("x" + std::to_string(i), 0, 0));
    if (coin(rng) && !s.robots.empty()) s.robots.erase(s.robots.begin());
    s.sim_time += 0.05;
    const json next = frame_json(s);
    frame_apply(client, frame_diff(server, next));
    server = next;
    ASSERT_EQ(client, server) << "step " << i;
  }
}

TEST(WebFrames, ADockingRobotCarriesItsTargetsAndDetectedPalletUntilTheDockingEnds) {
  const LiveSnapshot parked = snapshot(2);
  LiveSnapshot docking = parked;
  docking.robots[1].state.docking_targets = {{10.12345, 4.0}, {11.5, 3.5}};
  docking.robots[1].state.detected_pallet = fleet::geometry::Pose2{11.5, 2.2, 1.570796};
  json frame = frame_json(parked);
  EXPECT_FALSE(frame["robots"]["r1"].contains("dock_targets")) << "absent, not empty, while it does not dock";
  EXPECT_FALSE(frame["robots"]["r1"].contains("detected_pallet"));

  const json diff = frame_diff(frame, frame_json(docking));
  ASSERT_EQ(diff["robots"].size(), 1u) << diff.dump();
  const json& r1 = diff["robots"]["r1"];
  EXPECT_EQ(r1.size(), 2u) << r1.dump();
  EXPECT_EQ(r1["dock_targets"], json::parse("[[10.123, 4.0], [11.5, 3.5]]")) << r1.dump();
  EXPECT_EQ(r1["detected_pallet"], json::parse("[11.5, 2.2, 1.5708]")) << r1.dump();
  frame_apply(frame, diff);
  EXPECT_EQ(frame, frame_json(docking));
  EXPECT_EQ(fleet::server::state_json(docking)["robots"][1]["detected_pallet"], r1["detected_pallet"]);

  // Docked: both go, sent as null and removed by the client.
  const json back = frame_diff(frame, frame_json(parked));
  EXPECT_TRUE(back["robots"]["r1"]["dock_targets"].is_null()) << back.dump();
  EXPECT_TRUE(back["robots"]["r1"]["detected_pallet"].is_null()) << back.dump();
  frame_apply(frame, back);
  EXPECT_EQ(frame, frame_json(parked));
}

TEST(WebFrames, StateListsRobotsWithIdsAndOrdersWithHistory) {
  LiveSnapshot s = snapshot(2);
  s.orders[0].history.push_back({1.0, "QUEUED", "", "", "", 0, 0});
  const json state = fleet::server::state_json(s);
  ASSERT_EQ(state["robots"].size(), 2u);
  EXPECT_EQ(state["robots"][1]["id"], "r1");
  EXPECT_EQ(state["orders"][0]["history"][0]["state"], "QUEUED");
  EXPECT_EQ(state["pallets"]["A1"], true);
}

TEST(WebFrames, PosesAreRoundedToShortDecimals) {
  LiveSnapshot s = snapshot(1);
  s.robots[0].state.pose.x = 0.7000000000000001;
  s.robots[0].state.covariance[0] = 1.23456e-5;
  const json f = frame_json(s);
  EXPECT_EQ(f["robots"]["r0"]["x"].dump(), "0.7");
  EXPECT_EQ(f["robots"]["r0"]["cov"][0].dump(), "1.23e-05");
}

TEST(WebFrames, FleetsAreVda5050Factsheets) {
  const auto config = fleet::config::parse_fleet_config(R"(
fleets:
  - id: small
    robot_type: forklift
    robots: [{id: s1, home: H1}]
  - id: tall
    robot_type: forklift
    profile: {footprint: [[0.8, -0.45], [0.8, 0.45], [-0.8, 0.45], [-0.8, -0.45]], load: {lift_height: 4.5}, actions: [pick, drop]}
    robots: [{id: t1, home: H2}, {id: t2, home: H3}]
)",
                                                        "t");
  const auto j = fleet::server::fleets_json(config);
  ASSERT_EQ(j["fleets"].size(), 2u);
  EXPECT_EQ(j["fleets"][1]["fleet"], "tall");
  EXPECT_DOUBLE_EQ(j["fleets"][1]["physicalParameters"]["length"].get<double>(), 1.6);
  EXPECT_DOUBLE_EQ(j["fleets"][1]["loadSpecification"]["loadSets"][0]["maxLoadhandlingHeight"].get<double>(), 4.5);
  EXPECT_EQ(j["fleets"][1]["protocolFeatures"]["agvActions"].size(), 2u);
  EXPECT_EQ(j["fleets"][1]["robots"].size(), 2u);
}
