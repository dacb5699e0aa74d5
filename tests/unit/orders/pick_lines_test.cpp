// Pick lists: read from CSV, checked whole against the places' boxes, cut into tours.
#include "orders/pick_lines.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "common/errors.hpp"
#include "map/site_map.hpp"
#include "test_paths.hpp"

namespace fleet::orders {
namespace {

std::string error_of(std::string_view text) {
  try {
    parse_pick_lines(text, "lines.csv");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(PickLines, ReadsPlaceItemQuantityWithAHeaderCommentsAndBlankLines) {
  const auto lines = parse_pick_lines("place,item,quantity\n# morning wave\nRB1, A1, 2\n\nRB3,A3,1\r\n", "l.csv");
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0].place, "RB1");
  EXPECT_EQ(lines[0].item, "A1");
  EXPECT_EQ(lines[0].quantity, 2);
  EXPECT_EQ(lines[0].line, 3);
  EXPECT_EQ(lines[1].line, 5);
  // Written back as the server stores a tour, it reads the same.
  EXPECT_EQ(pick_lines_csv(lines), "RB1,A1,2\nRB3,A3,1\n");
  EXPECT_EQ(parse_pick_lines(pick_lines_csv(lines), "again.csv")[1].quantity, 1);
}

TEST(PickLines, ALineItCannotReadIsNamedWithItsFileAndNumber) {
  EXPECT_EQ(error_of("RB1,A1,2\nRB2,A2\n"), "lines.csv:2: expected place,item,quantity, got 2 fields: 'RB2,A2'");
  EXPECT_EQ(error_of("RB1,A1,two\n"), "lines.csv:1: quantity 'two' is not a whole number of boxes >= 1");
  EXPECT_EQ(error_of("RB1,A1,0\n"), "lines.csv:1: quantity '0' is not a whole number of boxes >= 1");
  EXPECT_EQ(error_of("RB1,A1,1.5\n"), "lines.csv:1: quantity '1.5' is not a whole number of boxes >= 1");
  EXPECT_EQ(error_of(",A1,1\n"), "lines.csv:1: the place is empty");
  EXPECT_EQ(error_of("# nothing\n\n"), "lines.csv: no pick lines (expected place,item,quantity per line)");
}

struct Plant {
  map::SiteMap site = map::load_site_map(fleet::test::source_path("/maps/plant.yaml"));
  std::vector<std::string> places = site.site.area_ids();
  std::map<std::string, map::BoxStock> stock = declared_boxes(site.site);
  std::map<std::string, geometry::Pose2> poses = place_poses(site.site);
  std::optional<std::string> check(std::string_view text) const {
    return check_pick_lines(parse_pick_lines(text, "l.csv"), places, stock, 5.0, "l.csv");
  }
};

TEST(PickLines, ThePlantsFloorPalletsHoldBoxesOfOneArticleEach) {
  const Plant plant;
  ASSERT_EQ(plant.stock.size(), 24u);
  const map::BoxStock& rb1 = plant.stock.at("RB1");
  EXPECT_EQ(rb1.item, "A1");
  EXPECT_EQ(rb1.count, 6);
  EXPECT_DOUBLE_EQ(rb1.mass, 3.0);
  EXPECT_DOUBLE_EQ(plant.stock.at("RB4").mass, 12.0);
}

TEST(PickLines, EveryLineIsCheckedAgainstWhatItsPlaceHolds) {
  const Plant plant;
  EXPECT_EQ(plant.check("RB1,A1,2\nRB2,A2,3\nRB1,A1,4\n"), std::nullopt);
  EXPECT_EQ(*plant.check("RB1,A1,2\nRB99,A1,1\n"), "l.csv:2: unknown place 'RB99'; closest: RB9, RB19, RB1, RB2, RB3");
  EXPECT_EQ(*plant.check("RH1,A1,1\n"), "l.csv:1: place RH1 holds no boxes to pick");
  EXPECT_EQ(*plant.check("RB1,A2,1\n"), "l.csv:1: place RB1 holds item A1, not A2");
  // Lines on one place count together: 2 + 5 of the 6 boxes on RB1.
  EXPECT_EQ(*plant.check("RB1,A1,2\nRB2,A2,1\nRB1,A1,5\n"),
            "l.csv:3: place RB1 holds 6 boxes of A1, the lines ask for 7");
  EXPECT_EQ(*plant.check("RB4,A4,1\n"),
            "l.csv:1: a box of A4 weighs 12.0 kg, more than the pickers' grippers hold (5.0 kg)");
}

TEST(PickLines, ToursKeepToTheAislesAndToWhatAPickerCarries) {
  const Plant plant;
  // RB1, RB2 and RB5 stand along one rack face: visited by x.
  const auto lines = parse_pick_lines("RB2,A2,1\nRB5,A5,2\nRB1,A1,3\nRB1,A1,1\n", "l.csv");
  const auto tours = plan_tours(lines, 4, plant.poses);
  int boxes = 0;
  for (const auto& t : tours) {
    EXPECT_LE(t.boxes(), 4);
    boxes += t.boxes();
  }
  EXPECT_EQ(boxes, 7);
  ASSERT_EQ(tours.size(), 2u);
  // Ordered along the aisles: the places of a tour are visited by y, then x.
  for (const auto& t : tours) {
    for (std::size_t i = 1; i < t.lines.size(); ++i) {
      const auto& a = plant.poses.at(t.lines[i - 1].place);
      const auto& b = plant.poses.at(t.lines[i].place);
      EXPECT_TRUE(a.y < b.y - 0.01 || (std::abs(a.y - b.y) <= 0.01 && a.x <= b.x));
    }
  }
  // A line beyond the capacity is split.
  const auto big = plan_tours(parse_pick_lines("RB3,A3,9\n", "l.csv"), 4, plant.poses);
  ASSERT_EQ(big.size(), 3u);
  EXPECT_EQ(big[0].boxes(), 4);
  EXPECT_EQ(big[2].boxes(), 1);
  EXPECT_THROW(plan_tours(lines, 0, plant.poses), std::invalid_argument);
}

TEST(PickLines, AutomaticListsAreValidKeepToOneRackRowAndStopWhenTheBoxesRunOut) {
  Plant plant;
  std::mt19937_64 rng(7);
  // A list of at most `capacity` boxes, valid, from places of one rack row: its boxes and lines.
  const auto draw = [&](int capacity) {
    const auto lines = choose_auto_pick_list(plant.stock, plant.poses, 5.0, capacity, rng);
    EXPECT_TRUE(lines.has_value());
    if (!lines) return std::pair{0, std::vector<PickLine>{}};
    const auto csv = pick_lines_csv(*lines);
    EXPECT_EQ(check_pick_lines(*lines, plant.places, plant.stock, 5.0, "auto"), std::nullopt) << csv;
    int boxes = 0;
    for (const auto& line : *lines) {
      boxes += line.quantity;
      EXPECT_NEAR(plant.poses.at(line.place).y, plant.poses.at(lines->front().place).y, 0.05) << csv;
    }
    EXPECT_GE(boxes, 1);
    EXPECT_LE(boxes, capacity);
    EXPECT_EQ(plan_tours(*lines, capacity, plant.poses).size(), 1u) << csv;
    return std::pair{boxes, *lines};
  };
  int two_lines = 0;
  for (int i = 0; i < 200; ++i) {
    if (draw(kTourBoxes).second.size() == 2) ++two_lines;
  }
  EXPECT_GT(two_lines, 0);
  // A loader walk's list fills the pallet its stacker brings, unless its row runs out of boxes.
  int more_lines = 0;
  for (int i = 0; i < 200; ++i) {
    const auto [boxes, lines] = draw(kLoaderWalkBoxes);
    if (lines.empty()) continue;
    int row_stock = 0;
    for (const auto& [place, stock] : plant.stock) {
      if (stock.mass <= 5.0 && std::abs(plant.poses.at(place).y - plant.poses.at(lines.front().place).y) < 0.05) {
        row_stock += stock.count;
      }
    }
    EXPECT_EQ(boxes, std::min(kLoaderWalkBoxes, row_stock)) << pick_lines_csv(lines);
    if (lines.size() > 2) ++more_lines;
  }
  EXPECT_GT(more_lines, 0);
  // Only the heavy boxes left: the grippers hold none of them, so there is no list to give.
  for (auto& [place, boxes] : plant.stock) {
    if (boxes.mass <= 5.0) boxes.count = 0;
  }
  EXPECT_EQ(choose_auto_pick_list(plant.stock, plant.poses, 5.0, kTourBoxes, rng), std::nullopt);
}

}  // namespace
}  // namespace fleet::orders
