#include "orders/area_ledger.hpp"

#include <gtest/gtest.h>

using namespace fleet::orders;
using fleet::geometry::Pose2;

namespace {
AreaLedger three_places() {
  return AreaLedger({{"A1", {1, 0, 0}}, {"A2", {2, 0, 0}}, {"A3", {3, 0, 0}}});
}

Load standing(int id, const std::string& place, const std::string& kind = "pallet") {
  return {id, kind, {0.5 * id, 0, 0}, place, ""};
}
}  // namespace

TEST(AreaLedger, EveryPlaceStartsFree) {
  const AreaLedger ledger = three_places();
  EXPECT_EQ(ledger.occupancy().size(), 3u);
  for (const auto& [place, holds] : ledger.occupancy()) EXPECT_FALSE(holds) << place;
  EXPECT_FALSE(ledger.holds_load("nowhere"));
}

TEST(AreaLedger, ALoadOfAnyKindStandingOnAPlaceOccupiesIt) {
  AreaLedger ledger = three_places();
  ledger.record(standing(1, "A1", "pallet"));
  ledger.record(standing(2, "A2", "cart"));
  EXPECT_TRUE(ledger.holds_load("A1"));
  EXPECT_TRUE(ledger.holds_load("A2"));
  EXPECT_FALSE(ledger.holds_load("A3"));
  ASSERT_NE(ledger.standing_on("A2"), nullptr);
  EXPECT_EQ(ledger.standing_on("A2")->kind, "cart");
  EXPECT_EQ(ledger.standing_on("A3"), nullptr);
}

TEST(AreaLedger, LiftingFreesThePlaceAndTheRobotCarriesTheLoad) {
  AreaLedger ledger = three_places();
  ledger.record(standing(7, "A1"));
  const auto lifted = ledger.lifted("r1", 7, "A1");
  ASSERT_TRUE(lifted.has_value());
  EXPECT_EQ(lifted->carried_by, "r1");
  EXPECT_TRUE(lifted->place.empty());
  ledger.record(*lifted);
  EXPECT_FALSE(ledger.holds_load("A1"));
  ASSERT_NE(ledger.carried_by("r1"), nullptr);
  EXPECT_EQ(ledger.carried_by("r1")->id, 7);
  EXPECT_EQ(ledger.standing_on("A1"), nullptr);
  // Reported again, nothing changes.
  EXPECT_FALSE(ledger.lifted("r1", 7, "A1").has_value());
}

TEST(AreaLedger, ALiftNamingNoKnownLoadTakesTheOneOnThePickPlace) {
  AreaLedger ledger = three_places();
  ledger.record(standing(3, "A2"));
  const auto lifted = ledger.lifted("r2", 0, "A2");
  ASSERT_TRUE(lifted.has_value());
  EXPECT_EQ(lifted->id, 3);
  EXPECT_FALSE(ledger.lifted("r2", 0, "A3").has_value());
}

TEST(AreaLedger, PuttingDownStandsTheLoadWhereTheRobotPutIt) {
  AreaLedger ledger = three_places();
  ledger.record(standing(4, "A1"));
  ledger.record(*ledger.lifted("r1", 4, "A1"));
  const auto placed = ledger.put_down(4, {2.03, 0.01, 0.02}, "A2");
  ASSERT_TRUE(placed.has_value());
  ledger.record(*placed);
  EXPECT_TRUE(ledger.holds_load("A2"));
  EXPECT_EQ(ledger.carried_by("r1"), nullptr);
  EXPECT_DOUBLE_EQ(ledger.find(4)->pose.x, 2.03);
  EXPECT_FALSE(ledger.put_down(99, {}, "A3").has_value());
}

TEST(AreaLedger, AnUnnamedDropOccupiesThePlace) {
  AreaLedger ledger = three_places();
  ledger.record_unnamed_drop("A3");
  EXPECT_TRUE(ledger.holds_load("A3"));
  EXPECT_EQ(ledger.standing_on("A3"), nullptr);
}

TEST(AreaLedger, FoundEmptyKeepsARecordedLoadsPlaceOccupied) {
  AreaLedger ledger = three_places();
  ledger.record(standing(5, "A1"));
  const Load* recorded = ledger.found_empty("A1");
  ASSERT_NE(recorded, nullptr);
  EXPECT_EQ(recorded->id, 5);
  EXPECT_TRUE(ledger.holds_load("A1"));
}

TEST(AreaLedger, FoundEmptyFreesAPlaceWithoutARecordedLoad) {
  AreaLedger ledger = three_places();
  ledger.record_unnamed_drop("A2");
  EXPECT_EQ(ledger.found_empty("A2"), nullptr);
  EXPECT_FALSE(ledger.holds_load("A2"));
}

TEST(AreaLedger, ARestartedRobotsLoadGoesBackToThePreferredPlaceWhenFree) {
  AreaLedger ledger = three_places();
  ledger.record(standing(1, "A1"));
  ledger.record(*ledger.lifted("r1", 1, "A1"));
  const auto back = ledger.returned_from("r1", "A1");
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->place, "A1");
  EXPECT_TRUE(back->carried_by.empty());
  EXPECT_DOUBLE_EQ(back->pose.x, 1.0);  // exactly on the place
}

TEST(AreaLedger, ARestartedRobotsLoadGoesToTheFirstFreePlaceOtherwise) {
  AreaLedger ledger = three_places();
  ledger.record(standing(1, "A1"));
  ledger.record(standing(2, "A2"));
  ledger.record(*ledger.lifted("r1", 1, "A1"));
  ledger.record(standing(3, "A1"));  // another load took its place
  const auto back = ledger.returned_from("r1", "A1");
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->place, "A3");
  EXPECT_FALSE(ledger.returned_from("r1", "unknown")->place.empty());
}

TEST(AreaLedger, NoReturnWithoutACarriedLoadOrAFreePlace) {
  AreaLedger ledger = three_places();
  EXPECT_FALSE(ledger.returned_from("r1", "A1").has_value());
  ledger.record(standing(1, "A1"));
  ledger.record(standing(2, "A2"));
  ledger.record(standing(3, "A3"));
  ledger.record({4, "box", {}, "", "r1"});
  EXPECT_FALSE(ledger.returned_from("r1", "A1").has_value());
}
