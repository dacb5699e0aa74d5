#include "orders/site_state.hpp"

#include <gtest/gtest.h>

#include "common/errors.hpp"

using namespace fleet::orders;

namespace {
std::vector<Place> three_places() {
  return {{"A1", {1, 0, 0}}, {"A2", {2, 0, 0}}, {"A3", {3, 0, 0}}};
}

SiteNames plant_names(const std::string& map_id = "site") {
  return {map_id, three_places(), {"fk1", "fk2"}, {"door", "spill"}};
}

SiteState busy_state() {
  SiteState state;
  state.map_id = "site";
  state.ledger = AreaLedger(three_places());
  state.ledger.record({1, "pallet", {1.02, 0.01, 0.05}, "A1", ""});
  state.ledger.record({2, "pallet", {5.0, 6.0, 1.0}, "", "fk2"});
  state.ledger.record_unnamed_drop("A3");
  state.parked_at = {{"fk1", "P7"}, {"fk2", "P2"}};
  state.obstacle_enabled = {{"door", true}, {"spill", false}};
  return state;
}

std::string message_of(const std::string& text, const SiteNames& names = plant_names()) {
  try {
    site_state_from_json(text, names, "var/fleet.db");
  } catch (const fleet::InputError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(SiteState, ReadsBackWhatItWrote) {
  const SiteState state = busy_state();
  const RestoredSiteState back = site_state_from_json(to_json(state), plant_names(), "var/fleet.db");
  EXPECT_TRUE(back.dropped.empty());
  EXPECT_EQ(to_json(back.state), to_json(state));
  EXPECT_TRUE(back.state.ledger.holds_load("A1"));
  EXPECT_FALSE(back.state.ledger.holds_load("A2"));
  EXPECT_TRUE(back.state.ledger.holds_load("A3")) << "a load put down without a name still occupies its place";
  ASSERT_NE(back.state.ledger.carried_by("fk2"), nullptr);
  EXPECT_EQ(back.state.ledger.carried_by("fk2")->id, 2);
  EXPECT_DOUBLE_EQ(back.state.ledger.find(1)->pose.yaw, 0.05);
  EXPECT_EQ(back.state.parked_at.at("fk1"), "P7");
  EXPECT_TRUE(back.state.obstacle_enabled.at("door"));
  EXPECT_FALSE(back.state.obstacle_enabled.at("spill"));
}

TEST(SiteState, OneStateGivesOneText) {
  // Built in another order, the same state serialises to the same bytes: a mirror can compare texts.
  SiteState other;
  other.map_id = "site";
  other.ledger = AreaLedger(three_places());
  other.ledger.record_unnamed_drop("A3");
  other.ledger.record({2, "pallet", {5.0, 6.0, 1.0}, "", "fk2"});
  other.ledger.record({1, "pallet", {1.02, 0.01, 0.05}, "A1", ""});
  other.obstacle_enabled = {{"spill", false}, {"door", true}};
  other.parked_at = {{"fk2", "P2"}, {"fk1", "P7"}};
  EXPECT_EQ(to_json(other), to_json(busy_state()));
}

TEST(SiteState, WhatTheSiteNoLongerHasIsLeftOutAndSaid) {
  SiteNames smaller{"site", {{"A2", {2, 0, 0}}}, {"fk2"}, {"door"}};
  const RestoredSiteState back = site_state_from_json(to_json(busy_state()), smaller, "var/fleet.db");
  ASSERT_NE(back.state.ledger.find(1), nullptr) << "the load itself is kept";
  EXPECT_EQ(back.state.ledger.find(1)->place, "");
  EXPECT_DOUBLE_EQ(back.state.ledger.find(1)->pose.x, 1.02);
  EXPECT_FALSE(back.state.parked_at.count("fk1"));
  EXPECT_FALSE(back.state.obstacle_enabled.count("spill"));
  EXPECT_TRUE(back.state.obstacle_enabled.at("door"));
  std::string all;
  for (const auto& line : back.dropped) all += line + "\n";
  EXPECT_EQ(back.dropped.size(), 4u) << all;
  EXPECT_NE(all.find("load 1 stood on 'A1'"), std::string::npos) << all;
  EXPECT_NE(all.find("'A3'"), std::string::npos) << all;
  EXPECT_NE(all.find("robot 'fk1'"), std::string::npos) << all;
  EXPECT_NE(all.find("obstacle 'spill'"), std::string::npos) << all;
}

TEST(SiteState, ObstaclesOfAnotherMapStartAsTheSiteFileSetsThem) {
  const RestoredSiteState back = site_state_from_json(to_json(busy_state()), plant_names("site-rev2"), "db");
  EXPECT_TRUE(back.state.obstacle_enabled.empty());
  EXPECT_EQ(back.state.map_id, "site-rev2");
  ASSERT_EQ(back.dropped.size(), 1u);
  EXPECT_NE(back.dropped[0].find("stored for map 'site'"), std::string::npos) << back.dropped[0];
  EXPECT_TRUE(back.state.ledger.holds_load("A1")) << "the loads do not depend on the map";
}

TEST(SiteState, ADocumentThatIsNotAStateIsRefusedNamingTheFileAndKey) {
  EXPECT_NE(message_of("{").find("var/fleet.db: site state: document: not JSON"), std::string::npos) << message_of("{");
  EXPECT_NE(message_of("[]").find("not a JSON object"), std::string::npos);
  const std::string head = R"({"version":1,"map":"site","held_unnamed":[],"parked_at":{},"obstacles":{},)";
  EXPECT_NE(
      message_of(head + R"("loads":[{"id":1,"kind":"pallet","x":"far","y":0,"yaw":0,"place":"","carried_by":""}]})")
          .find("loads[0].x: not a finite number: \"far\""),
      std::string::npos);
  EXPECT_NE(message_of(head + R"("loads":[{"id":1.5,"kind":"pallet","x":0,"y":0,"yaw":0,"place":"","carried_by":""}]})")
                .find("loads[0].id: not a load id: 1.5"),
            std::string::npos);
  EXPECT_NE(message_of(head + R"("loads":[{"id":1,"x":0,"y":0,"yaw":0,"place":"","carried_by":""}]})")
                .find("loads[0]: missing key 'kind'"),
            std::string::npos);
  EXPECT_NE(message_of(R"({"version":2})").find("version 2 is not the 1 this server reads"), std::string::npos);
  EXPECT_NE(
      message_of(R"({"version":1,"map":"site","loads":[],"held_unnamed":[],"parked_at":{},"obstacles":{"door":1}})")
          .find("obstacles.door: not true or false: 1"),
      std::string::npos);
}
