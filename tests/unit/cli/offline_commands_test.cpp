// fleetctl fleets, traffic-eval, pick-eval, mapf-eval and the evaluations' flags through the entry
// points fleetctl calls.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli/commands.hpp"
#include "common/args.hpp"
#include "common/paths.hpp"
#include "test_paths.hpp"

using namespace fleet::cli;

namespace {

struct CommandRun {
  int code = -1;
  std::string out;
  std::string err;
};

template <typename Command>
CommandRun run(Command command, std::vector<std::string> args, const std::string& config) {
  CommandArgs a;
  a.args = std::move(args);
  a.json = true;
  a.config_file = fleet::test::source_dir() + "/config/" + config;
  a.source_dir = fleet::test::source_dir();
  std::ostringstream out, err;
  CommandRun r;
  r.code = command(a, out, err);
  r.out = out.str();
  r.err = err.str();
  return r;
}

}  // namespace

TEST(FleetsCommand, ThePlantHasFourFleetsOfDifferentVehicles) {
  const auto r = run(fleets_command, {}, "sites/plant.yaml");
  ASSERT_EQ(r.code, 0);
  const auto doc = nlohmann::json::parse(r.out);
  ASSERT_EQ(doc["fleets"].size(), 4u);
  EXPECT_EQ(doc["fleets"][3]["fleet"], "pickers");
  EXPECT_EQ(doc["fleets"][3]["typeSpecification"]["agvKinematic"], "OMNI") << doc["fleets"][3];
  const auto& picker_actions = doc["fleets"][3]["protocolFeatures"]["agvActions"];
  ASSERT_EQ(picker_actions.size(), 2u) << doc["fleets"][3];
  EXPECT_EQ(picker_actions[0]["actionType"], "pickItem");
  EXPECT_EQ(picker_actions[1]["actionType"], "dropItem");
  EXPECT_EQ(doc["fleets"][2]["fleet"], "stackers");
  EXPECT_EQ(doc["fleets"][2]["typeSpecification"]["agvKinematic"], "THREEWHEEL") << doc["fleets"][2];
  EXPECT_EQ(doc["fleets"][0]["fleet"], "forklifts");
  EXPECT_EQ(doc["fleets"][1]["fleet"], "reach_trucks");
  EXPECT_LT(doc["fleets"][0]["physicalParameters"]["width"].get<double>(),
            doc["fleets"][1]["physicalParameters"]["width"].get<double>());
  EXPECT_GT(doc["fleets"][1]["loadSpecification"]["loadSets"][0]["maxLoadhandlingHeight"].get<double>(), 4.4);
}

TEST(TrafficEval, ComparesTheSameTripsOnTwoSitesWithoutCollisions) {
  const auto r =
      run(traffic_eval_command,
          {"--site", "plant", "--against", "plant_one_lane", "--robots", "4", "--duration", "300"}, "sites/plant.yaml");
  ASSERT_EQ(r.code, 0);
  const auto doc = nlohmann::json::parse(r.out);
  ASSERT_EQ(doc["runs"].size(), 2u);
  for (const auto& run : doc["runs"]) {
    EXPECT_EQ(run["collisions"], 0) << run;
    EXPECT_GT(run["trips"].get<int>(), 0) << run;
  }
  EXPECT_GT(doc["trips_ratio"].get<double>(), 0.0);
}

TEST(TrafficEval, ComparesTheManagerAndThePlacePlannerOnTheSameTrips) {
  const auto r = run(traffic_eval_command,
                     {"--site", "table_a", "--robots", "8", "--duration", "300", "--core", "both"}, "fleet.yaml");
  ASSERT_EQ(r.code, 0);
  const auto doc = nlohmann::json::parse(r.out);
  ASSERT_EQ(doc["runs"].size(), 2u);
  EXPECT_EQ(doc["runs"][0]["core"], "manager");
  EXPECT_EQ(doc["runs"][1]["core"], "pibt");
  for (const auto& run : doc["runs"]) {
    EXPECT_EQ(run["collisions"], 0) << run;
    EXPECT_EQ(run["deadlocks"], 0) << run;
    EXPECT_GT(run["trips"].get<int>(), 0) << run;
  }
  EXPECT_EQ(doc["runs"][1]["plan_conflicts"], 0);
  EXPECT_EQ(doc["runs"][1]["wait_cycles"], 0);
  EXPECT_GT(doc["pibt_over_manager"].get<double>(), 0.0);
}

/// The place planner's run on table_a, 8 robots, 300 s, with `more` flags.
nlohmann::json place_planner_run(std::vector<std::string> more) {
  std::vector<std::string> args{"--site", "table_a", "--robots", "8", "--duration", "300", "--core", "pibt"};
  args.insert(args.end(), more.begin(), more.end());
  const auto r = run(traffic_eval_command, args, "fleet.yaml");
  EXPECT_EQ(r.code, 0);
  return nlohmann::json::parse(r.out)["runs"][0];
}

TEST(TrafficEval, ThePlacePlannerDrivesTheOneWayCorridorsWhenAsked) {
  const auto run_doc = place_planner_run({"--lanes", "one-way"});
  EXPECT_EQ(run_doc["lanes"], "one-way");
  EXPECT_EQ(run_doc["collisions"], 0) << run_doc;
  EXPECT_EQ(run_doc["deadlocks"], 0) << run_doc;
  EXPECT_GT(run_doc["trips"].get<int>(), 0) << run_doc;
}

TEST(TrafficEval, DelayedMovesKeepThePlacePlannersRobotsApartAndOutOfWaitCycles) {
  const auto run_doc = place_planner_run({"--delay", "0.05,2,8"});
  EXPECT_GT(run_doc["delays"].get<int>(), 0) << run_doc;
  EXPECT_EQ(run_doc["collisions"], 0) << run_doc;
  EXPECT_EQ(run_doc["wait_cycles"], 0) << run_doc;
  EXPECT_EQ(run_doc["plan_conflicts"], 0) << run_doc;
  EXPECT_GT(run_doc["trips"].get<int>(), 0) << run_doc;
}

TEST(TrafficEval, UnknownSiteAndPlacesAreBadInput) {
  EXPECT_THROW(run(traffic_eval_command, {"--core", "rmf"}, "fleet.yaml"), fleet::ArgError);
  EXPECT_THROW(run(traffic_eval_command, {"--site", "plant", "--against", "plant_one_lane", "--core", "both"},
                   "sites/plant.yaml"),
               fleet::ArgError);
  EXPECT_THROW(run(traffic_eval_command, {"--site", "plant", "--against", "plantt"}, "sites/plant.yaml"),
               fleet::ArgError);
  EXPECT_THROW(run(traffic_eval_command, {"--site", "plant", "--places", "ZZ"}, "sites/plant.yaml"), fleet::ArgError);
  EXPECT_THROW(run(traffic_eval_command, {"--core", "pibt", "--delay", "2,1,3"}, "fleet.yaml"), fleet::ArgError);
  EXPECT_THROW(run(traffic_eval_command, {"--core", "both", "--delay", "0.1,1,3"}, "fleet.yaml"), fleet::ArgError);
  EXPECT_THROW(run(traffic_eval_command, {"--core", "pibt", "--lanes", "sideways"}, "fleet.yaml"), fleet::ArgError);
  EXPECT_THROW(run(traffic_eval_command, {"--core", "manager", "--lanes", "one-way"}, "fleet.yaml"), fleet::ArgError);
}

TEST(PickEval, AFlagItDoesNotKnowOrASeedThatIsNoNumberIsBadInput) {
  EXPECT_THROW(run(pick_eval_command, {"--seed", "one"}, "sites/plant.yaml"), fleet::ArgError);
  EXPECT_THROW(run(pick_eval_command, {"--seed"}, "sites/plant.yaml"), fleet::ArgError);
  EXPECT_THROW(run(pick_eval_command, {"--runs", "3"}, "sites/plant.yaml"), fleet::ArgError);
  EXPECT_THROW(run(pick_eval_command, {"extra"}, "sites/plant.yaml"), fleet::ArgError);
  EXPECT_EQ(run(pick_eval_command, {"--help"}, "sites/plant.yaml").code, 0);
  EXPECT_THROW(run(pick_eval_command, {"--drop"}, "sites/plant.yaml"), fleet::ArgError);
}

TEST(PickEval, AnUnknownDropPlaceIsBadInputBeforeAnySectionRuns) {
  const CommandRun r = run(pick_eval_command, {"--drop", "NOWHERE"}, "sites/plant.yaml");
  EXPECT_EQ(r.code, 2);
  EXPECT_TRUE(r.out.empty()) << r.out;
}

TEST(SiteConfig, ASiteWithFleetsOfItsOwnBringsThemUnlessAConfigIsGiven) {
  EXPECT_TRUE(fleet::config_path_for(std::nullopt, "plant").ends_with("/config/sites/plant.yaml"));
  EXPECT_EQ(fleet::config_path_for(std::nullopt, "table_a"), fleet::default_config_path());
  EXPECT_EQ(fleet::config_path_for(std::nullopt, std::nullopt), fleet::default_config_path());
  EXPECT_EQ(fleet::config_path_for(std::string("mine.yaml"), "plant"), "mine.yaml");
  fleet::Args args(std::vector<std::string>{"demo", "--site=plant", "--agents", "2"});
  EXPECT_EQ(args.peek("site"), "plant");
  EXPECT_EQ(args.peek("agents"), "2");
  EXPECT_EQ(args.remaining().size(), 4u);  // peeking takes nothing away
}

namespace {

/// A League of Robot Runners instance of a small room, in a folder of its own.
std::filesystem::path write_room_instance(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / name;
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "room.map") << "type octile\nheight 3\nwidth 5\nmap\n.....\n.@.@.\n.....\n";
  std::ofstream(dir / "room.agents") << "2\n0\n14\n";
  std::ofstream(dir / "room.tasks") << "4\n14\n0\n2\n12\n";
  std::ofstream(dir / "room.json") << R"({"mapFile": "room.map", "agentFile": "room.agents", "teamSize": 2,
      "taskFile": "room.tasks", "numTasksReveal": 1, "taskAssignmentStrategy": "roundrobin"})";
  return dir;
}

}  // namespace

TEST(MapfEval, RunsAnInstanceAndWritesTheCompetitionsOutputFile) {
  const auto dir = write_room_instance("fleet_mapf_eval_test");
  const std::string output = (dir / "out.json").string();
  const auto r = run(mapf_eval_command,
                     {"--instance", (dir / "room.json").string(), "--steps", "40", "--output", output}, "fleet.yaml");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto summary = nlohmann::json::parse(r.out.substr(r.out.rfind('{')));
  EXPECT_EQ(summary["robots"], 2);
  EXPECT_EQ(summary["steps"], 40);
  EXPECT_TRUE(summary["valid"].get<bool>());
  EXPECT_GE(summary["finished"].get<int>(), 4);
  std::ifstream in(output);
  const auto doc = nlohmann::json::parse(in);
  EXPECT_EQ(doc["numTaskFinished"], summary["finished"]);
  EXPECT_EQ(doc["Planner Paths"].size(), 2u);
  std::filesystem::remove_all(dir);
}

TEST(MapfEval, BadFlagsAndFilesAreBadInput) {
  const auto dir = write_room_instance("fleet_mapf_eval_bad_test");
  const std::string instance = (dir / "room.json").string();
  EXPECT_THROW(run(mapf_eval_command, {"--instance", instance, "--delay", "0.5,3"}, "fleet.yaml"), fleet::ArgError);
  EXPECT_THROW(run(mapf_eval_command, {"--instance", instance, "--delay", "2,1,3"}, "fleet.yaml"), fleet::ArgError);
  EXPECT_THROW(run(mapf_eval_command, {"--steps", "10"}, "fleet.yaml"), fleet::ArgError);
  EXPECT_THROW(run(mapf_eval_command, {"--instance", (dir / "none.json").string()}, "fleet.yaml"), fleet::InputError);
  std::filesystem::remove_all(dir);
}

TEST(OfflineEvals, BadFlagsAreBadInputNamingTheFlagAndDashHShowsTheUsage) {
  struct Case {
    int (*command)(const CommandArgs&, std::ostream&, std::ostream&);
    std::vector<std::string> args;
    std::string said;
  };
  const std::vector<Case> cases{
      {dock_eval_command, {"--runs", "0"}, "flag --runs: 0 is outside 1 .. 10000"},
      {dock_eval_command, {"--pose-noise", "3"}, "flag --pose-noise: '3' must be CM,DEG"},
      {dock_eval_command, {"--bogus"}, "unknown flag '--bogus'"},
      {loc_eval_command, {"--trajectory", "spiral"}, "flag --trajectory: 'spiral' is not one of square"},
      {loc_eval_command, {"--nlos", "2"}, "flag --nlos: 2 is outside"},
      {loc_eval_command, {"--seed"}, "--seed"},
      {plan_eval_command, {}, "--site is required"},
      {plan_eval_command, {"--site", "table_a", "--queries", "many"}, "flag --queries: 'many' is not an integer"},
      {ctrl_eval_command, {"--speed", "5"}, "flag --speed: 5 is outside"},
  };
  for (const Case& c : cases) {
    const auto r = run(c.command, c.args, "fleet.yaml");
    EXPECT_EQ(r.code, kExitBadInput) << c.said;
    EXPECT_NE(r.err.find(c.said), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("usage: fleetctl"), std::string::npos) << r.err;
  }
  for (auto* command : {dock_eval_command, loc_eval_command, plan_eval_command, ctrl_eval_command}) {
    const auto r = run(command, {"-h"}, "fleet.yaml");
    EXPECT_EQ(r.code, kExitOk);
    EXPECT_EQ(r.out.rfind("usage: fleetctl", 0), 0u) << r.out;
  }
}
