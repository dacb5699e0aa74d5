// Orders on the plant with its three fleets: the checks fleetctl, the web API and the server make,
// with the places each fleet reaches on the lanes its vehicle fits.

#include <gtest/gtest.h>

#include <algorithm>

#include "config/fleet_config.hpp"
#include "map/site_map.hpp"
#include "orders/order_request_check.hpp"
#include "test_paths.hpp"
#include "traffic/order_names.hpp"

using namespace fleet;

namespace {

struct Plant {
  config::FleetConfig config = config::load_fleet_config(fleet::test::source_path("/config/sites/plant.yaml"));
  map::SiteMap site = map::load_site_map(fleet::test::source_path("/maps/plant.yaml"));
  orders::KnownNames names = traffic::order_request_names(config, site);
  std::optional<orders::RequestProblem> check(const std::string& from, const std::string& to,
                                              const std::string& fleet) {
    return orders::check_order_request({"", from, to, "", fleet, 0}, names);
  }
};

}  // namespace

TEST(PlantCapability, AHighRackPlaceIsForTheReachTrucksOnly) {
  Plant plant;
  EXPECT_FALSE(plant.check("RH1", "EX1", "").has_value());
  EXPECT_FALSE(plant.check("RH1", "EX1", "reach_trucks").has_value());
  const auto forklifts = plant.check("RH1", "EX1", "forklifts");
  ASSERT_TRUE(forklifts.has_value());
  EXPECT_EQ(forklifts->field, "fleet");
  EXPECT_NE(forklifts->message.find("forklifts lifts to 0.50 m, the load at RH1 stands at 2.20 m"), std::string::npos)
      << forklifts->message;
}

TEST(PlantCapability, APlaceOnlyTheNarrowRoadsReachIsForTheForkliftsOnly) {
  Plant plant;
  const auto& reach = plant.names.abilities[1];
  ASSERT_EQ(reach.fleet_id, "reach_trucks");
  EXPECT_NE(std::find(reach.out_of_reach.begin(), reach.out_of_reach.end(), "EN1"), reach.out_of_reach.end());
  // The forklifts reach every place but the stackers' bays (PT1-PT4), which no lane leads into
  // (a stacker reverses in from the aisle), and the pickers' stalls (PP1-PP4), too narrow for them.
  for (const auto& place : plant.names.abilities[0].out_of_reach) {
    EXPECT_TRUE(place.starts_with("PT") || place.starts_with("PP")) << place;
  }
  EXPECT_FALSE(plant.check("EX1", "EN1", "").has_value());
  const auto trucks = plant.check("EX1", "EN1", "reach_trucks");
  ASSERT_TRUE(trucks.has_value());
  EXPECT_NE(trucks->message.find("does not reach EN1 on the lanes its vehicles fit"), std::string::npos)
      << trucks->message;
}

TEST(PlantCapability, AFinishedGoodsPlaceBehindItsLimiterIsNeverADropPlace) {
  Plant plant;
  const auto drop = plant.check("EX1", "FG1", "");
  ASSERT_TRUE(drop.has_value());
  EXPECT_EQ(drop->field, "to");
  EXPECT_NE(drop->message.find("FG1 offers pick, not 'drop'"), std::string::npos) << drop->message;
}

TEST(PlantCapability, OnlyThePickersPickItemsAndOnlyWhereAPlaceOffersThem) {
  Plant plant;
  EXPECT_EQ(orders::check_order_request({"pick", "RB1", "PS1", "", "", 0}, plant.names), std::nullopt);
  const auto pinned = orders::check_order_request({"pick", "RB1", "PS1", "", "forklifts", 0}, plant.names);
  ASSERT_TRUE(pinned.has_value());
  EXPECT_NE(pinned->message.find("forklifts cannot 'pickItem'"), std::string::npos) << pinned->message;
  // A transport's places offer no items: EX1 takes no dropItem.
  const auto to_expedition = orders::check_order_request({"pick", "RB1", "EX1", "", "", 0}, plant.names);
  ASSERT_TRUE(to_expedition.has_value());
  EXPECT_NE(to_expedition->message.find("'dropItem'"), std::string::npos) << to_expedition->message;
}

TEST(PlantCapability, AStackerDocksOnlyWhereTheRoadInFrontLeavesItRoomToTurn) {
  Plant plant;
  const auto& stackers = plant.names.abilities[2];
  ASSERT_EQ(stackers.fleet_id, "stackers");
  const auto out = [&](const std::string& place) {
    return std::find(stackers.out_of_reach.begin(), stackers.out_of_reach.end(), place) != stackers.out_of_reach.end();
  };
  // The narrow spurs: the expedition spur's EN places and the packing stations on the spurs.
  for (const char* place : {"EN1", "EN6", "PS1", "PS8"}) EXPECT_TRUE(out(place)) << place;
  // The corridor (2.98 m), the cross aisles (3.5 m: the packing stations along the south one too)
  // and the rack aisles (3.0 m).
  for (const char* place : {"FG1", "FG16", "PK1", "EX1", "EX11", "WA1", "RB1", "PS9", "PS12"}) {
    EXPECT_FALSE(out(place)) << place;
  }
  EXPECT_FALSE(plant.check("FG1", "EX2", "stackers").has_value());
  // The packing chain's two transports from a station by the racks.
  EXPECT_FALSE(plant.check("PS9", "EX1", "stackers").has_value());
  EXPECT_FALSE(plant.check("PK1", "PS9", "stackers").has_value());
  const auto spur = plant.check("FG1", "EN1", "stackers");
  ASSERT_TRUE(spur.has_value());
  EXPECT_NE(spur->message.find("stackers does not reach EN1"), std::string::npos) << spur->message;
}
