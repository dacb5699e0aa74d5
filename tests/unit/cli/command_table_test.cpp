#include "cli/command_table.hpp"

#include <gtest/gtest.h>

using namespace fleet::cli;

TEST(CommandTable, HelpListsEveryCommandAndTheExitCodes) {
  const std::string help = help_text();
  for (const auto& spec : command_table()) {
    EXPECT_NE(help.find("  " + usage_line(spec)), std::string::npos) << usage_line(spec);
  }
  for (const char* code : {"0  ok", "1  the operation ran and failed", "2  bad input", "3  no fleet-server"}) {
    EXPECT_NE(help.find(code), std::string::npos) << code;
  }
}

TEST(CommandTable, CompletionScriptKnowsCommandsSubcommandsAndFlags) {
  const std::string script = bash_completion_script();
  EXPECT_NE(script.find("complete -F _fleetctl fleetctl"), std::string::npos);
  for (const auto& name : command_names()) EXPECT_NE(script.find("    " + name + ")"), std::string::npos) << name;
  for (const auto& spec : command_table()) {
    for (const auto& flag : spec.flags) EXPECT_NE(script.find(flag.name), std::string::npos) << flag.name;
  }
}

TEST(CommandTable, FlagsTakeAValueEverywhereOrNowhere) {
  // The completion treats a flag name as taking a value for every command alike.
  std::map<std::string, bool> takes_value;
  for (const auto& spec : command_table()) {
    for (const auto& flag : spec.flags) {
      const bool valued = flag.kind != FlagSpec::Kind::kSwitch;
      const auto [it, inserted] = takes_value.emplace(flag.name, valued);
      EXPECT_EQ(it->second, valued) << flag.name;
    }
  }
}
