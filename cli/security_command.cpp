// fleetctl security init|check: the credentials every process presents on a domain with DDS
// Security (docs/security.md).

#include <ctime>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli/command_flags.hpp"
#include "cli/commands.hpp"
#include "common/args.hpp"
#include "config/fleet_config.hpp"
#include "security/credentials.hpp"
#include "security/security_folder.hpp"

namespace fleet::cli {

namespace {

constexpr int kDefaultDays = 365;

int init(const CommandArgs& args, const CommandFlags& flags, const std::string& dir, std::ostream& out) {
  const config::FleetConfig config = config::load_fleet_config(args.config_file);
  std::vector<std::string> robots, vehicles;
  for (const auto& [fleet, robot] : config.all_robots()) {
    robots.push_back(robot->id);
    if (fleet->vda5050) vehicles.push_back(robot->id);
  }
  const auto identities = security::site_identities(robots, vehicles);
  const int days = static_cast<int>(flags.integer("days").value_or(kDefaultDays));
  std::vector<std::string> web_names = security::default_web_names();
  if (const auto hosts = flags.value("web-hosts")) {
    web_names.clear();
    std::string name;
    for (std::istringstream in(*hosts); std::getline(in, name, ',');) web_names.push_back(name);
  }
  const std::int64_t until = security::init_folder(dir, identities, days, flags.flag("force"), web_names);
  if (args.json) {
    nlohmann::json names = nlohmann::json::array();
    for (const auto& identity : identities) names.push_back(identity.name);
    out << nlohmann::json{{"folder", dir},
                          {"config", config.source},
                          {"identities", names},
                          {"web_certificate", security::FolderLayout(dir).web_certificate()},
                          {"valid_until", security::utc_time(until)}}
               .dump()
        << "\n";
  } else {
    out << "credentials for " << identities.size() << " identities (server, operator and " << robots.size() << " robots"
        << (vehicles.empty() ? "" : ", and the VDA 5050 bridge") << " of " << config.source << ") in " << dir
        << ", valid until " << security::utc_time(until) << " UTC\n"
        << "the web view's HTTPS certificate and key: " << security::FolderLayout(dir).web_certificate() << ", "
        << security::FolderLayout(dir).web_key() << "\n";
  }
  return kExitOk;
}

int check(const CommandArgs& args, const std::string& dir, std::ostream& out) {
  const auto now = static_cast<std::int64_t>(std::time(nullptr));
  const auto certificates = security::expiries(dir);
  bool expired = false;
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& c : certificates) {
    const bool gone = c.not_after < now;
    expired = expired || gone;
    const double days_left = static_cast<double>(c.not_after - now) / 86400.0;
    if (args.json) {
      rows.push_back({{"file", c.file},
                      {"subject", c.subject},
                      {"not_after", security::utc_time(c.not_after)},
                      {"days_left", days_left},
                      {"expired", gone}});
    } else {
      out << security::utc_time(c.not_after) << " UTC  " << (gone ? "EXPIRED " : "") << std::fixed
          << std::setprecision(1) << days_left << " days  " << c.file << "  (" << c.subject << ")\n";
    }
  }
  if (args.json) out << nlohmann::json{{"folder", dir}, {"certificates", rows}, {"expired", expired}}.dump() << "\n";
  return expired ? kExitFailed : kExitOk;
}

}  // namespace

int security_command(const CommandArgs& args, std::ostream& out, std::ostream& /*err*/) {
  if (args.args.empty() || (args.args[0] != "init" && args.args[0] != "check")) {
    throw ArgError("security needs a subcommand: init DIR | check DIR");
  }
  const std::string sub = args.args[0];
  const CommandFlags flags("security", sub, std::vector<std::string>(args.args.begin() + 1, args.args.end()));
  if (flags.positionals().size() != 1) throw ArgError("security " + sub + ": give one folder\n" + flags.usage());
  const std::string& dir = flags.positionals().front();
  try {
    return sub == "init" ? init(args, flags, dir, out) : check(args, dir, out);
  } catch (const security::SecurityError& e) {
    throw InputError(e.what());
  }
}

}  // namespace fleet::cli
