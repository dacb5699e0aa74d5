#include "map/site.hpp"

#include <gtest/gtest.h>

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
  const Site site = load_site(FLEET_SOURCE_DIR "/maps/table_a.yaml");
  EXPECT_EQ(site.name, "table_a");
  EXPECT_GE(site.loading_areas.size(), 6u);
  EXPECT_GE(site.homes.size(), 4u);
  EXPECT_EQ(site.uwb_anchors.size(), 4u);
  ASSERT_NE(site.find_area("A1"), nullptr);
  EXPECT_TRUE(site.find_area("A1")->pallet_at_start);
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

namespace fleet::map {
namespace {

TEST(SiteRevision, TableAWithARoadClosedIsARevisionTableBIsNot) {
  const Site a = load_site(FLEET_SOURCE_DIR "/maps/table_a.yaml");
  const Site closed = load_site(FLEET_SOURCE_DIR "/maps/table_a_north_closed.yaml");
  const Site b = load_site(FLEET_SOURCE_DIR "/maps/table_b.yaml");
  EXPECT_EQ(revision_mismatch(a, closed), "");
  EXPECT_EQ(revision_mismatch(closed, a), "");
  const std::string why = revision_mismatch(a, b);
  EXPECT_NE(why.find("table_b is not a revision of table_a"), std::string::npos) << why;
  Site moved = closed;
  moved.homes[3].pose.x += 0.01;
  EXPECT_NE(revision_mismatch(a, moved).find("home H4"), std::string::npos) << revision_mismatch(a, moved);
}

}  // namespace
}  // namespace fleet::map
