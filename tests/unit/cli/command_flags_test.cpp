#include "cli/command_flags.hpp"

#include <gtest/gtest.h>

#include <sstream>
#include <stdexcept>

#include "common/args.hpp"

using namespace fleet::cli;

namespace {

std::string error_of(std::string_view command, std::string_view subcommand, const std::vector<std::string>& args) {
  try {
    CommandFlags(command, subcommand, args);
  } catch (const fleet::ArgError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(CommandFlags, EveryTypedFlagOfTheTableHasARangeAndEveryChoiceFlagItsChoices) {
  for (const auto& spec : command_table()) {
    for (const auto& flag : spec.flags) {
      SCOPED_TRACE(usage_line(spec) + " " + flag.name);
      if (flag.type == FlagSpec::Type::kInteger || flag.type == FlagSpec::Type::kNumber) {
        EXPECT_LT(flag.min, flag.max);
        EXPECT_NE(flag.kind, FlagSpec::Kind::kSwitch);
      }
      EXPECT_EQ(flag.kind == FlagSpec::Kind::kChoice, !flag.choices.empty());
    }
  }
}

TEST(CommandFlags, ParsesTypedValuesInBothSpellingsAndKeepsPositionals) {
  const CommandFlags flags(
      "soak", "", {"--agents", "8", "--time-scale=2.5", "--seed", "3", "--set", "a=1", "--set", "b=2", "--verbose"});
  EXPECT_EQ(flags.integer("agents"), 8);
  EXPECT_EQ(flags.number("time-scale"), 2.5);
  EXPECT_EQ(flags.integer("seed"), 3);
  EXPECT_EQ(flags.values("set"), (std::vector<std::string>{"a=1", "b=2"}));
  EXPECT_TRUE(flags.flag("verbose"));
  EXPECT_FALSE(flags.integer("http-port").has_value());
  const CommandFlags map_check("map", "check", {"table_a", "--strict", "plant"});
  EXPECT_EQ(map_check.positionals(), (std::vector<std::string>{"table_a", "plant"}));
  const CommandFlags negative("map", "render", {"x", "-o", "x.svg", "--since", "-5"});
  EXPECT_EQ(negative.number("since"), -5.0) << "a negative number is a value, not a flag";
}

TEST(CommandFlags, BadFlagsAreArgErrorsNamingTheFlagTheValueAndWhatTheCommandTakes) {
  EXPECT_EQ(error_of("dock-eval", "", {"--rusn", "3"}),
            "unknown flag '--rusn' for dock-eval; it takes --runs, --seed, --pose-noise, --no-sweeps, --plot");
  EXPECT_EQ(error_of("dock-eval", "", {"--runs", "0"}), "flag --runs: 0 is outside 1 .. 10000");
  EXPECT_EQ(error_of("dock-eval", "", {"--runs", "many"}), "flag --runs: 'many' is not an integer");
  EXPECT_EQ(error_of("dock-eval", "", {"--runs"}), "flag --runs needs a value (N)");
  EXPECT_EQ(error_of("dock-eval", "", {"--seed", "-1"}), "flag --seed: '-1' is not a non-negative integer");
  EXPECT_EQ(error_of("soak", "", {"--traffic", "maybe"}), "flag --traffic: 'maybe' is not one of on, off");
  EXPECT_EQ(error_of("soak", "", {"--verbose=yes"}), "flag --verbose takes no value");
  EXPECT_EQ(error_of("order", "add", {"--priority", "5000"}), "flag --priority: 5000 is outside -1000 .. 1000");
  EXPECT_EQ(error_of("stats", "", {"--all"}), "unknown flag '--all' for stats (it takes none)");
  EXPECT_EQ(error_of("load", "", {"--duration", "nan"}), "flag --duration: 'nan' is not a number");
  EXPECT_EQ(error_of("dock-eval", "", {"extra"}), "unexpected argument 'extra'") << "dock-eval takes no argument";
  EXPECT_EQ(error_of("map", "check", {"table_a", "plant"}), "") << "map check takes sites";
}

TEST(CommandFlags, ReadingAFlagTheTableDoesNotDeclareIsAProgrammingError) {
  const CommandFlags flags("dock-eval", "", {});
  EXPECT_THROW((void)flags.value("sites"), std::logic_error);
  EXPECT_THROW((void)flags.number("runs"), std::logic_error) << "declared as an integer";
  EXPECT_FALSE(flags.integer("runs").has_value());
}

TEST(CommandFlags, DashHAsksForTheUsageWithTheSummary) {
  const CommandFlags flags("map", "render", {"-h"});
  EXPECT_TRUE(flags.asks_for_usage());
  EXPECT_EQ(flags.usage().rfind("usage: fleetctl map render SITE.yaml -o FILE.svg", 0), 0u) << flags.usage();
  EXPECT_NE(flags.usage().find("an SVG picture of a site"), std::string::npos) << flags.usage();
  std::ostringstream err;
  EXPECT_FALSE(flags_or_report("map", "sample", {"--step", "x"}, err).has_value());
  EXPECT_EQ(err.str().rfind("map sample: flag --step: 'x' is not a number\nusage: fleetctl map sample", 0), 0u)
      << err.str();
}
