// fleetctl loc-eval --trajectory rack_aisle|plant_route: the picker's localization by markers, printed; the
// evaluation is eval::run_marker_loc_eval.
#include <exception>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>

#include "cli/commands.hpp"
#include "common/errors.hpp"
#include "config/fleet_config.hpp"
#include "eval/marker_loc_eval.hpp"
#include "map/site.hpp"
#include "map/site_map.hpp"
#include "planning/road_planner.hpp"

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

// The pickers' round on the plant as the live fleet drives it: from pk1's parking place to the first
// rack place with boxes, on to the first packing station and back to the parking place, along the
// road graph as an agent plans it, at the speed the plant's pickers drive (config/sites/plant.yaml).
constexpr const char* kRouteHome = "PP1";

double plant_picker_speed(const std::string& source_dir) {
  const std::string path = source_dir + "/config/sites/plant.yaml";
  const config::FleetConfig config = config::load_fleet_config(path);
  for (const auto& fleet : config.fleets) {
    if (fleet.robot_type == "picker") return config.top_speed(fleet);
  }
  throw InputError(path + ": no fleet of robot_type picker");
}

std::vector<geometry::Vec2> plant_picker_route(const map::SiteMap& plant, std::string& stops_named) {
  const map::Site& site = plant.site;
  const map::Home* home = site.find_home(kRouteHome);
  const map::LoadingArea* rack = nullptr;
  for (const auto& area : site.loading_areas) {
    if (area.boxes) {
      rack = &area;
      break;
    }
  }
  const map::LoadingArea* station =
      site.packing && !site.packing->stations.empty() ? site.find_area(site.packing->stations.front()) : nullptr;
  if (!home || !rack || !station) {
    throw InputError(std::string("maps/plant.yaml: plant_route needs parking place ") + kRouteHome +
                     ", a rack place with boxes and a packing station");
  }
  stops_named = std::string(kRouteHome) + " -> " + rack->id + " -> " + station->id + " -> " + kRouteHome;
  const std::vector<geometry::Pose2> stops{home->pose, rack->approach_pose(site.approach_distance),
                                           station->approach_pose(site.approach_distance), home->pose};
  planning::RoadPlanner planner(plant.graph.graph);
  std::vector<geometry::Vec2> route{stops.front().position()};
  for (std::size_t i = 1; i < stops.size(); ++i) {
    const planning::RoadPlan plan = planner.plan(stops[i - 1], stops[i]);
    if (plan.status != planning::PlanStatus::kFound) {
      throw InputError("maps/plant.yaml: no road from stop " + std::to_string(i - 1) + " to stop " + std::to_string(i) +
                       " of " + stops_named);
    }
    route.insert(route.end(), plan.points.begin(), plan.points.end());
    route.push_back(stops[i].position());
  }
  return route;
}

}  // namespace

int marker_loc_eval_command(const CommandArgs& args, const std::string& trajectory, double duration, std::uint64_t seed,
                            bool json, std::ostream& out, std::ostream& err) {
  eval::MarkerLocEvalParams params;
  params.duration = duration;
  params.seed = seed;
  std::string markers_from = "the plant's rack aisle 1 pattern";
  std::string driven;
  if (trajectory == "plant_route") {
    if (args.source_dir.empty()) {
      err << "loc-eval: plant_route reads maps/plant.yaml, and the project's maps/ was not found\n";
      return kExitBadInput;
    }
    try {
      const map::SiteMap plant = map::load_site_map(map::site_path(args.source_dir + "/maps", "plant"));
      params.markers = plant.site.markers;
      for (const auto& rack : plant.site.racks) params.occluders.push_back(rack.polygon);
      params.route = plant_picker_route(plant, driven);
      params.speed = plant_picker_speed(args.source_dir);
      markers_from = "maps/plant.yaml";
    } catch (const std::exception& e) {
      err << "loc-eval: " << e.what() << '\n';
      return kExitBadInput;
    }
  } else if (!args.source_dir.empty()) {
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
  out << "loc-eval: " << trajectory << " (picker, markers of " << markers_from << "), " << params.duration
      << " s, seed " << params.seed << ", " << params.speed << " m/s, ";
  if (params.route.empty()) {
    out << params.rack_distance << " m from the rack face\n";
  } else {
    out << driven << " and back\n";
  }
  out << "  " << r.sightings << " marker sightings, " << r.sightings_fused << " fused, " << r.sightings_gated
      << " gated, " << r.markers_seen << " markers, longest gap " << std::fixed << std::setprecision(1)
      << r.longest_gap_s << " s, " << r.distance_m << " m in " << r.laps
      << (params.route.empty() ? " aisle lengths" : " route lengths") << "; largest error at (" << r.worst_at.x << ", "
      << r.worst_at.y << ")\n";
  out << "  " << std::left << std::setw(22) << "estimate" << std::right << std::setw(9) << "rmse cm" << std::setw(9)
      << "p95 cm" << std::setw(9) << "max cm" << std::setw(10) << "hdg rmse" << std::setw(10) << "hdg max" << '\n';
  print_row(out, "wheel odometry", r.odometry);
  print_row(out, "EKF gyro+odometry+markers", r.ekf);
  if (json) {
    nlohmann::json j;
    j["trajectory"] = trajectory;
    j["speed_mps"] = params.speed;
    j["worst_at"] = {r.worst_at.x, r.worst_at.y};
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
