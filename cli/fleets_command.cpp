#include <iomanip>
#include <sstream>

#include "cli/command_flags.hpp"
#include "cli/commands.hpp"
#include "common/args.hpp"
#include "config/fleet_config.hpp"
#include "vehicle/factsheet.hpp"

namespace fleet::cli {

namespace {

std::string joined(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& item : items) out += (out.empty() ? "" : ", ") + item;
  return out;
}

std::string fixed(double value, int digits) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << value;
  return s.str();
}

}  // namespace

int fleets_command(const CommandArgs& args, std::ostream& out, std::ostream& /*err*/) {
  // --site only chooses the configuration (config/sites/SITE.yaml), which main() has done.
  const CommandFlags flags("fleets", "", args.args);  // takes no argument
  const config::FleetConfig config = config::load_fleet_config(args.config_file);
  if (args.json) {
    nlohmann::json fleets = nlohmann::json::array();
    for (const auto& fleet : config.fleets) {
      std::vector<std::string> ids;
      for (const auto& robot : fleet.robots) ids.push_back(robot.id);
      fleets.push_back(vehicle::factsheet(fleet.id, fleet.robot_type, fleet.profile, ids));
    }
    out << nlohmann::json{{"config", config.source}, {"fleets", fleets}}.dump() << "\n";
    return kExitOk;
  }
  out << "fleets of " << config.source << "\n";
  for (const auto& fleet : config.fleets) {
    const auto& p = fleet.profile;
    std::vector<std::string> ids;
    for (const auto& robot : fleet.robots) ids.push_back(robot.id);
    out << "\n"
        << fleet.id << " (" << fleet.robot_type << ", " << fleet.robots.size() << " robots: " << joined(ids) << ")\n";
    out << "  footprint   " << fixed(fleet.footprint.length, 2) << " x " << fixed(fleet.footprint.width, 2) << " m, "
        << p.footprint.size() << " corners\n";
    out << "  kinematics  " << vehicle::to_string(p.kinematics);
    if (p.kinematics == vehicle::Kinematics::kTricycle) {
      out << ", wheelbase " << fixed(p.wheelbase, 2) << " m, steering up to " << fixed(p.max_steering_angle, 2)
          << " rad, rear axle at x = " << fixed(p.rear_axle_x, 2) << " m";
    }
    out << "\n  limits      " << fixed(p.max_speed, 2) << " m/s, " << fixed(p.max_acceleration, 2) << " m/s^2, "
        << fixed(p.max_yaw_rate, 2) << " rad/s\n";
    out << "  load        " << p.load.load_type << ", up to " << fixed(p.load.max_mass, 1) << " kg, lifted to "
        << fixed(p.load.lift_height, 2) << " m\n";
    out << "  actions     " << (p.actions.empty() ? "none" : joined(p.actions)) << "\n";
  }
  return kExitOk;
}

}  // namespace fleet::cli
