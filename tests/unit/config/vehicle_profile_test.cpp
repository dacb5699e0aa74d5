#include <gtest/gtest.h>

#include "config/fleet_config.hpp"
#include "vehicle/factsheet.hpp"
#include "vehicle/vehicle_types.hpp"

using namespace fleet;
using config::ConfigError;
using config::parse_fleet_config;

namespace {

std::string fleet_with(const std::string& type, const std::string& profile) {
  return "fleets:\n  - id: f\n    robot_type: " + type + "\n" + (profile.empty() ? "" : "    profile:\n" + profile) +
         "    robots: [{id: r1, home: H1}]\n";
}

std::string message_of(const std::string& yaml) {
  try {
    parse_fleet_config(yaml, "plant.yaml");
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(VehicleProfile, OmittedProfileIsTheRobotTypesOwnVehicle) {
  const auto config = parse_fleet_config(fleet_with("forklift", ""), "t");
  const auto& profile = config.fleets[0].profile;
  EXPECT_EQ(profile.kinematics, vehicle::Kinematics::kOmni);
  EXPECT_TRUE(profile.can("pick"));
  EXPECT_DOUBLE_EQ(config.fleets[0].footprint.length, 0.25);
  EXPECT_DOUBLE_EQ(config.fleets[0].footprint.width, 0.16);
}

TEST(VehicleProfile, PolygonFootprintIsKeptCounterClockwiseAndItsExtentCoversIt) {
  // An L-shaped body given clockwise, origin off-centre towards the front.
  const auto config = parse_fleet_config(
      fleet_with("forklift",
                 R"(      footprint: [[0.9, 0.4], [0.9, -0.4], [-0.7, -0.4], [-0.7, 0.1], [-0.2, 0.1], [-0.2, 0.4]]
      kinematics: {type: tricycle, wheelbase: 1.2, max_steering_angle: 1.5708}
      max_speed: 1.2
      load: {type: pallet, max_mass: 1000, lift_height: 4.5}
      actions: [pick, drop]
)"),
      "t");
  const auto& fleet = config.fleets[0];
  EXPECT_GT(geometry::signed_area(fleet.profile.footprint), 0.0);
  EXPECT_DOUBLE_EQ(fleet.footprint.length, 1.8);  // twice the larger half-length
  EXPECT_DOUBLE_EQ(fleet.footprint.width, 0.8);
  EXPECT_EQ(fleet.profile.kinematics, vehicle::Kinematics::kTricycle);
  EXPECT_DOUBLE_EQ(fleet.profile.load.lift_height, 4.5);
  EXPECT_FALSE(fleet.profile.can("finePositioning"));
}

TEST(VehicleProfile, UnknownRobotTypeNamesTheKeyAndTheKnownTypes) {
  const std::string msg = message_of(fleet_with("hovercraft", ""));
  EXPECT_NE(msg.find("plant.yaml:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("fleets[0].robot_type"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'hovercraft' is not a known robot type (forklift"), std::string::npos) << msg;
}

TEST(VehicleProfile, SelfCrossingFootprintIsRefused) {
  const std::string msg = message_of(fleet_with("forklift", "      footprint: [[1, 1], [-1, -1], [1, -1], [-1, 1]]\n"));
  EXPECT_NE(msg.find("fleets[0].profile.footprint' is not a simple polygon"), std::string::npos) << msg;
  EXPECT_NE(message_of(fleet_with("forklift", "      footprint: [[1, 1], [2, 2]]\n")).find("not a simple polygon"),
            std::string::npos);
  EXPECT_NE(message_of(fleet_with("forklift", "      footprint: [[1, 0], [2, 0], [3, 0]]\n")).find("not a simple"),
            std::string::npos);
}

TEST(VehicleProfile, FootprintMustHoldTheBodyOrigin) {
  const std::string msg = message_of(fleet_with("forklift", "      footprint: [[1, 1], [2, 1], [2, 2], [1, 2]]\n"));
  EXPECT_NE(msg.find("profile.footprint': the body origin"), std::string::npos) << msg;
}

TEST(VehicleProfile, ActionTheRobotTypeCannotPerformIsRefused) {
  const std::string msg = message_of(fleet_with("forklift", "      actions: [pick, pickItem]\n"));
  EXPECT_NE(msg.find("fleets[0].profile.actions': a forklift cannot perform 'pickItem'"), std::string::npos) << msg;
}

TEST(VehicleProfile, TricycleNeedsAWheelbaseAndKinematicsMustBeKnown) {
  EXPECT_NE(message_of(fleet_with("forklift", "      kinematics: tricycle\n")).find("kinematics.wheelbase"),
            std::string::npos);
  EXPECT_NE(message_of(fleet_with("forklift", "      kinematics: hover\n")).find("'hover' is not a kinematics"),
            std::string::npos);
}

TEST(VehicleProfile, TricycleRearAxleLiesWithinTheFootprint) {
  const auto stacker = parse_fleet_config(fleet_with("stacker", ""), "t");
  EXPECT_DOUBLE_EQ(stacker.fleets[0].profile.rear_axle_x, -0.75);
  const std::string outside = message_of(fleet_with(
      "stacker", "      kinematics: {type: tricycle, wheelbase: 1.3, max_steering_angle: 1.5, rear_axle_x: -2}\n"));
  EXPECT_NE(outside.find("kinematics.rear_axle_x"), std::string::npos) << outside;
  const std::string word = message_of(fleet_with(
      "stacker", "      kinematics: {type: tricycle, wheelbase: 1.3, max_steering_angle: 1.5, rear_axle_x: back}\n"));
  EXPECT_NE(word.find("rear_axle_x': 'back' is not a number"), std::string::npos) << word;
}

TEST(VehicleProfile, FootprintBesideTheProfileSaysWhereItBelongs) {
  const std::string msg = message_of(
      "fleets:\n  - id: f\n    robot_type: forklift\n    footprint: {length: 1, width: 1}\n    robots: [{id: r, "
      "home: H1}]\n");
  EXPECT_NE(msg.find("'fleets[0].profile.footprint'"), std::string::npos) << msg;
}

TEST(Factsheet, SpeaksVda5050) {
  const auto config = parse_fleet_config(fleet_with("forklift", "      max_speed: 1.5\n"), "t");
  const auto sheet = vehicle::factsheet("f", "forklift", config.fleets[0].profile, {"r1"});
  EXPECT_EQ(sheet["typeSpecification"]["agvKinematic"], "OMNI");
  EXPECT_DOUBLE_EQ(sheet["physicalParameters"]["speedMax"].get<double>(), 1.5);
  EXPECT_DOUBLE_EQ(sheet["physicalParameters"]["length"].get<double>(), 0.25);
  EXPECT_EQ(sheet["protocolFeatures"]["agvActions"][0]["actionType"], "pick");
  EXPECT_EQ(sheet["agvGeometry"]["envelopes2d"][0]["polyPoints"].size(), 4u);
  EXPECT_EQ(sheet["robots"][0], "r1");
}
