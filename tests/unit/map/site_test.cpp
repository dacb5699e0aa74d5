#include "map/site.hpp"

#include <gtest/gtest.h>

#include <numbers>

#include "test_paths.hpp"

using namespace fleet::map;

namespace {
std::string message_of(const std::string& yaml) {
  try {
    parse_site(yaml, "maps/bad.yaml");
  } catch (const MapError& e) {
    return e.what();
  }
  return "";
}
const std::string kBounds = "bounds: {min_x: 0, min_y: 0, max_x: 3, max_y: 3}\n";
}  // namespace

TEST(Site, ShippedTableALoads) {
  const Site site = load_site(fleet::test::source_path("/maps/table_a.yaml"));
  EXPECT_EQ(site.name, "table_a");
  EXPECT_GE(site.loading_areas.size(), 6u);
  EXPECT_GE(site.homes.size(), 4u);
  EXPECT_EQ(site.uwb_anchors.size(), 4u);
  ASSERT_NE(site.find_area("A1"), nullptr);
  EXPECT_TRUE(site.find_area("A1")->pallet_at_start);
}

TEST(Site, AVehicleStandsAtTheApproachDistanceOnTheRoadSideFacingThePlace) {
  LoadingArea area;
  area.pose = {1.0, 2.0, std::numbers::pi / 2};  // the road lies to +y
  const fleet::geometry::Pose2 stand = area.approach_pose(0.3);
  EXPECT_NEAR(stand.x, 1.0, 1e-12);
  EXPECT_NEAR(stand.y, 2.3, 1e-12);
  EXPECT_NEAR(stand.yaw, -std::numbers::pi / 2, 1e-12);
}

TEST(Site, UnknownKeyIsNamedWithFileAndLine) {
  const std::string msg = message_of(kBounds + "loading_areas:\n  - {id: A1, x: 1, y: 1, yaw: 0, colour: red}\n");
  EXPECT_NE(msg.find("maps/bad.yaml:3"), std::string::npos) << msg;
  EXPECT_NE(msg.find("loading_areas[0].colour"), std::string::npos) << msg;
}

TEST(Site, DuplicateIdsAndNonNumbersAreRefused) {
  EXPECT_NE(message_of(kBounds + "homes:\n  - {id: H, x: 1, y: 1, yaw: 0}\n  - {id: H, x: 2, y: 1, yaw: 0}\n")
                .find("duplicate id 'H'"),
            std::string::npos);
  EXPECT_NE(message_of(kBounds + "homes:\n  - {id: H, x: one, y: 1, yaw: 0}\n").find("'one' is not a number"),
            std::string::npos);
}

TEST(Site, ObstacleOutsideTheAreaIsRefused) {
  const std::string msg = message_of(kBounds + "static_obstacles:\n  - {id: O1, polygon: [[1, 1], [4, 1], [4, 2]]}\n");
  EXPECT_NE(msg.find("obstacle 'O1' lies outside the bounds"), std::string::npos) << msg;
}

TEST(Site, AMarkerInsideARackIsRefusedAndOneOnItsFaceIsTaken) {
  const std::string rack = "racks:\n  - {id: L1, polygon: [[1, 2], [2.5, 2], [2.5, 2.15], [1, 2.15]]}\n";
  // 5 cm into the rack, facing out of it: a camera's line of sight ends inside the rack.
  const std::string msg = message_of(kBounds + rack + "markers:\n  - {id: 13, x: 2, y: 2.05, yaw: -1.570796}\n");
  EXPECT_NE(msg.find("marker 13 lies inside rack L1"), std::string::npos) << msg;
  EXPECT_NE(msg.find("markers[0]"), std::string::npos) << msg;
  const Site site =
      parse_site(kBounds + rack + "markers:\n  - {id: 13, x: 2, y: 2, yaw: -1.570796}\n", "maps/good.yaml");
  EXPECT_EQ(site.markers.size(), 1u);
}

TEST(Site, PlacesOfferPickAndDropOnTheFloorUnlessTheySayOtherwise) {
  const Site site = parse_site(kBounds +
                                   "loading_areas:\n"
                                   "  - {id: A1, x: 1, y: 1, yaw: 0}\n"
                                   "  - {id: A2, x: 2, y: 1, yaw: 0, actions: [pickItem, dropItem], height: 4.4}\n",
                               "maps/good.yaml");
  ASSERT_EQ(site.loading_areas.size(), 2u);
  EXPECT_EQ(site.loading_areas[0].actions, (std::vector<std::string>{"pick", "drop"}));
  EXPECT_EQ(site.loading_areas[0].height, 0.0);
  EXPECT_TRUE(site.loading_areas[0].offers("drop"));
  EXPECT_EQ(site.loading_areas[1].actions, (std::vector<std::string>{"pickItem", "dropItem"}));
  EXPECT_FALSE(site.loading_areas[1].offers("pick"));
  EXPECT_DOUBLE_EQ(site.loading_areas[1].height, 4.4);
  EXPECT_DOUBLE_EQ(site.approach_distance, 0.30);
  EXPECT_TRUE(site.markers.empty());
}

TEST(Site, UnknownActionsAndLoadsBelowTheFloorAreNamed) {
  const std::string unknown =
      message_of(kBounds + "loading_areas:\n  - {id: A1, x: 1, y: 1, yaw: 0, actions: [pick, fly]}\n");
  EXPECT_NE(unknown.find("maps/bad.yaml:3: key 'loading_areas[0].actions[1]': unknown action 'fly'"), std::string::npos)
      << unknown;
  EXPECT_NE(unknown.find("valid: pick, drop, pickItem, dropItem"), std::string::npos) << unknown;
  EXPECT_NE(message_of(kBounds + "loading_areas:\n  - {id: A1, x: 1, y: 1, yaw: 0, actions: []}\n")
                .find("key 'loading_areas[0].actions': must be a list of at least one action"),
            std::string::npos);
  EXPECT_NE(message_of(kBounds + "loading_areas:\n  - {id: A1, x: 1, y: 1, yaw: 0, actions: [pick, pick]}\n")
                .find("action 'pick' is named twice"),
            std::string::npos);
  const std::string below = message_of(kBounds + "loading_areas:\n  - {id: A1, x: 1, y: 1, yaw: 0, height: -0.3}\n");
  EXPECT_NE(below.find("key 'loading_areas[0].height': '-0.3' is below the floor"), std::string::npos) << below;
  EXPECT_NE(message_of(kBounds + "loading_areas:\n  - {id: A1, x: 1, y: 1, yaw: 0, height: high}\n")
                .find("'high' is not a number"),
            std::string::npos);
  EXPECT_NE(message_of(kBounds + "approach_distance: 0\n").find("key 'approach_distance': must be positive"),
            std::string::npos);
}

TEST(Site, APlaceForItemsDeclaresTheBoxesOnItsPallet) {
  const std::string place = "  - {id: B1, x: 1, y: 1, yaw: 0, pallet: true, actions: [pick, pickItem], ";
  const Site site = parse_site(
      kBounds + "loading_areas:\n" + place + "boxes: {item: A7, count: 9, size: [0.4, 0.3, 0.2], mass: 4.5}}\n",
      "maps/good.yaml");
  ASSERT_TRUE(site.loading_areas[0].boxes.has_value());
  const BoxStock& b = *site.loading_areas[0].boxes;
  EXPECT_EQ(b.item, "A7");
  EXPECT_EQ(b.count, 9);
  EXPECT_DOUBLE_EQ(b.length, 0.4);
  EXPECT_DOUBLE_EQ(b.height, 0.2);
  EXPECT_DOUBLE_EQ(b.mass, 4.5);
  EXPECT_NE(message_of(kBounds + "loading_areas:\n" + place + "boxes: {item: A7, count: 2.5}}\n")
                .find("key 'loading_areas[0].boxes.count': '2.5' is not a whole number of boxes >= 1"),
            std::string::npos);
  EXPECT_NE(message_of(kBounds + "loading_areas:\n" + place + "boxes: {item: A7, count: 2, size: [0.4, 0]}}\n")
                .find("key 'loading_areas[0].boxes.size': must be [length, width, height]"),
            std::string::npos);
  EXPECT_NE(message_of(kBounds + "loading_areas:\n  - {id: B1, x: 1, y: 1, yaw: 0, actions: [pickItem], " +
                       "boxes: {item: A7, count: 2}}\n")
                .find("boxes need a pallet to stand on (pallet: true)"),
            std::string::npos);
  EXPECT_NE(message_of(kBounds + "loading_areas:\n  - {id: B1, x: 1, y: 1, yaw: 0, pallet: true, " +
                       "boxes: {item: A7, count: 2}}\n")
                .find("boxes are picked only where the place offers pickItem"),
            std::string::npos);
}

TEST(Site, MarkersHaveWholeNumberIdsOncePoseAndHeight) {
  const Site site = parse_site(kBounds +
                                   "markers:\n  - {id: 7, x: 1, y: 2, z: 1.5, yaw: 3.14}\n"
                                   "  - {id: 8, x: 2, y: 2, yaw: 0}\n",
                               "maps/good.yaml");
  ASSERT_EQ(site.markers.size(), 2u);
  EXPECT_EQ(site.markers[0].id, 7);
  EXPECT_DOUBLE_EQ(site.markers[0].pose.y, 2.0);
  EXPECT_DOUBLE_EQ(site.markers[0].z, 1.5);
  EXPECT_DOUBLE_EQ(site.markers[1].z, 0.0);
  EXPECT_NE(message_of(kBounds + "markers:\n  - {id: 7, x: 1, y: 1, yaw: 0}\n  - {id: 7, x: 2, y: 1, yaw: 0}\n")
                .find("key 'markers[1].id': duplicate id '7'"),
            std::string::npos);
  EXPECT_NE(message_of(kBounds + "markers:\n  - {id: M1, x: 1, y: 1, yaw: 0}\n").find("'M1' is not a whole number"),
            std::string::npos);
  EXPECT_NE(message_of(kBounds + "markers:\n  - {id: 1, x: 9, y: 1, yaw: 0}\n").find("marker 1 lies outside"),
            std::string::npos);
  EXPECT_NE(message_of(kBounds + "markers:\n  - {id: 1, x: 1, y: 1}\n").find("key 'markers[0].yaw' is missing"),
            std::string::npos);
}

namespace fleet::map {
namespace {

TEST(SiteRevision, TableAWithARoadClosedIsARevisionTableBIsNot) {
  const Site a = load_site(fleet::test::source_path("/maps/table_a.yaml"));
  const Site closed = load_site(fleet::test::source_path("/maps/table_a_north_closed.yaml"));
  const Site b = load_site(fleet::test::source_path("/maps/table_b.yaml"));
  EXPECT_EQ(revision_mismatch(a, closed), "");
  EXPECT_EQ(revision_mismatch(closed, a), "");
  const std::string why = revision_mismatch(a, b);
  EXPECT_NE(why.find("table_b is not a revision of table_a"), std::string::npos) << why;
  Site moved = closed;
  moved.homes[3].pose.x += 0.01;
  EXPECT_NE(revision_mismatch(a, moved).find("home H4"), std::string::npos) << revision_mismatch(a, moved);
  Site raised = closed;
  raised.loading_areas[0].height = 2.2;
  EXPECT_NE(revision_mismatch(a, raised).find("loading area A1 holds its load at another height"), std::string::npos);
}

// The plant's switchable maps are its closures; the one-lane corridor is another design of it,
// measured against it, which no server switches its robots to.
TEST(SiteRevision, ADesignVariantIsNeverARevision) {
  const Site plant = load_site(fleet::test::source_path("/maps/plant.yaml"));
  const Site one_lane = load_site(fleet::test::source_path("/maps/plant_one_lane.yaml"));
  EXPECT_EQ(one_lane.variant_of, "plant");
  EXPECT_EQ(revision_mismatch(plant, one_lane), "");  // the same places: comparable run for run
  EXPECT_EQ(site_revisions(plant), (std::vector<std::string>{"plant", "plant_middle_closed"}));
  EXPECT_EQ(site_revisions(load_site(fleet::test::source_path("/maps/table_a.yaml"))),
            (std::vector<std::string>{"table_a", "table_a_north_closed"}));
}

}  // namespace
}  // namespace fleet::map

TEST(Site, PackingNamesStationsWherePickersDropAndPlacesForFullAndEmptyPallets) {
  const std::string places = kBounds +
                             "loading_areas:\n"
                             "  - {id: PS1, x: 1, y: 1, yaw: 0, pallet: true, actions: [pick, drop, dropItem]}\n"
                             "  - {id: EX1, x: 2, y: 1, yaw: 0}\n"
                             "  - {id: PK1, x: 2, y: 2, yaw: 0, pallet: true}\n";
  const Site site = parse_site(places +
                                   "packing: {boxes_per_pallet: 6, stations: [PS1], full_pallets_to: [EX1], "
                                   "empty_pallets_from: [PK1]}\n",
                               "maps/good.yaml");
  ASSERT_TRUE(site.packing.has_value());
  EXPECT_EQ(site.packing->boxes_per_pallet, 6);
  EXPECT_EQ(site.packing->stations, std::vector<std::string>{"PS1"});
  EXPECT_EQ(site.packing->full_pallets_to, std::vector<std::string>{"EX1"});
  EXPECT_EQ(site.packing->empty_pallets_from, std::vector<std::string>{"PK1"});
  EXPECT_NE(message_of(places + "packing: {boxes_per_pallet: 6, stations: [PS1], full_pallets_to: [EX9], "
                                "empty_pallets_from: [PK1]}\n")
                .find("maps/bad.yaml:6: key 'packing.full_pallets_to[0]': unknown place 'EX9'"),
            std::string::npos);
  EXPECT_NE(message_of(places + "packing: {boxes_per_pallet: 6, stations: [EX1], full_pallets_to: [EX1], "
                                "empty_pallets_from: [PK1]}\n")
                .find("key 'packing.stations[0]': place 'EX1' does not offer dropItem"),
            std::string::npos);
  EXPECT_NE(message_of(places + "packing: {boxes_per_pallet: 0, stations: [PS1], full_pallets_to: [EX1], "
                                "empty_pallets_from: [PK1]}\n")
                .find("key 'packing.boxes_per_pallet': '0' is not a whole number of boxes >= 1"),
            std::string::npos);
  EXPECT_NE(message_of(places + "packing: {boxes_per_pallet: 6, stations: [PS1], full_pallets_to: [EX1]}\n")
                .find("key 'packing.empty_pallets_from' is missing"),
            std::string::npos);
}
