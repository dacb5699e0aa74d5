#include "robot/neighbour_memory.hpp"

#include <gtest/gtest.h>

using fleet::robot::Neighbour;
using fleet::robot::NeighbourMemory;

namespace {

Neighbour at(const std::string& id, double x) {
  return {id, {x, 0.5, 0.0}, {}, 0.0, 0.1};
}

std::vector<std::string> ids(const std::vector<Neighbour>& ns) {
  std::vector<std::string> out;
  for (const auto& n : ns) out.push_back(n.robot_id);
  return out;
}

TEST(NeighbourMemory, ARobotMissingFromAViewStaysWhereItWasLastListed) {
  NeighbourMemory memory(20.0);
  memory.update({at("fl2", 1.0), at("fl4", 0.8)}, 100.0);
  // A restarted server's first view lists only the robots heard from so far.
  memory.update({at("fl2", 1.1)}, 101.0);
  const auto now = memory.current();
  ASSERT_EQ(ids(now), (std::vector<std::string>{"fl2", "fl4"}));
  EXPECT_DOUBLE_EQ(now[0].pose.x, 1.1);
  EXPECT_DOUBLE_EQ(now[1].pose.x, 0.8);  // as last listed
  memory.update({at("fl2", 1.2), at("fl4", 0.9)}, 102.0);
  EXPECT_DOUBLE_EQ(memory.current()[1].pose.x, 0.9);
}

TEST(NeighbourMemory, ARobotLeftOutOfViewsForLongIsForgotten) {
  NeighbourMemory memory(20.0);
  memory.update({at("fl2", 1.0), at("fl4", 0.8)}, 100.0);
  memory.update({at("fl2", 1.0)}, 119.0);
  EXPECT_EQ(memory.current().size(), 2u);
  memory.update({at("fl2", 1.0)}, 121.0);
  EXPECT_EQ(ids(memory.current()), (std::vector<std::string>{"fl2"}));
}

}  // namespace

namespace {

TEST(NeighbourMemory, ARobotThatLeftTheRadiusOfACompleteViewIsForgottenAtOnce) {
  NeighbourMemory memory(20.0);
  memory.update_within({at("fl2", 3.0), at("fl4", 9.5)}, 100.0, {0.0, 0.5}, 10.0);
  // fl2 drove off beyond the radius: a complete view no longer lists it, and where it was last
  // listed (3 m away, well inside) it is not any more.
  memory.update_within({at("fl4", 9.6)}, 100.05, {0.0, 0.5}, 10.0);
  EXPECT_EQ(ids(memory.current()), (std::vector<std::string>{"fl4"}));
  // fl4 left across the edge: its last pose was within a metre of it, so it is kept a while
  // (it may have been listed from a pose of ours a step older).
  memory.update_within({}, 100.1, {0.0, 0.5}, 10.0);
  EXPECT_EQ(ids(memory.current()), (std::vector<std::string>{"fl4"}));
  memory.update_within({}, 121.0, {0.0, 0.5}, 10.0);
  EXPECT_TRUE(memory.current().empty());
}

}  // namespace
