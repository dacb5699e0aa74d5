// Every fleetctl command line the README and docs/ show names a command fleetctl has, with flags
// that command (or fleetctl itself) takes: the docs cannot drift from the command table.

#include <gtest/gtest.h>

#include <cctype>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "cli/command_table.hpp"
#include "test_paths.hpp"

using namespace fleet::cli;

namespace {

std::string read(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

/// The code of a Markdown page: fenced blocks line by line (continued lines joined) and inline
/// code spans.
std::vector<std::string> code_of(const std::string& page) {
  std::vector<std::string> code;
  std::istringstream lines(page);
  bool fenced = false;
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("```", 0) == 0) {
      fenced = !fenced;
      continue;
    }
    if (fenced) {
      // A shell line continued with a backslash is one command.
      if (!code.empty() && !code.back().empty() && code.back().back() == '\\') {
        code.back().back() = ' ';
        code.back() += line;
      } else {
        code.push_back(line);
      }
      continue;
    }
    for (std::size_t open = line.find('`'); open != std::string::npos; open = line.find('`', open + 1)) {
      const std::size_t close = line.find('`', open + 1);
      if (close == std::string::npos) break;
      code.push_back(line.substr(open + 1, close - open - 1));
      open = close;
    }
  }
  return code;
}

std::vector<std::filesystem::path> pages() {
  std::vector<std::filesystem::path> found{fleet::test::source_path("/README.md")};
  for (const auto& entry : std::filesystem::directory_iterator(fleet::test::source_path("/docs"))) {
    if (entry.path().extension() == ".md") found.push_back(entry.path());
  }
  return found;
}

}  // namespace

TEST(DocsCommands, EveryFleetctlLineInTheDocsNamesACommandAndItsFlags) {
  std::map<std::string, std::set<std::string>> flags_of;
  for (const auto& spec : command_table()) {
    auto& flags = flags_of[spec.command];
    for (const auto& flag : spec.flags) flags.insert(flag.name);
  }
  std::map<std::string, bool> global;  // fleetctl's own flags: whether each takes a value
  for (const auto& flag : global_flags()) global[flag.name] = flag.kind != FlagSpec::Kind::kSwitch;
  global["--help"] = false;

  int lines_checked = 0;
  for (const auto& page : pages()) {
    for (const std::string& code : code_of(read(page))) {
      const std::size_t at = code.find("fleetctl ");
      if (at == std::string::npos) continue;
      std::istringstream words(code.substr(at + 9));
      std::vector<std::string> tokens;
      for (std::string word; words >> word;) tokens.push_back(word);
      // fleetctl's own flags come first, then the command.
      std::size_t k = 0;
      while (k < tokens.size() && tokens[k].rfind("-", 0) == 0) {
        const auto own = global.find(tokens[k]);
        k += own != global.end() && own->second ? 2 : 1;
      }
      if (k >= tokens.size() || !std::isalpha(static_cast<unsigned char>(tokens[k][0]))) continue;
      const std::string where = page.filename().string() + ": " + code;
      const std::string command = tokens[k];
      const auto known = flags_of.find(command);
      ASSERT_NE(known, flags_of.end()) << where << "\n  no fleetctl command '" << command << "'";
      ++lines_checked;
      for (++k; k < tokens.size(); ++k) {
        // "--flag", "[--flag", "--flag=value"; a pipe or a shell's "&&" ends the command.
        if (tokens[k] == "|" || tokens[k] == "&&" || tokens[k] == ";") break;
        std::string name = tokens[k];
        name.erase(0, name.find_first_not_of("[("));
        if (name.rfind("--", 0) != 0) continue;
        name = name.substr(0, name.find_first_of("=]|)"));
        EXPECT_TRUE(known->second.count(name) > 0 || global.count(name) > 0)
            << where << "\n  fleetctl " << command << " takes no " << name;
      }
    }
  }
  EXPECT_GT(lines_checked, 20) << "the docs show fleetctl command lines; none were found";
}
