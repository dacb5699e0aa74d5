#pragma once
// The picker evaluation behind `fleetctl pick-eval`, on core/ alone: the seed's aisle-following
// tests [Picker thesis, Tables 7-9], the marker camera's error against distance [Picker thesis,
// Experiment 1, Tables 2-3], the arm's pick cycle over the plant's boxes [Picker thesis, section
// 4.4, Algorithm 4] and the job cycle of one picker on a plant pick list, each beside the thesis's
// figure and a target.

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "eval/aisle_eval.hpp"

namespace fleet::eval {

/// Experiment 1 [Picker thesis, section 4.2.9.2.1, Tables 2-3] on the simulated Axis PTZ camera
/// (perception::MarkerCameraParams::axis_ptz()): a marker straight ahead of the camera, square to
/// it, at each distance.
struct MarkerSweepParams {
  double from = 1.0;  ///< m
  double to = 10.0;   ///< m: the thesis moved the robot 10 m away from the wall [Picker thesis, Table 3]
  double step = 0.5;  ///< m
  /// Distinct markers per distance, each with its own systematic error (its print and placement):
  /// one marker's error repeats from frame to frame, so one alone would show one draw of it.
  int markers = 20;
  int frames = 10;     ///< frames of each marker
  double speed = 0.3;  ///< m/s, the thesis's standard speed in Experiment 1 [Picker thesis, Table 3]
};

struct MarkerErrorRow {
  double distance = 0.0;  ///< m, camera to marker
  int frames = 0;
  int detected = 0;
  double range_median = 0.0;  ///< |measured - true distance|, m
  double range_p95 = 0.0;
  double position_median = 0.0;  ///< where the detection puts the marker, off the truth, m
  double position_p95 = 0.0;
};

struct MarkerSweepResult {
  std::vector<MarkerErrorRow> rows;
  /// "The errors are well below 30 cm for a distance of 5.5 meters" and "close to 1 meter" near
  /// 10 m [Picker thesis, section 4.2.9.2.1, Fig. 4.7].
  double thesis_error = 0.30;         ///< m
  double thesis_distance = 5.5;       ///< m
  double thesis_far_error = 1.0;      ///< m
  double thesis_far_distance = 10.0;  ///< m
  double worst_range_p95 = 0.0;       ///< the largest range p95 up to thesis_distance, m
  bool within_target = false;         ///< worst_range_p95 < thesis_error
};

/// The distance error of the picker's Axis camera from `params.from` to `params.to`; `seed`
/// drives its noise and the markers' systematic errors.
MarkerSweepResult run_marker_sweep(const MarkerSweepParams& params, std::uint64_t seed);

/// What is read from files: the plant, its fleets, the pick list.
struct PickEvalFiles {
  std::string site;       ///< maps/plant.yaml
  std::string config;     ///< config/sites/plant.yaml: the fleet of robot_type picker
  std::string pick_list;  ///< maps/plant_pick_list.csv
};

/// The files under the project root `source_dir`.
PickEvalFiles plant_pick_eval_files(const std::string& source_dir);

struct PickEvalParams {
  std::uint64_t seed = 1;
  PickEvalFiles files;
  /// Single-box picks over the site's box stocks, round robin: each from a random slot of the
  /// pallet's near edge (PickerArmLayout::slots) on a random layer of those the stock's count fills
  /// (as many boxes a layer as fit on an EPAL).
  int pick_trials = 200;
  MarkerSweepParams markers;
  /// The tours' drop place; empty: the site's first packing station, as the server's automatic
  /// pick orders (fleet_server_picks.cpp).
  std::string drop_place;
  bool aisle = true;  ///< run the aisle tests (the slowest section: four closed loops)
};

/// One box stock the site declares, picked `trials` times.
struct StockPicks {
  std::string place;
  std::string item;
  double mass = 0.0;      ///< kg
  bool pickable = false;  ///< no heavier than the pickers' load max_mass: pick lines may ask for it
  int layers = 0;         ///< layers its count fills on an EPAL
  int trials = 0;
  int successes = 0;
  double per_box_median = 0.0;  ///< s to locate, pick and stow one box, over successes
  double per_box_p95 = 0.0;
  double drop_median = 0.0;  ///< s to take it off the tray and put it down
};

/// The picks of pickable stocks from one place of the pallet.
struct PositionPicks {
  int slot = 0;   ///< along the near edge: in front of the arm, ahead, behind
  int layer = 0;  ///< boxes below it
  int trials = 0;
  int successes = 0;
};

struct PickCycleResult {
  double max_box_mass = 0.0;  ///< kg: the pickers' load max_mass (what pick lines may ask for)
  std::vector<StockPicks> stocks;
  std::vector<PositionPicks> positions;  ///< by slot, then layer
  int trials = 0;                        ///< over pickable stocks
  int successes = 0;
  double success_rate = 0.0;
  double per_box_median = 0.0;  ///< s, over successful picks of pickable stocks
  double per_box_p95 = 0.0;
  double per_box_max = 0.0;
  double drop_median = 0.0;  ///< s per box
  double drop_p95 = 0.0;
  std::map<std::string, int> refusals;  ///< pickable stocks' failed picks by reason
  int heavy_trials = 0;                 ///< picks of stocks over max_box_mass
  std::map<std::string, int> heavy_refusals;
  /// "The state machine then comes back to state '2.0' after 36 seconds" [Picker thesis, section 5.3.3.1.2].
  double thesis_pick = 36.0;     ///< s per box
  double target_success = 0.99;  ///< of pickable picks
  bool within_target = false;    ///< per_box_p95 <= thesis_pick and success_rate >= target_success
};

/// One leg of a tour: from one stand to the next.
struct TourLeg {
  std::string from;
  std::string to;
  double distance = 0.0;  ///< m on the road graph
  double time = 0.0;      ///< s
};

struct TourResult {
  std::vector<std::string> places;  ///< in the order visited
  int boxes = 0;
  std::vector<TourLeg> legs;
  double travel_distance = 0.0;  ///< m
  double travel_time = 0.0;      ///< s
  double pick_time = 0.0;        ///< s, the arm at every place
  double drop_time = 0.0;        ///< s, the arm at the drop place
  double cycle_time = 0.0;       ///< s
  bool ok = true;
  std::string reason;  ///< why not
};

struct JobCycleResult {
  std::string pick_list;          ///< the file
  std::string drop_place;         ///< the tours' packing station
  std::string fleet;              ///< the pickers' fleet id
  double max_speed = 0.0;         ///< m/s, the fleet's profile
  double max_acceleration = 0.0;  ///< m/s^2
  int lines = 0;
  int boxes = 0;      ///< asked for
  int delivered = 0;  ///< boxes of tours that ended at the drop place
  std::vector<TourResult> tours;
  double cycle_median = 0.0;  ///< s per tour
  double cycle_max = 0.0;
  double total_time = 0.0;  ///< s, the tours back to back
  double items_per_hour = 0.0;
  /// Where a delivered box's time goes, over the tours that delivered: the arm (locate, pick,
  /// stow, unstow, put down) and the driving, s per box. Each alone bounds the rate: the arm's
  /// with no driving at all, the driving's with an arm that took no time.
  double arm_per_box = 0.0;
  double travel_per_box = 0.0;
  double arm_bound_items_per_hour = 0.0;
  double travel_bound_items_per_hour = 0.0;
  int tour_capacity = 0;  ///< boxes a tour carries at most
  std::vector<std::string> assumptions;
  /// "The time of the simulation was specified to be 7 minutes approximately" for one job of pick
  /// and drop [Picker thesis, section 5.3.3.1.3].
  double thesis_cycle = 420.0;  ///< s
  /// IAM Robotics' published rate for its picker; the thesis gives none.
  double target_items_per_hour = 100.0;
  bool within_target = false;  ///< cycle_max <= thesis_cycle and items_per_hour >= the target
};

/// The loader and transporter of [Picker thesis, section 4.3.3.1], which the thesis never built:
/// a transporter (a stacker) stands behind the picker with a pallet on its raised forks, and the
/// picker sets each box straight on that pallet instead of its own tray. It neither unstows nor
/// drives to a packing station; when the pallet is full, the next transporter, waiting behind,
/// moves up while the full one leaves. The same pick list, arm plans and road travel as the job
/// cycle; the places are walked nearest first.
struct LoaderCycleResult {
  /// Where a box can stand on the transporter's pallet: the candidate places behind the base
  /// (base frame, bottom centre, m) that the arm reaches with the list's first box.
  std::vector<Eigen::Vector3d> deck;
  int runs = 0;                ///< transporters filled, one after the other along the walk
  int boxes = 0;               ///< asked for
  int delivered = 0;           ///< boxes set on a transporter
  double arm_time = 0.0;       ///< s: locate, pick and set down, every box
  double travel_time = 0.0;    ///< s: the picker from place to place
  double swap_time = 0.0;      ///< s: every transporter moving up behind a full one
  double swap_distance = 0.0;  ///< m a transporter moves up: its length and a gap
  double total_time = 0.0;
  double items_per_hour = 0.0;
  double arm_per_box = 0.0;           ///< s
  std::vector<std::string> failures;  ///< boxes the arm refused, with why
  std::vector<std::string> assumptions;
  double target_items_per_hour = 100.0;  ///< IAM Robotics' published rate
};

struct PickEvalResult {
  PickEvalParams params;
  std::vector<AisleTestResult> aisle;
  AisleTargets aisle_targets;
  MarkerSweepResult markers;
  PickCycleResult picks;
  JobCycleResult job;
  LoaderCycleResult loader;

  /// Every section within its target.
  bool within_targets() const;
};

/// The whole evaluation. Throws InputError for a file it cannot read or a pick list the site
/// cannot serve (check_pick_lines' message).
PickEvalResult run_pick_eval(const PickEvalParams& params);

}  // namespace fleet::eval
