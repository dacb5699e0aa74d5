// fleetctl fleets, traffic-eval and pick-eval's flags through the entry points fleetctl calls.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <sstream>

#include "cli/commands.hpp"
#include "common/args.hpp"
#include "common/paths.hpp"

using namespace fleet::cli;

namespace {

struct CommandRun {
  int code = -1;
  std::string out;
};

template <typename Command>
CommandRun run(Command command, std::vector<std::string> args, const std::string& config) {
  CommandArgs a;
  a.args = std::move(args);
  a.json = true;
  a.config_file = std::string(FLEET_SOURCE_DIR) + "/config/" + config;
  a.source_dir = FLEET_SOURCE_DIR;
  std::ostringstream out, err;
  CommandRun r;
  r.code = command(a, out, err);
  r.out = out.str();
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

TEST(TrafficEval, UnknownSiteAndPlacesAreBadInput) {
  EXPECT_THROW(run(traffic_eval_command, {"--site", "plant", "--against", "plantt"}, "sites/plant.yaml"),
               fleet::ArgError);
  EXPECT_THROW(run(traffic_eval_command, {"--site", "plant", "--places", "ZZ"}, "sites/plant.yaml"), fleet::ArgError);
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
