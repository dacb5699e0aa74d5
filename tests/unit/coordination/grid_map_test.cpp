#include "coordination/grid_map.hpp"

#include <gtest/gtest.h>

#include <sstream>

#include "common/errors.hpp"
#include "coordination/heading_distances.hpp"

namespace fleet::coordination {
namespace {

GridMap parse(const std::string& text) {
  std::istringstream in(text);
  return parse_grid_map(in, "test.map");
}

std::string message_of(const std::string& text) {
  try {
    parse(text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(GridMap, ReadsTheMovingAiFormatWithItsFreeAndBlockedSymbols) {
  const GridMap map = parse("type octile\nheight 2\nwidth 4\nmap\n.E@S\nT..G\n");
  EXPECT_EQ(map.rows, 2);
  EXPECT_EQ(map.cols, 4);
  EXPECT_EQ(map.free_cells(), 6);
  EXPECT_TRUE(map.is_free(1));
  EXPECT_FALSE(map.is_free(2));
  EXPECT_FALSE(map.is_free(4));
  EXPECT_EQ(map.step(1, 1), 5);   // south
  EXPECT_EQ(map.step(1, 0), -1);  // east is blocked
  EXPECT_EQ(map.step(0, 2), -1);  // west leaves the map
  EXPECT_EQ(map.step(3, 0), -1);  // east of the last column does not wrap to the next row
  EXPECT_EQ(map.heading_between(5, 6), 0);
  EXPECT_EQ(map.heading_between(5, 1), 3);
  EXPECT_EQ(map.heading_between(0, 6), -1);
}

TEST(GridMap, NamesTheFileAndLineOfWhatIsWrong) {
  EXPECT_NE(message_of("type octile\nheight 2\nwidth 3\nmap\n...\n.x.\n").find("test.map:6: unknown cell symbol 'x'"),
            std::string::npos);
  EXPECT_NE(message_of("type octile\nheight 2\nwidth 3\nmap\n...\n..\n").find("test.map:6: a row of 2 cells"),
            std::string::npos);
  EXPECT_NE(message_of("type octile\nheight 3\nwidth 3\nmap\n...\n").find("has 1 rows"), std::string::npos);
  EXPECT_NE(message_of("type octile\nwidth 3\n").find("expected 'height N'"), std::string::npos);
  EXPECT_NE(message_of("hello\n").find("not a MovingAI map"), std::string::npos);
  EXPECT_NE(message_of("type octile\nheight 1\nwidth 2\nmap\n@@\n").find("no free cell"), std::string::npos);
}

TEST(HeadingDistances, CountForwardMovesAndQuarterTurns) {
  // A corridor of four cells and one cell below its east end.
  const GridMap map = parse("type octile\nheight 2\nwidth 4\nmap\n....\n@@@.\n");
  HeadingDistances d(map);
  EXPECT_EQ(d.to(3, 0, 0), 3);  // facing east: three forward moves
  EXPECT_EQ(d.to(3, 0, 2), 5);  // facing west: two turns first
  EXPECT_EQ(d.to(3, 0, 1), 4);  // facing south: one turn
  EXPECT_EQ(d.to(7, 0, 0), 5);  // three forward, a turn south, one forward
  EXPECT_EQ(d.best(7, 3), 1);
  EXPECT_EQ(d.to(0, 4, 0), HeadingDistances::kUnreachable);  // a blocked cell
  EXPECT_EQ(d.goals_kept(), 3u);
}

}  // namespace
}  // namespace fleet::coordination
