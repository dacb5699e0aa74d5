#include "coordination/lifelong_run.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "common/errors.hpp"
#include "coordination/lorr_instance.hpp"

namespace fleet::coordination {
namespace {

namespace fs = std::filesystem;

/// An instance folder in the competition's layout, written for the test.
class InstanceFolder {
 public:
  InstanceFolder()
      : dir_(fs::temp_directory_path() /
             ("fleet_lorr_" + std::to_string(::getpid()) + "_" + std::to_string(count_++))) {
    fs::create_directories(dir_ / "maps");
    fs::create_directories(dir_ / "agents");
    fs::create_directories(dir_ / "tasks");
    write("maps/room.map", "type octile\nheight 4\nwidth 6\nmap\n......\n.@..@.\n......\n..@...\n");
    write("agents/room.agents", "3\n0\n5\n18\n");
    write("tasks/room.tasks", "6\n23\n12\n2\n21\n6\n3\n");
    instance(R"({"mapFile": "maps/room.map", "agentFile": "agents/room.agents", "teamSize": 3,
                 "taskFile": "tasks/room.tasks", "numTasksReveal": 1, "taskAssignmentStrategy": "roundrobin"})");
  }
  ~InstanceFolder() { fs::remove_all(dir_); }
  void write(const std::string& name, const std::string& text) const { std::ofstream(dir_ / name) << text; }
  void instance(const std::string& json) const { write("room.json", json); }
  std::string path() const { return (dir_ / "room.json").string(); }

 private:
  static inline int count_ = 0;
  fs::path dir_;
};

std::string load_error(const InstanceFolder& folder) {
  try {
    load_lorr_instance(folder.path());
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(LorrInstance, ReadsTheCompetitionsFiles) {
  InstanceFolder folder;
  const LorrInstance instance = load_lorr_instance(folder.path());
  EXPECT_EQ(instance.map.cols, 6);
  EXPECT_EQ(instance.starts, (std::vector<int>{0, 5, 18}));
  EXPECT_EQ(instance.tasks.size(), 6u);
  EXPECT_EQ(instance.tasks_revealed, 1);
}

TEST(LorrInstance, NamesTheFileAndKeyOfWhatIsWrong) {
  InstanceFolder folder;
  folder.instance(R"({"mapFile": "maps/room.map", "agentFile": "agents/room.agents", "teamSize": 3})");
  EXPECT_NE(load_error(folder).find("the key 'taskFile' is missing"), std::string::npos);
  folder.instance(R"({"mapFile": "maps/room.map", "agentFile": "agents/room.agents", "teamSize": 4,
                      "taskFile": "tasks/room.tasks"})");
  EXPECT_NE(load_error(folder).find("has 3 start locations for a teamSize of 4"), std::string::npos);
  folder.instance(R"({"mapFile": "maps/room.map", "agentFile": "agents/room.agents", "teamSize": 3,
                      "taskFile": "tasks/room.tasks", "taskAssignmentStrategy": "greedy"})");
  EXPECT_NE(load_error(folder).find("taskAssignmentStrategy 'greedy' is not supported"), std::string::npos);
  folder.instance(R"({"mapFile": "maps/room.map", "agentFile": "agents/room.agents", "teamSize": 3,
                      "taskFile": "tasks/room.tasks"})");
  folder.write("agents/room.agents", "3\n0\n7\n18\n");
  EXPECT_NE(load_error(folder).find("robot 1 at location 7 (row 1, column 1) is a blocked cell"), std::string::npos);
  folder.write("agents/room.agents", "3\n0\n0\n18\n");
  EXPECT_NE(load_error(folder).find("robot 1 starts on location 0, where an earlier robot starts"), std::string::npos);
  folder.write("agents/room.agents", "3\n0\n5\n");
  EXPECT_NE(load_error(folder).find("says 3 locations and ends after 2"), std::string::npos);
  folder.write("agents/room.agents", "3\n0\n5\n18\n");
  folder.write("tasks/room.tasks", "2\n23\n99\n");
  EXPECT_NE(load_error(folder).find("errand 1 at location 99 is off the 4 x 6 map"), std::string::npos);
  folder.write("room.json", "{not json");
  EXPECT_NE(load_error(folder).find("not JSON"), std::string::npos);
}

TEST(LifelongGridRun, RobotsFinishErrandsRoundRobinWithinTheCompetitionsRules) {
  InstanceFolder folder;
  const LorrInstance instance = load_lorr_instance(folder.path());
  LifelongSettings settings;
  settings.steps = 60;
  LifelongGridRun run(instance, settings);
  const LifelongResult& result = run.run();
  EXPECT_TRUE(result.errors.empty()) << result.errors.front();
  EXPECT_EQ(result.wait_cycles, 0);
  EXPECT_EQ(result.steps, 60);
  EXPECT_GE(result.finished, 10);
  // Robot 0's errands are task lines 0, 3, 6 (= 0 again), ...: round robin over the file.
  ASSERT_GE(result.events[0].size(), 3u);
  EXPECT_EQ(result.errands[0].cell, 23);
  EXPECT_FALSE(result.events[0][0].finished);
  for (const std::string& actions : result.actions) EXPECT_EQ(actions.size(), 60u);

  const auto doc = nlohmann::json::parse(lorr_output_json(instance, result));
  EXPECT_EQ(doc["actionModel"], "MAPF_T");
  EXPECT_EQ(doc["AllValid"], "Yes");
  EXPECT_EQ(doc["numTaskFinished"], result.finished);
  EXPECT_EQ(doc["Planner Paths"], doc["actualPaths"]);
  EXPECT_EQ(doc["start"][2], nlohmann::json::array({3, 0, "E"}));
  EXPECT_EQ(doc["actualPaths"][0].get<std::string>().size(), 60u * 2 - 1);
}

TEST(LifelongGridRun, DelayedRobotsHoldUpOnlyThoseOrderedBehindThem) {
  InstanceFolder folder;
  const LorrInstance instance = load_lorr_instance(folder.path());
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    LifelongSettings settings;
    settings.planner = seed % 2 == 0 ? GridPlanner::kCells : GridPlanner::kOperations;
    settings.steps = 200;
    settings.seed = seed;
    settings.delays = {0.2, 2, 8};
    LifelongGridRun run(instance, settings);
    const LifelongResult& result = run.run();
    EXPECT_TRUE(result.errors.empty()) << "seed " << seed << ": " << result.errors.front();
    EXPECT_EQ(result.wait_cycles, 0) << "seed " << seed;
    EXPECT_GT(result.delayed_robot_steps, 50) << "seed " << seed;
    EXPECT_GE(result.finished, 10) << "seed " << seed;
  }
}

TEST(LifelongGridRun, EveryPlannerKeepsTheRulesWithEveryRobotOfARoomBusy) {
  // Nine robots in the 4 x 6 room's 20 free cells: most moves push someone.
  InstanceFolder folder;
  folder.write("agents/room.agents", "9\n0\n1\n2\n3\n5\n12\n13\n14\n15\n");
  folder.instance(R"({"mapFile": "maps/room.map", "agentFile": "agents/room.agents", "teamSize": 9,
                      "taskFile": "tasks/room.tasks", "numTasksReveal": 1, "taskAssignmentStrategy": "roundrobin"})");
  const LorrInstance instance = load_lorr_instance(folder.path());
  // The cell planner, the operations alone, and the operations with the window search.
  for (const int planner : {0, 1, 2}) {
    for (std::uint64_t seed = 1; seed <= 5; ++seed) {
      LifelongSettings settings;
      settings.steps = 300;
      settings.seed = seed;
      settings.planner = planner == 0 ? GridPlanner::kCells : GridPlanner::kOperations;
      if (planner == 1) settings.lns_window = 0;
      settings.delays = {seed % 2 == 0 ? 0.0 : 0.05, 1, 4};
      LifelongGridRun run(instance, settings);
      const LifelongResult& result = run.run();
      const std::string which = std::string(planner == 0   ? "cells"
                                            : planner == 1 ? "operations"
                                                           : "window search") +
                                ", seed " + std::to_string(seed);
      EXPECT_TRUE(result.errors.empty()) << which << ": " << result.errors.front();
      EXPECT_EQ(result.wait_cycles, 0) << which;
      EXPECT_GE(result.finished, 20) << which;
    }
  }
}

TEST(LifelongFigures, NearestRankPercentilesOfThePlanningTimes) {
  LifelongResult result;
  result.steps = 4;
  result.finished = 6;
  result.planning_s = {0.004, 0.001, 0.003, 0.002};
  const LifelongFigures f = figures_of(result);
  EXPECT_DOUBLE_EQ(f.throughput, 1.5);
  EXPECT_DOUBLE_EQ(f.planning_ms_p50, 2.0);
  EXPECT_DOUBLE_EQ(f.planning_ms_p99, 4.0);
  EXPECT_DOUBLE_EQ(f.planning_ms_max, 4.0);
}

}  // namespace
}  // namespace fleet::coordination
