// fleetctl ctrl-eval: argument parsing and printing only; the evaluation is eval::run_ctrl_eval.
#include <cmath>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <numbers>
#include <ostream>
#include <sstream>
#include <string>

#include "cli/command_flags.hpp"
#include "cli/commands.hpp"
#include "common/args.hpp"
#include "eval/ctrl_eval.hpp"
#include "map/site.hpp"

namespace fleet::cli {

namespace {

std::string cm(double metres) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(2) << metres * 100.0;
  return s.str();
}

}  // namespace

int ctrl_eval_command(const CommandArgs& args, std::ostream& out, std::ostream& err) {
  eval::CtrlEvalParams params;
  bool json = args.json;
  std::string site = "table_a";
  std::string plot_file;
  int exit_code = kExitOk;
  const auto parsed = flags_or_exit("ctrl-eval", args.args, out, err, exit_code);
  if (!parsed) return exit_code;
  const CommandFlags& a = *parsed;
  try {
    params.gyro_standstill_calibration = a.flag("gyro-cal");
    if (const auto v = a.value("plot")) plot_file = *v;
    if (const auto v = a.u64("seed")) params.seed = *v;
    if (const auto v = a.integer("runs")) params.runs = static_cast<int>(*v);
    if (const auto v = a.number("speed")) params.speed = *v;
    if (const auto v = a.value("site")) site = *v;
    if (const auto v = a.value("follower")) params.use_regulated = *v == "regulated";
  } catch (const ArgError& e) {
    err << "ctrl-eval: " << e.what() << '\n' << a.usage();
    return kExitBadInput;
  }
  try {
    params.site_file = known_site_path(args.source_dir, site);
  } catch (const InputError& e) {
    err << "ctrl-eval: " << e.what() << '\n';
    return kExitBadInput;
  }

  eval::CtrlEvalResult r;
  try {
    r = eval::run_ctrl_eval(params);
  } catch (const map::MapError& e) {
    err << "ctrl-eval: " << e.what() << '\n';
    return kExitBadInput;
  } catch (const std::invalid_argument& e) {
    err << "ctrl-eval: " << e.what() << '\n';
    return kExitBadInput;
  }

  out << "ctrl-eval: site " << site << ", seed " << params.seed << ", speed " << params.speed << " m/s, " << params.runs
      << " pick-and-drop orders\n\n";
  out << "path tracking (cross-track of the true pose to the planned path, cm)\n";
  out << "  " << std::left << std::setw(13) << "path" << std::setw(11) << "follower" << std::setw(9) << "loc"
      << std::right << std::setw(8) << "len m" << std::setw(8) << "time s" << std::setw(8) << "rms" << std::setw(8)
      << "max" << std::setw(9) << "loc rms" << std::setw(11) << "|dw| max"
      << "  arrived\n";
  for (const auto& t : r.tracking) {
    out << "  " << std::left << std::setw(13) << t.path << std::setw(11) << t.follower << std::setw(9) << t.localization
        << std::right << std::fixed << std::setprecision(2) << std::setw(8) << t.length << std::setprecision(1)
        << std::setw(8) << t.duration << std::setw(8) << cm(t.cross_track_rms) << std::setw(8) << cm(t.cross_track_max)
        << std::setw(9) << cm(t.loc_rms) << std::setprecision(3) << std::setw(11) << t.omega_jump_max << "  "
        << (t.arrived ? "yes" : "NO") << '\n';
  }
  const char* which = params.use_regulated ? "regulated" : "seed";
  out << "\n  " << which << " follower: EKF rms " << cm(r.cross_track_rms) << " cm, max " << cm(r.cross_track_max)
      << " cm; perfect localization rms " << cm(r.cross_track_rms_perfect) << " cm, max "
      << cm(r.cross_track_max_perfect) << " cm\n";
  if (params.runs > 0) {
    int failed = 0;
    for (const auto& o : r.orders) failed += !(o.picked && o.placed);
    out << "\npick and drop (" << params.runs << " orders, EKF, marker camera " << std::setprecision(0)
        << params.camera.miss_rate * 100.0 << " % misses)\n";
    out << "  pick success     " << std::setprecision(1) << r.pick_success * 100.0 << " % (" << r.picks << "/"
        << params.runs << ")\n";
    out << "  placement error  p50 " << cm(r.place_error.p50) << " cm, p95 " << cm(r.place_error.p95) << " cm, max "
        << cm(r.place_error.max) << " cm  (" << r.places << " placed)\n";
    out << "  placement yaw    p50 " << std::setprecision(2) << r.place_yaw_error.p50 << " deg, p95 "
        << r.place_yaw_error.p95 << " deg, max " << r.place_yaw_error.max << " deg\n";
    out << "  with perfect localization: pick success " << std::setprecision(1) << r.perfect_pick_success * 100.0
        << " %, placement p50 " << cm(r.perfect_place_error.p50) << " cm, p95 " << cm(r.perfect_place_error.p95)
        << " cm, yaw p95 " << std::setprecision(2) << r.perfect_place_yaw_error.p95 << " deg\n";
    if (std::getenv("FLEET_CTRL_EVAL_ORDERS") != nullptr) {
      for (std::size_t i = 0; i < r.orders.size(); ++i) {
        const auto& o = r.orders[i];
        out << "  order " << i + 1 << " " << o.pick_area << " -> " << o.drop_area << " place " << cm(o.place_error)
            << " cm " << std::setprecision(2) << o.place_yaw_error * 180.0 / std::numbers::pi << " deg, pick lat "
            << cm(o.pick_offset_lateral) << " cm yaw " << o.pick_offset_yaw * 180.0 / std::numbers::pi << " deg, loc "
            << cm(o.loc_error_at_drop) << " cm " << o.loc_yaw_error_at_drop * 180.0 / std::numbers::pi << " deg, "
            << std::setprecision(1) << o.duration << " s\n";
      }
    }
    for (std::size_t i = 0; i < r.orders.size(); ++i) {
      const auto& o = r.orders[i];
      if (o.picked && o.placed) continue;
      out << "  order " << i + 1 << " " << o.pick_area << " -> " << o.drop_area << ": " << o.failure << '\n';
    }
    out << "  failed orders    " << failed << '\n';
  }

  if (!plot_file.empty()) {
    std::ofstream f(plot_file);
    f << eval::ctrl_eval_svg(r);
    if (!f) {
      err << "ctrl-eval: cannot write " << plot_file << '\n';
      return kExitBadInput;
    }
    out << "  plot written to " << plot_file << '\n';
  }

  if (json) {
    nlohmann::json tracking = nlohmann::json::array();
    for (const auto& t : r.tracking) {
      tracking.push_back({{"path", t.path},
                          {"follower", t.follower},
                          {"localization", t.localization},
                          {"length_m", t.length},
                          {"duration_s", t.duration},
                          {"arrived", t.arrived},
                          {"cross_track_rms_m", t.cross_track_rms},
                          {"cross_track_max_m", t.cross_track_max},
                          {"loc_rms_m", t.loc_rms},
                          {"omega_jump_max_rad_s", t.omega_jump_max}});
    }
    nlohmann::json j = {{"seed", params.seed},
                        {"runs", params.runs},
                        {"site", site},
                        {"speed_m_s", params.speed},
                        {"follower", which},
                        {"gyro_standstill_calibration", params.gyro_standstill_calibration},
                        {"cross_track_rms_m", r.cross_track_rms},
                        {"cross_track_max_m", r.cross_track_max},
                        {"cross_track_rms_perfect_m", r.cross_track_rms_perfect},
                        {"cross_track_max_perfect_m", r.cross_track_max_perfect},
                        {"place_err_p50_m", r.place_error.p50},
                        {"place_err_p95_m", r.place_error.p95},
                        {"place_yaw_err_p50_deg", r.place_yaw_error.p50},
                        {"place_yaw_err_p95_deg", r.place_yaw_error.p95},
                        {"pick_success", r.pick_success},
                        {"perfect_loc_place_err_p95_m", r.perfect_place_error.p95},
                        {"perfect_loc_place_yaw_err_p95_deg", r.perfect_place_yaw_error.p95},
                        {"perfect_loc_pick_success", r.perfect_pick_success},
                        {"picks", r.picks},
                        {"places", r.places},
                        {"tracking", tracking}};
    out << j.dump() << '\n';
  }
  return kExitOk;
}

}  // namespace fleet::cli
