// fleetctl loc-eval --trajectory rack_aisle: the picker's localization by markers, printed; the evaluation is
// eval::run_marker_loc_eval.
#include <exception>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>

#include "cli/commands.hpp"
#include "eval/marker_loc_eval.hpp"
#include "map/site.hpp"

namespace fleet::cli {

namespace {

nlohmann::json errors_json(const eval::MarkerLocErrors& e) {
  return {{"pos_rmse_cm", e.rmse_cm},
          {"pos_p95_cm", e.p95_cm},
          {"pos_max_cm", e.max_cm},
          {"heading_rmse_deg", e.heading_rmse_deg},
          {"heading_max_deg", e.heading_max_deg}};
}

void print_row(std::ostream& out, const std::string& name, const eval::MarkerLocErrors& e) {
  out << "  " << std::left << std::setw(22) << name << std::right << std::fixed << std::setprecision(1) << std::setw(9)
      << e.rmse_cm << std::setw(9) << e.p95_cm << std::setw(9) << e.max_cm << std::setprecision(2) << std::setw(10)
      << e.heading_rmse_deg << std::setw(10) << e.heading_max_deg << '\n';
}

}  // namespace

int marker_loc_eval_command(const CommandArgs& args, double duration, std::uint64_t seed, bool json, std::ostream& out,
                            std::ostream& err) {
  eval::MarkerLocEvalParams params;
  params.duration = duration;
  params.seed = seed;
  std::string markers_from = "the plant's rack aisle 1 pattern";
  if (!args.source_dir.empty()) {
    try {
      const map::Site site = map::load_site(map::site_path(args.source_dir + "/maps", "plant"));
      if (!site.markers.empty()) {
        params.markers = site.markers;
        for (const auto& rack : site.racks) params.occluders.push_back(rack.polygon);
        markers_from = "maps/plant.yaml";
      }
    } catch (const std::exception& e) {
      err << "loc-eval: markers of " << markers_from << " (" << e.what() << ")\n";
    }
  }
  eval::MarkerLocEvalResult r;
  try {
    r = eval::run_marker_loc_eval(params);
  } catch (const std::exception& e) {
    err << "loc-eval: " << e.what() << '\n';
    return kExitBadInput;
  }
  out << "loc-eval: rack_aisle (picker, markers of " << markers_from << "), " << params.duration << " s, seed "
      << params.seed << ", " << params.speed << " m/s, " << params.rack_distance << " m from the rack face\n";
  out << "  " << r.sightings << " marker sightings, " << r.sightings_fused << " fused, " << r.sightings_gated
      << " gated, " << r.markers_seen << " markers, longest gap " << std::fixed << std::setprecision(1)
      << r.longest_gap_s << " s, " << r.distance_m << " m in " << r.laps << " aisle lengths\n";
  out << "  " << std::left << std::setw(22) << "estimate" << std::right << std::setw(9) << "rmse cm" << std::setw(9)
      << "p95 cm" << std::setw(9) << "max cm" << std::setw(10) << "hdg rmse" << std::setw(10) << "hdg max" << '\n';
  print_row(out, "wheel odometry", r.odometry);
  print_row(out, "EKF gyro+odometry+markers", r.ekf);
  if (json) {
    nlohmann::json j;
    j["trajectory"] = "rack_aisle";
    j["duration_s"] = params.duration;
    j["seed"] = params.seed;
    j["markers_from"] = markers_from;
    j["sightings"] = r.sightings;
    j["sightings_fused"] = r.sightings_fused;
    j["sightings_gated"] = r.sightings_gated;
    j["markers_seen"] = r.markers_seen;
    j["longest_gap_s"] = r.longest_gap_s;
    j["distance_m"] = r.distance_m;
    j["ekf"] = errors_json(r.ekf);
    j["odometry"] = errors_json(r.odometry);
    out << j.dump() << '\n';
  }
  return kExitOk;
}

}  // namespace fleet::cli
