// fleetctl loc-eval: argument parsing and printing only; the evaluation is eval::run_loc_eval.
#include <exception>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>

#include "cli/command_flags.hpp"
#include "cli/commands.hpp"
#include "common/args.hpp"
#include "eval/loc_eval.hpp"
#include "map/site.hpp"

namespace fleet::cli {

namespace {

nlohmann::json stats_json(const eval::ErrorStats& s) {
  return {{"pos_rmse_m", s.pos_rmse},
          {"pos_max_m", s.pos_max},
          {"heading_rmse_deg", s.heading_rmse_deg},
          {"heading_max_deg", s.heading_max_deg}};
}

void print_row(std::ostream& out, const std::string& name, const eval::ErrorStats& s, bool heading, int gated,
               double resolved_at) {
  out << "  " << std::left << std::setw(22) << name << std::right << std::fixed << std::setprecision(1) << std::setw(9)
      << s.pos_rmse * 100.0 << std::setw(9) << s.pos_max * 100.0;
  if (heading) {
    out << std::setprecision(2) << std::setw(10) << s.heading_rmse_deg << std::setw(10) << s.heading_max_deg
        << std::setw(7) << gated << std::setprecision(2) << std::setw(9) << resolved_at;
  }
  out << '\n';
}

}  // namespace

int loc_eval_command(const CommandArgs& args, std::ostream& out, std::ostream& err) {
  eval::LocEvalParams params;
  std::string marker_trajectory;  // rack_aisle or plant_route: the picker's markers, not UWB
  std::string plot_file;
  bool json = args.json;
  int exit_code = kExitOk;
  const auto parsed = flags_or_exit("loc-eval", args.args, out, err, exit_code);
  if (!parsed) return exit_code;
  const CommandFlags& a = *parsed;
  try {
    if (const auto v = a.value("trajectory")) {
      if (*v == "rack_aisle" || *v == "plant_route") {
        marker_trajectory = *v;
      } else {
        params.trajectory = eval::parse_trajectory(*v).value();  // the table's choices are the trajectories
      }
    }
    if (const auto v = a.number("duration")) params.duration = *v;
    if (const auto v = a.u64("seed")) params.seed = *v;
    if (const auto v = a.number("nlos")) params.nlos_fraction = *v;
    if (const auto v = a.value("plot")) plot_file = *v;
  } catch (const ArgError& e) {
    err << "loc-eval: " << e.what() << '\n' << a.usage();
    return kExitBadInput;
  }

  if (!marker_trajectory.empty()) {
    if (params.nlos_fraction > 0.0 || !plot_file.empty()) {
      err << "loc-eval: --nlos and --plot apply to the UWB trajectories, not " << marker_trajectory << '\n'
          << a.usage();
      return kExitBadInput;
    }
    return marker_loc_eval_command(args, marker_trajectory, params.duration, params.seed, json, out, err);
  }

  // Anchors from the demo site when it is readable; the same four corners otherwise.
  if (!args.source_dir.empty()) {
    try {
      const map::Site site = map::load_site(map::site_path(args.source_dir + "/maps", "table_a"));
      if (site.uwb_anchors.size() >= 3) params.anchors = site.uwb_anchors;
    } catch (const std::exception& e) {
      err << "loc-eval: using default anchors (" << e.what() << ")\n";
    }
  }

  eval::LocEvalResult r;
  try {
    r = eval::run_loc_eval(params);
  } catch (const std::exception& e) {
    err << "loc-eval: " << e.what() << '\n';
    return kExitBadInput;
  }

  if (!plot_file.empty()) {
    std::ofstream f(plot_file);
    f << eval::loc_eval_svg(r);
    if (!f) {
      err << "loc-eval: cannot write --plot file '" << plot_file << "'\n";
      return kExitBadInput;
    }
  }

  out << "loc-eval: " << eval::to_string(params.trajectory) << ", " << params.duration << " s, seed " << params.seed
      << ", NLOS fraction " << params.nlos_fraction << "\n";
  out << "  UWB: " << r.uwb_fixes << " fixes, " << r.uwb_missing << " epochs without fix, " << r.ranges << " ranges ("
      << r.nlos_ranges << " NLOS), LOS range noise " << std::fixed << std::setprecision(1) << r.range_noise_std * 100.0
      << " cm\n";
  out << "  " << std::left << std::setw(22) << "estimate" << std::right << std::setw(9) << "rmse cm" << std::setw(9)
      << "max cm" << std::setw(10) << "hdg rmse" << std::setw(10) << "hdg max" << std::setw(7) << "gated"
      << std::setw(9) << "hdg at s" << '\n';
  print_row(out, "raw UWB", r.uwb, false, 0, 0.0);
  print_row(out, "EKF full", r.full.ekf, true, r.full.fixes_gated, r.full.heading_resolved_at);
  for (const auto& v : r.variants) {
    print_row(out, "EKF " + v.name, v.ekf, true, v.fixes_gated, v.heading_resolved_at);
  }
  const double ratio = r.uwb.pos_rmse > 0.0 ? r.full.ekf.pos_rmse / r.uwb.pos_rmse : 0.0;
  out << "  EKF / UWB RMSE ratio " << std::setprecision(3) << ratio << '\n';
  if (!plot_file.empty()) out << "  plot written to " << plot_file << '\n';

  if (json) {
    nlohmann::json j;
    j["trajectory"] = eval::to_string(params.trajectory);
    j["duration_s"] = params.duration;
    j["seed"] = params.seed;
    j["nlos_fraction"] = params.nlos_fraction;
    j["uwb_pos_rmse_m"] = r.uwb.pos_rmse;
    j["uwb_pos_max_m"] = r.uwb.pos_max;
    j["ekf_pos_rmse_m"] = r.full.ekf.pos_rmse;
    j["ekf_pos_max_m"] = r.full.ekf.pos_max;
    j["ekf_heading_rmse_deg"] = r.full.ekf.heading_rmse_deg;
    j["ekf_heading_max_deg"] = r.full.ekf.heading_max_deg;
    j["ekf_to_uwb_ratio"] = ratio;
    j["heading_resolved_at_s"] = r.full.heading_resolved_at;
    j["fixes_gated"] = r.full.fixes_gated;
    j["uwb_fixes"] = r.uwb_fixes;
    j["range_noise_std_m"] = r.range_noise_std;
    j["nlos_ranges"] = r.nlos_ranges;
    nlohmann::json variants = nlohmann::json::object();
    for (const auto& v : r.variants) variants[v.name] = stats_json(v.ekf);
    j["variants"] = variants;
    out << j.dump() << '\n';
  }
  return kExitOk;
}

}  // namespace fleet::cli
