#include "config/fleet_config.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "config/schema.hpp"
#include "test_paths.hpp"

using namespace fleet::config;

namespace {
const char* kFleets = R"(
fleets:
  - id: forklifts
    robot_type: forklift
    profile: {footprint: {length: 0.25, width: 0.16}}
    robots:
      - {id: fl1, home: H1}
      - {id: fl2, home: H2}
)";

std::string message_of(const std::string& yaml) {
  try {
    parse_fleet_config(yaml, "test.yaml");
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(FleetConfig, ShippedDefaultsLoad) {
  const FleetConfig config = load_fleet_config(fleet::test::source_path("/config/fleet.yaml"));
  ASSERT_FALSE(config.fleets.empty());
  EXPECT_EQ(config.fleets[0].robot_type, "forklift");
  EXPECT_EQ(config.settings.get_string("server.dispatch_policy"), "ascending-id");
  EXPECT_TRUE(config.find_robot("fl1").has_value());
}

TEST(FleetConfig, ReadsNestedKeysAndFleets) {
  const FleetConfig config =
      parse_fleet_config(std::string("server:\n  dispatch_policy: optimal\ntime_scale: 5\n") + kFleets, "t");
  EXPECT_EQ(config.settings.get_string("server.dispatch_policy"), "optimal");
  EXPECT_DOUBLE_EQ(config.settings.get_double("time_scale"), 5.0);
  EXPECT_EQ(config.all_robots().size(), 2u);
  EXPECT_DOUBLE_EQ(config.fleets[0].footprint.width, 0.16);
}

TEST(FleetConfig, UnknownKeyNamesKeyAndFile) {
  const std::string msg = message_of(std::string("server:\n  dispatch_polcy: optimal\n") + kFleets);
  EXPECT_NE(msg.find("test.yaml"), std::string::npos) << msg;
  EXPECT_NE(msg.find("server.dispatch_polcy"), std::string::npos) << msg;
}

TEST(FleetConfig, OutOfRangeAndWrongChoiceAreRefused) {
  EXPECT_NE(message_of(std::string("time_scale: 1000\n") + kFleets).find("time_scale"), std::string::npos);
  EXPECT_NE(message_of(std::string("time_scale: nan\n") + kFleets).find("not a finite number"), std::string::npos);
  EXPECT_NE(message_of(std::string("server: {dispatch_policy: fastest}\n") + kFleets).find("ascending-id"),
            std::string::npos);
}

TEST(FleetConfig, DuplicateRobotIdsAreRefused) {
  const std::string msg = message_of(R"(
fleets:
  - id: a
    robot_type: forklift
    profile: {footprint: {length: 0.25, width: 0.16}}
    robots: [{id: fl1, home: H1}, {id: fl1, home: H2}]
)");
  EXPECT_NE(msg.find("duplicate robot id 'fl1'"), std::string::npos) << msg;
}

TEST(Schema, EveryKeyHasADescriptionAndAValidDefault) {
  Settings settings;
  for (const KeySpec& spec : schema()) {
    EXPECT_FALSE(spec.description.empty()) << spec.key;
    EXPECT_NO_THROW(settings.set(spec.key, spec.default_value, "schema")) << spec.key;
  }
  EXPECT_NE(schema_markdown().find("server.dispatch_policy"), std::string::npos);
}

TEST(FleetConfig, CommonFlagsOverrideTheFileAndAreChecked) {
  FleetConfig config = load_fleet_config(fleet::test::source_path("/config/fleet.yaml"));
  fleet::Args args({"--domain", "42", "--time-scale=5", "--site", "table_b", "--id", "fl1"});
  apply_common_flags(args, config);
  EXPECT_EQ(config.settings.get_int("dds.domain"), 42);
  EXPECT_DOUBLE_EQ(config.settings.get_double("time_scale"), 5.0);
  EXPECT_EQ(config.settings.get_string("site"), "table_b");
  EXPECT_EQ(args.remaining(), (std::vector<std::string>{"--id", "fl1"}));  // other flags are left alone
  fleet::Args bad({"--seed", "-3"});
  try {
    apply_common_flags(bad, config);
    FAIL() << "a negative seed was accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("--seed"), std::string::npos) << e.what();
  }
}

// docs/configuration.md is what `fleetctl config keys --markdown` prints; a key added, removed or
// changed in the schema without re-making the page fails here.
TEST(ConfigurationPage, CommittedPageMatchesTheSchema) {
  const std::string path = fleet::test::source_path("/docs/configuration.md");
  std::ifstream file(path);
  ASSERT_TRUE(file) << path << " is missing: build/bin/fleetctl config keys --markdown > docs/configuration.md";
  std::stringstream committed;
  committed << file.rdbuf();
  EXPECT_EQ(committed.str(), fleet::config::configuration_page())
      << path << " is stale: re-make it with build/bin/fleetctl config keys --markdown > docs/configuration.md";
}

TEST(ConfigurationPage, EveryKeyHasARowUnderItsSection) {
  const std::string page = fleet::config::configuration_page();
  for (const auto& spec : fleet::config::schema()) {
    EXPECT_NE(page.find("| `" + spec.key + "` |"), std::string::npos) << spec.key;
  }
  EXPECT_LT(page.find("## Server"), page.find("| `server.dispatch_policy` |"));
  EXPECT_LT(page.find("## Traffic control"), page.find("| `traffic.enabled` |"));
  EXPECT_NE(page.find("| `seed` | 1 |  | 0 .. 2147483647 |"), std::string::npos) << "integer ranges print whole";
}

namespace {
const char* kCountedAndListed = R"(
fleets:
  - id: forklifts
    robot_type: forklift
    robots: {count: 3, id: "fk{n}"}
  - id: trucks
    robot_type: forklift
    robots:
      - {id: rt1, home: P2}
)";
}  // namespace

TEST(FleetConfig, RobotsByCountAreNamedByThePattern) {
  const FleetConfig config = parse_fleet_config(kCountedAndListed, "t");
  ASSERT_EQ(config.fleets[0].robots.size(), 3u);
  EXPECT_EQ(config.fleets[0].robots[0].id, "fk1");
  EXPECT_EQ(config.fleets[0].robots[2].id, "fk3");
  EXPECT_TRUE(config.fleets[0].robots[1].home.empty());
}

TEST(FleetConfig, RobotsByCountTakeTheSiteHomesNoListedRobotNames) {
  FleetConfig config = parse_fleet_config(kCountedAndListed, "t");
  assign_homes(config, {"P1", "P2", "P3", "P4", "P5"}, "yard");
  EXPECT_EQ(config.find_robot("fk1")->second->home, "P1");
  EXPECT_EQ(config.find_robot("fk2")->second->home, "P3");  // P2 is rt1's
  EXPECT_EQ(config.find_robot("fk3")->second->home, "P4");
  EXPECT_EQ(config.find_robot("rt1")->second->home, "P2");
}

TEST(FleetConfig, TooFewHomesForTheCountNameTheSite) {
  FleetConfig config = parse_fleet_config(kCountedAndListed, "fleet.yaml");
  try {
    assign_homes(config, {"P1", "P2", "P3"}, "yard");
    FAIL() << "three homes cannot hold four robots";
  } catch (const ConfigError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("fleet.yaml"), std::string::npos) << msg;
    EXPECT_NE(msg.find("'yard' has 2 homes left"), std::string::npos) << msg;
  }
}

TEST(FleetConfig, BadCountOrPatternIsRefused) {
  const std::string head = "fleets:\n  - id: f\n    robot_type: forklift\n    robots: ";
  EXPECT_NE(message_of(head + "{count: 2, id: fk}\n").find("must hold {n}"), std::string::npos);
  EXPECT_NE(message_of(head + "{count: 2.5, id: \"fk{n}\"}\n").find("whole number"), std::string::npos);
  EXPECT_NE(message_of(head + "{count: 0, id: \"fk{n}\"}\n").find("must be positive"), std::string::npos);
  EXPECT_NE(message_of(head + "{count: 2, id: \"fk{n}\", home: H1}\n").find("home"), std::string::npos);
  EXPECT_NE(message_of(head + "{count: 2, id: \"x{n}\"}\n  - id: g\n    robot_type: forklift\n    robots: "
                              "[{id: x2, home: H1}]\n")
                .find("duplicate robot id 'x2'"),
            std::string::npos);
}

TEST(FleetConfig, AVda5050FleetNamesHowItsVehiclesAreReachedAndEachSerialDefaultsToTheId) {
  const FleetConfig config = parse_fleet_config(R"(
fleets:
  - id: visitors
    robot_type: vda5050
    vda5050: {manufacturer: Sim}
    robots: [{id: v1, home: H1, serial_number: agv-1}, {id: v2, home: H2}]
  - id: more
    robot_type: vda5050
    vda5050: {manufacturer: Acme, interface_name: plant, version: 2.1.0}
    robots: {count: 2, id: "m{n}"}
)",
                                                "t");
  ASSERT_TRUE(config.fleets[0].vda5050);
  EXPECT_EQ(config.fleets[0].vda5050->interface_name, "uagv");
  EXPECT_EQ(config.fleets[0].vda5050->version, "2.0.0");
  EXPECT_EQ(config.fleets[0].robots[0].serial_number, "agv-1");
  EXPECT_EQ(config.fleets[0].robots[1].serial_number, "v2");
  EXPECT_EQ(config.fleets[1].robots[1].serial_number, "m2") << "robots declared by count too";
  EXPECT_EQ(config.fleets[1].vda5050->version, "2.1.0");
}

TEST(FleetConfig, Vda5050KeysAreCheckedAndOnlyForVda5050Fleets) {
  const auto fleet = [](const std::string& body) {
    return "fleets:\n  - id: f\n" + body + "    robots: [{id: r1, home: H1}]\n";
  };
  EXPECT_NE(message_of(fleet("    robot_type: vda5050\n")).find("'fleets[0].vda5050' must be a map"),
            std::string::npos);
  EXPECT_NE(message_of(fleet("    robot_type: vda5050\n    vda5050: {manufacturer: Sim, version: 3.0.0}\n"))
                .find("'3.0.0' is not a VDA 5050 version Fleet speaks (2.0.0, 2.1.0)"),
            std::string::npos);
  EXPECT_NE(message_of(fleet("    robot_type: vda5050\n    vda5050: {manufacturer: S/m}\n")).find("reserve"),
            std::string::npos);
  EXPECT_NE(message_of(fleet("    robot_type: forklift\n    vda5050: {manufacturer: Sim}\n"))
                .find("'fleets[0].vda5050' is only for robot type vda5050"),
            std::string::npos);
}
