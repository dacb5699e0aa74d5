#include "eval/pick_eval.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <random>
#include <sstream>

#include "arm/pick_motion.hpp"
#include "arm/ur5.hpp"
#include "common/errors.hpp"
#include "common/percentile.hpp"
#include "config/fleet_config.hpp"
#include "map/site_map.hpp"
#include "orders/loader_job.hpp"
#include "orders/pick_lines.hpp"
#include "perception/marker_camera.hpp"
#include "planning/plan_eval.hpp"
#include "planning/road_travel.hpp"
#include "robot/forklift/forklift.hpp"
#include "robot/picker/picker_arm_work.hpp"
#include "robot/picker/picker_robot.hpp"
#include "robot/robot_factory.hpp"
#include "sim/depth_camera.hpp"
#include "task/task_executor.hpp"
#include "traffic/traffic_settings.hpp"

namespace fleet::eval {

namespace {

/// One stream of seeds per section and trial, so that changing one section's size does not
/// reshuffle another's noise (splitmix64).
std::uint64_t seed_of(std::uint64_t seed, std::uint64_t stream) {
  std::uint64_t z = seed + 0x9e3779b97f4a7c15ULL * (stream + 1);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

constexpr std::uint64_t kPickStream = 1000;
constexpr std::uint64_t kJobStream = 2000000;

double median(const std::vector<double>& v) {
  return common::percentile(v, 0.5);
}
double p95(const std::vector<double>& v) {
  return common::percentile(v, 0.95);
}

/// The plant as the picker's software sees it: the site, the fleets, the pickers' fleet and the
/// picker's configuration as make_robot builds it.
struct PlantPicker {
  map::SiteMap site;
  config::FleetConfig config;
  config::FleetSpec fleet;
  robot::PickerConfig picker;
};

PlantPicker load_plant_picker(const PickEvalFiles& files) {
  PlantPicker p;
  p.site = map::load_site_map(files.site);
  p.config = config::load_fleet_config(files.config);
  const auto fleet = std::find_if(p.config.fleets.begin(), p.config.fleets.end(),
                                  [](const config::FleetSpec& f) { return f.robot_type == "picker"; });
  if (fleet == p.config.fleets.end()) throw InputError(files.config + ": no fleet of robot_type picker");
  p.fleet = *fleet;
  p.picker = robot::picker_robot_config(p.config, p.fleet, p.site);
  return p;
}

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError("cannot read '" + path + "'");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// ---- section 2: the marker camera's error against distance ---------------------------------------------------

/// The errors of the frames of `markers` distinct markers `d` m straight ahead of the camera, square to it.
MarkerErrorRow marker_errors_at(double d, const MarkerSweepParams& params, std::uint64_t seed) {
  perception::MarkerCamera camera(perception::MarkerCameraParams::axis_ptz(), seed);
  const geometry::Pose2 robot{0.0, 0.0, 0.0};
  const geometry::Pose2 cam = perception::camera_pose(robot, camera.mount());
  const geometry::Vec2 ahead{std::cos(cam.yaw), std::sin(cam.yaw)};
  const geometry::Vec2 at = cam.position() + d * ahead;
  MarkerErrorRow row;
  row.distance = d;
  std::vector<double> range, position;
  const double period = 1.0 / camera.params().rate_hz;
  double t = 0.0;
  for (int m = 0; m < params.markers; ++m) {
    // The printed face looks back at the camera.
    const perception::Marker marker{m, {at.x, at.y, geometry::normalize_angle(cam.yaw + std::numbers::pi)}};
    for (int f = 0; f < params.frames; ++f, t += period) {
      ++row.frames;
      for (const auto& det : camera.capture(t, robot, std::span(&marker, 1), params.speed)) {
        ++row.detected;
        range.push_back(std::abs(det.d - d));
        const perception::Marker seen = perception::marker_from_detection(robot, camera.mount(), det);
        position.push_back(geometry::distance(seen.pose.position(), marker.pose.position()));
      }
    }
  }
  row.range_median = median(range);
  row.range_p95 = p95(range);
  row.position_median = median(position);
  row.position_p95 = p95(position);
  return row;
}

// ---- section 3: the arm's pick cycle over the site's box stocks ----------------------------------------------

void summarize_picks(PickCycleResult& r, const std::vector<double>& per_box, const std::vector<double>& drops) {
  r.success_rate = r.trials > 0 ? static_cast<double>(r.successes) / r.trials : 0.0;
  r.per_box_median = median(per_box);
  r.per_box_p95 = p95(per_box);
  r.per_box_max = per_box.empty() ? 0.0 : *std::max_element(per_box.begin(), per_box.end());
  r.drop_median = median(drops);
  r.drop_p95 = p95(drops);
  r.within_target = r.successes > 0 && r.per_box_p95 <= r.thesis_pick && r.success_rate >= r.target_success;
}

/// Layers `stock`'s count fills on an EPAL, its boxes' width along the pallet's 1.2 m (away from the base, as
/// PickerArmLayout stands them) and their length along its 800 mm face.
int layers_of(const map::BoxStock& stock) {
  const sim::EpalDimensions epal;
  const int per_layer = std::max(1, static_cast<int>(std::floor(epal.length / stock.width + 1e-9)) *
                                        static_cast<int>(std::floor(epal.width / stock.length + 1e-9)));
  return std::max(1, (stock.count + per_layer - 1) / per_layer);
}

PickCycleResult run_pick_trials(const PlantPicker& plant, int trials, std::uint64_t seed) {
  PickCycleResult r;
  r.max_box_mass = orders::max_pickable_mass(plant.config);
  const auto boxes = orders::declared_boxes(plant.site.site);
  for (const map::LoadingArea& area : plant.site.site.loading_areas) {  // in the site's order
    const auto declared = boxes.find(area.id);
    if (declared == boxes.end()) continue;
    const map::BoxStock& stock = declared->second;
    r.stocks.push_back(
        {area.id, stock.item, stock.mass, stock.mass <= r.max_box_mass, layers_of(stock), 0, 0, 0.0, 0.0, 0.0});
  }
  if (r.stocks.empty()) throw InputError(plant.site.site.name + ": the site declares no boxes");
  std::vector<std::vector<double>> stock_times(r.stocks.size()), stock_drops(r.stocks.size());
  std::vector<double> per_box, drops;
  std::map<std::pair<int, int>, PositionPicks> positions;  // by slot, then layer
  std::mt19937_64 where(seed_of(seed, kPickStream));
  for (int i = 0; i < trials; ++i) {
    const std::size_t s = static_cast<std::size_t>(i) % r.stocks.size();
    StockPicks& stock_picks = r.stocks[s];
    const map::BoxStock& stock = boxes.at(stock_picks.place);
    // A box at the near edge, which the arm reaches from the base's stand, on any layer the stock fills.
    const int slot = std::uniform_int_distribution<int>(0, plant.picker.arm_layout.slots - 1)(where);
    const int layer = std::uniform_int_distribution<int>(0, stock_picks.layers - 1)(where);
    robot::PickerArmWork arm =
        robot::make_picker_arm_work(plant.picker.box_camera, plant.picker.arm_layout,
                                    seed_of(seed, kPickStream + 1 + static_cast<std::uint64_t>(i)));
    std::vector<map::BoxStock> tray;
    const robot::ArmWork picked = arm.pick_at(stock, slot, layer, tray);
    ++stock_picks.trials;
    PositionPicks& at_position = positions[{slot, layer}];
    at_position.slot = slot;
    at_position.layer = layer;
    if (stock_picks.pickable) {
      ++at_position.trials;
      ++r.trials;
    } else {
      ++r.heavy_trials;
    }
    if (!picked.ok) {
      ++(stock_picks.pickable ? r.refusals : r.heavy_refusals)[picked.reason];
      continue;
    }
    const robot::ArmWork dropped = arm.drop(tray, 0);
    if (!dropped.ok) {
      ++(stock_picks.pickable ? r.refusals : r.heavy_refusals)["drop: " + dropped.reason];
      continue;
    }
    ++stock_picks.successes;
    stock_times[s].push_back(picked.duration / picked.boxes);
    stock_drops[s].push_back(dropped.duration / dropped.boxes);
    if (!stock_picks.pickable) continue;
    ++at_position.successes;
    ++r.successes;
    per_box.push_back(picked.duration / picked.boxes);
    drops.push_back(dropped.duration / dropped.boxes);
  }
  for (std::size_t s = 0; s < r.stocks.size(); ++s) {
    r.stocks[s].per_box_median = median(stock_times[s]);
    r.stocks[s].per_box_p95 = p95(stock_times[s]);
    r.stocks[s].drop_median = median(stock_drops[s]);
  }
  for (const auto& entry : positions) {
    if (entry.second.trials > 0) r.positions.push_back(entry.second);
  }
  summarize_picks(r, per_box, drops);
  return r;
}

// ---- section 4: the job cycle of one picker on a pick list ----------------------------------------------------

std::vector<std::string> job_assumptions(const JobCycleResult& j) {
  std::ostringstream profile;
  profile << "each leg a trapezoid from rest to rest at the vehicle profile of fleet " << j.fleet << ": " << j.max_speed
          << " m/s, " << j.max_acceleration << " m/s^2; no slowing in curves, no turning on the spot";
  return {
      "one picker alone on the site: no traffic waits, no other robot, no obstacle",
      "the tours back to back, each from the stand beside " + j.drop_place + " and back to it",
      "travel: the road-graph route of the server's travel planner on the graph of fleet " + j.fleet +
          " from stand to stand, plus the way onto and off the graph",
      profile.str(),
      "no time standing for localization or alignment at a stop: the arm starts on arrival",
      "the arm's times are PickerArmWork's plans (locate, pick, stow; unstow, put down), the boxes at the "
      "front of their pallets and the packing pallet empty",
      "a pick or drop the arm refuses ends its tour; its boxes are not delivered",
  };
}

/// How the picker gets from place to place: the server's travel planner for its fleet
/// (server::derive_site: its fleet graph, only the lanes its vehicle fits), where it
/// stands beside a place, and a leg's time at its profile.
class PickerRoads {
 public:
  explicit PickerRoads(const PlantPicker& plant)
      : plant_(plant),
        graphs_(traffic::fleet_graphs(plant.site.graph.graph, plant.config)),
        travel_(graphs_.at(plant.fleet.id)),
        executor_(plant.picker.base.task, {}) {}

  geometry::Pose2 stand_beside(const std::string& place) const {
    const map::LoadingArea* area = plant_.site.site.find_area(place);
    if (area == nullptr) throw InputError("unknown place '" + place + "' on " + plant_.site.site.name);
    return executor_.item_pose(area->pose);
  }

  /// Metres by road from the stand beside `from` to the stand beside `to`; +inf without a way.
  double distance(const std::string& from, const std::string& to) {
    return planning::road_travel_distance(travel_, stand_beside(from), stand_beside(to));
  }

  /// A trapezoid from rest to rest at the picker's profile; no time for a leg without a way.
  TourLeg leg(const std::string& from, const std::string& to) {
    TourLeg l{from, to, distance(from, to), 0.0};
    const auto& profile = plant_.fleet.profile;
    if (std::isfinite(l.distance))
      l.time = arm::trapezoid_time(l.distance, profile.max_speed, profile.max_acceleration);
    return l;
  }

 private:
  const PlantPicker& plant_;
  std::map<std::string, map::RoadGraph> graphs_;  ///< travel_ plans on one of them
  planning::RoadPlanner travel_;
  task::TaskExecutor executor_;  ///< only for item_pose
};

/// What a job's tours share: the plant, its roads, the arm.
struct JobContext {
  const PlantPicker& plant;
  PickerRoads& roads;
  robot::PickerArmWork& arm;
  std::string drop_place;
};

/// One tour from the drop place's stand to each place in turn and back; its cycle time is left to the caller.
TourResult run_tour(JobContext& job, const orders::PickTour& tour) {
  TourResult r;
  std::string at = job.drop_place;
  const auto drive_to = [&](const std::string& to) {
    const TourLeg leg = job.roads.leg(at, to);
    r.travel_distance += leg.distance;
    r.travel_time += leg.time;
    r.legs.push_back(leg);
    at = to;
    if (!std::isfinite(leg.distance)) {
      r.ok = false;
      r.reason = "no route from " + leg.from + " to " + to;
    }
    return r.ok;
  };
  std::vector<map::BoxStock> tray;
  for (const orders::PickLine& line : tour.lines) {
    r.places.push_back(line.place);
    r.boxes += line.quantity;
    if (!drive_to(line.place)) return r;
    const map::LoadingArea* area = job.plant.site.site.find_area(line.place);
    const robot::ArmWork picked = job.arm.pick(*area->boxes, line.quantity, tray);
    r.pick_time += picked.duration;
    if (!picked.ok) {
      r.ok = false;
      r.reason = line.place + ": " + picked.reason;
      return r;
    }
  }
  if (!drive_to(job.drop_place)) return r;
  const robot::ArmWork dropped = job.arm.drop(tray, 0);
  r.drop_time = dropped.duration;
  if (!dropped.ok) {
    r.ok = false;
    r.reason = job.drop_place + ": " + dropped.reason;
  }
  return r;
}

std::vector<orders::PickLine> checked_pick_list(const PlantPicker& plant, const std::string& file) {
  std::vector<orders::PickLine> lines = orders::parse_pick_lines(read_file(file), file);
  const auto why = orders::check_pick_lines(lines, plant.site.site.area_ids(), orders::declared_boxes(plant.site.site),
                                            orders::max_pickable_mass(plant.config), file);
  if (why) throw InputError(*why);
  return lines;
}

std::string drop_place_of(const PlantPicker& plant, const std::string& asked) {
  if (!asked.empty()) {
    if (plant.site.site.find_area(asked) == nullptr) throw InputError("unknown drop place '" + asked + "'");
    return asked;
  }
  const auto& packing = plant.site.site.packing;
  if (!packing || packing->stations.empty()) {
    throw InputError(plant.site.site.name + ": no packing station to drop at; name a drop place");
  }
  return packing->stations.front();
}

JobCycleResult run_job_cycle(const PlantPicker& plant, const std::vector<orders::PickLine>& lines,
                             const std::string& drop_place, const PickEvalParams& params) {
  JobCycleResult j;
  j.pick_list = params.files.pick_list;
  j.drop_place = drop_place;
  j.fleet = plant.fleet.id;
  j.max_speed = plant.fleet.profile.max_speed;
  j.max_acceleration = plant.fleet.profile.max_acceleration;
  j.assumptions = job_assumptions(j);
  j.lines = static_cast<int>(lines.size());
  for (const auto& l : lines) j.boxes += l.quantity;
  PickerRoads roads(plant);
  // One arm for the whole job, as the robot keeps one.
  robot::PickerArmWork arm =
      robot::make_picker_arm_work(plant.picker.box_camera, plant.picker.arm_layout, seed_of(params.seed, kJobStream));
  JobContext job{plant, roads, arm, j.drop_place};
  std::vector<double> cycles;
  j.tour_capacity = orders::kTourBoxes;
  double arm_time = 0.0;
  double travel_time = 0.0;
  for (const orders::PickTour& tour :
       orders::plan_tours(lines, orders::kTourBoxes, orders::place_poses(plant.site.site))) {
    TourResult r = run_tour(job, tour);
    r.cycle_time = r.travel_time + r.pick_time + r.drop_time;
    if (r.ok) {
      j.delivered += r.boxes;
      arm_time += r.pick_time + r.drop_time;
      travel_time += r.travel_time;
    }
    j.total_time += r.cycle_time;
    cycles.push_back(r.cycle_time);
    j.tours.push_back(std::move(r));
  }
  j.cycle_median = median(cycles);
  j.cycle_max = cycles.empty() ? 0.0 : *std::max_element(cycles.begin(), cycles.end());
  j.items_per_hour = j.total_time > 0.0 ? j.delivered * 3600.0 / j.total_time : 0.0;
  if (j.delivered > 0) {
    j.arm_per_box = arm_time / j.delivered;
    j.travel_per_box = travel_time / j.delivered;
    if (j.arm_per_box > 0.0) j.arm_bound_items_per_hour = 3600.0 / j.arm_per_box;
    if (j.travel_per_box > 0.0) j.travel_bound_items_per_hour = 3600.0 / j.travel_per_box;
  }
  j.within_target =
      j.delivered == j.boxes && j.cycle_max <= j.thesis_cycle && j.items_per_hour >= j.target_items_per_hour;
  return j;
}

// ---- section 5: the loader with a transporter behind it ---------------------------------------------------------

constexpr std::uint64_t kLoaderStream = 3000000;

/// The places behind the picker's base where a box could stand on a transporter's pallet, raised
/// to the tray's height: rows 0.3 m apart from just behind the base, three across.
std::vector<Eigen::Vector3d> deck_candidates(const robot::PickerArmLayout& layout) {
  const double height = layout.tray.empty() ? 0.40 : layout.tray.front().z();
  std::vector<Eigen::Vector3d> places;
  for (double x : {-0.55, -0.85, -1.15}) {
    for (double y : {0.25, -0.25, 0.0}) places.emplace_back(x, y, height);
  }
  return places;
}

LoaderCycleResult run_loader_cycle(const PlantPicker& plant, const std::vector<orders::PickLine>& lines,
                                   const PickEvalParams& params) {
  LoaderCycleResult l;
  for (const auto& line : lines) l.boxes += line.quantity;
  if (lines.empty()) return l;
  const map::LoadingArea* first = plant.site.site.find_area(lines.front().place);
  const map::BoxStock& sample = *first->boxes;
  const arm::PickMotionPlanner planner(arm::Ur5{}, arm::VacuumGripper{});
  for (const Eigen::Vector3d& place : deck_candidates(plant.picker.arm_layout)) {
    if (planner.plan_drop(robot::box_of(sample), {place, 0.0}, 0.0).ok) l.deck.push_back(place);
  }
  // The transporter moves up by its length and half a metre, at the stackers' profile.
  const auto stackers = std::find_if(plant.config.fleets.begin(), plant.config.fleets.end(),
                                     [](const config::FleetSpec& f) { return f.robot_type == "stacker"; });
  const config::FleetSpec& transporter = stackers != plant.config.fleets.end() ? *stackers : plant.fleet;
  l.swap_distance = transporter.footprint.length + 0.5;
  const double swap =
      arm::trapezoid_time(l.swap_distance, transporter.profile.max_speed, transporter.profile.max_acceleration);
  std::ostringstream moves;
  moves.setf(std::ios::fixed);
  moves.precision(1);
  moves << "a full transporter leaves and the next, waiting behind, moves up " << l.swap_distance
        << " m at the profile of fleet " << transporter.id << " (" << swap << " s), the picker standing meanwhile; "
        << "the transporters' drives to and from the packing stations overlap the picking";
  l.assumptions = {
      "one picker alone on the site, and always a transporter behind it with an empty pallet",
      "the transporter's pallet raised to the tray's height right behind the base: a box goes on the places the "
      "arm reaches there with the list's first box, one layer",
      moves.str(),
      "travel: the same road-graph route and trapezoid legs as the job cycle, from place to place as one walk: "
      "from the first place in aisle order, always on to the nearest by road",
      "the arm's times are PickerArmWork's plans (locate, pick, set down), as in the job cycle",
  };
  if (l.deck.empty()) return l;
  robot::PickerArmLayout layout = plant.picker.arm_layout;
  layout.tray = l.deck;
  robot::PickerArmWork arm =
      robot::make_picker_arm_work(plant.picker.box_camera, layout, seed_of(params.seed, kLoaderStream));
  PickerRoads roads(plant);
  // The picker no longer returns anywhere between loads, so it visits the places as one walk.
  const std::vector<orders::PickLine> walk =
      orders::loader_walk(lines, static_cast<int>(l.deck.size()), orders::place_poses(plant.site.site),
                          [&](const std::string& from, const std::string& to) { return roads.distance(from, to); });
  std::vector<map::BoxStock> pallet;
  std::string at;
  for (const orders::PickLine& line : walk) {
    if (pallet.size() + static_cast<std::size_t>(line.quantity) > l.deck.size()) {
      pallet.clear();  // the full transporter leaves, the next moves up
      ++l.runs;
      l.swap_time += swap;
    }
    if (!at.empty() && at != line.place) l.travel_time += roads.leg(at, line.place).time;
    at = line.place;
    const robot::ArmWork work = arm.pick(*plant.site.site.find_area(line.place)->boxes, line.quantity, pallet);
    l.arm_time += work.duration;
    l.delivered += work.boxes;
    if (!work.ok) l.failures.push_back(line.place + ": " + work.reason);
  }
  ++l.runs;  // the last transporter leaves as well
  l.swap_time += swap;
  l.total_time = l.arm_time + l.travel_time + l.swap_time;
  if (l.total_time > 0.0) l.items_per_hour = l.delivered * 3600.0 / l.total_time;
  if (l.delivered > 0) l.arm_per_box = l.arm_time / l.delivered;
  return l;
}

}  // namespace

MarkerSweepResult run_marker_sweep(const MarkerSweepParams& params, std::uint64_t seed) {
  MarkerSweepResult r;
  const int steps = static_cast<int>(std::floor((params.to - params.from) / params.step + 1e-9));
  for (int k = 0; k <= steps; ++k) {
    const double d = params.from + k * params.step;
    r.rows.push_back(marker_errors_at(d, params, seed_of(seed, static_cast<std::uint64_t>(k))));
    if (d <= r.thesis_distance + 1e-9) r.worst_range_p95 = std::max(r.worst_range_p95, r.rows.back().range_p95);
  }
  r.within_target = !r.rows.empty() && r.worst_range_p95 < r.thesis_error;
  return r;
}

PickEvalFiles plant_pick_eval_files(const std::string& source_dir) {
  const std::filesystem::path root(source_dir.empty() ? "." : source_dir);
  return {(root / "maps" / "plant.yaml").string(), (root / "config" / "sites" / "plant.yaml").string(),
          (root / "maps" / "plant_pick_list.csv").string()};
}

bool PickEvalResult::within_targets() const {
  const bool aisle_ok =
      std::all_of(aisle.begin(), aisle.end(), [](const AisleTestResult& a) { return a.within_target; });
  return aisle_ok && markers.within_target && picks.within_target && job.within_target;
}

PickEvalResult run_pick_eval(const PickEvalParams& params) {
  PickEvalResult r;
  r.params = params;
  // The files first: bad input is told before the long sections run.
  const PlantPicker plant = load_plant_picker(params.files);
  const std::vector<orders::PickLine> lines = checked_pick_list(plant, params.files.pick_list);
  const std::string drop_place = drop_place_of(plant, params.drop_place);
  if (params.aisle) r.aisle = run_seed_aisle_tests(params.seed, r.aisle_targets);
  r.markers = run_marker_sweep(params.markers, params.seed);
  r.picks = run_pick_trials(plant, params.pick_trials, params.seed);
  r.job = run_job_cycle(plant, lines, drop_place, params);
  r.loader = run_loader_cycle(plant, lines, params);
  return r;
}

}  // namespace fleet::eval
