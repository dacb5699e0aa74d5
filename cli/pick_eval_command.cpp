// fleetctl pick-eval: argument parsing and printing only; the evaluation is eval::run_pick_eval.
#include <cmath>
#include <exception>
#include <iomanip>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>
#include <ostream>
#include <sstream>
#include <string>

#include "cli/command_flags.hpp"
#include "cli/commands.hpp"
#include "common/args.hpp"
#include "common/errors.hpp"
#include "eval/pick_eval.hpp"
#include "geometry/pose.hpp"

namespace fleet::cli {

namespace {

using ::fleet::geometry::kDeg;

const char* met(bool ok) {
  return ok ? "met" : "MISSED";
}

/// A time that may be infinite (never settled) or not stated (NaN), for the table.
std::string seconds(double s) {
  if (std::isnan(s)) return "-";
  if (std::isinf(s)) return "never";
  std::ostringstream os;
  os << std::fixed << std::setprecision(2) << s;
  return os.str();
}

/// NaN and infinity are not JSON numbers: null.
nlohmann::json number_or_null(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

void print_aisle(std::ostream& out, const eval::PickEvalResult& r) {
  const auto& t = r.aisle_targets;
  out << "1. aisle following, tests I-III [Picker thesis, Tables 7-9]: rack 3 m, d_ref 1 m, 40 Hz; settled = within "
         "3 cm and 1 deg for good\n"
      << std::fixed << std::setprecision(1) << "   target: final lateral <= " << t.final_lateral * 100.0
      << " cm, heading <= " << t.final_heading / kDeg << " deg\n"
      << "   " << std::left << std::setw(9) << "test" << std::setw(9) << "source" << std::setw(42) << "thesis"
      << std::right << std::setw(10) << "thesis s" << std::setw(10) << "settle s" << std::setw(12) << "lateral cm"
      << std::setw(9) << "yaw deg" << std::setw(17) << "peak lat/fwd m/s" << std::setw(8) << "target" << '\n';
  for (const auto& a : r.aisle) {
    const auto& f = a.figures;
    std::ostringstream peaks;
    peaks << std::fixed << std::setprecision(2) << f.peak_lateral << " / " << f.peak_forward;
    out << "   " << std::left << std::setw(9) << a.test.name << std::setw(9) << a.test.source << std::setw(42)
        << a.test.thesis << std::right << std::setw(10) << seconds(a.test.thesis_settle) << std::setw(10)
        << seconds(f.settle) << std::fixed << std::setprecision(2) << std::setw(12) << f.final_lateral * 100.0
        << std::setw(9) << f.final_heading / kDeg << std::setw(17) << peaks.str() << std::setw(8)
        << met(a.within_target) << '\n';
  }
}

void print_markers(std::ostream& out, const eval::PickEvalResult& r) {
  const auto& m = r.markers;
  const auto& p = r.params.markers;
  out << "2. marker localization error against distance [Picker thesis, Experiment 1, Tables 2-3]: Axis PTZ, "
      << p.markers << " markers x " << p.frames << " frames per distance at " << std::setprecision(1) << p.speed
      << " m/s\n"
      << "   thesis: below " << m.thesis_error * 100.0 << " cm up to about " << m.thesis_distance << " m, close to "
      << m.thesis_far_error << " m near " << m.thesis_far_distance << " m [Fig. 4.7]; target: range p95 below "
      << m.thesis_error * 100.0 << " cm up to " << m.thesis_distance << " m\n"
      << "   " << std::setw(7) << "dist m" << std::setw(10) << "read" << std::setw(15) << "range med cm"
      << std::setw(12) << "p95 cm" << std::setw(18) << "position med cm" << std::setw(12) << "p95 cm" << '\n';
  for (const auto& row : m.rows) {
    out << "   " << std::setprecision(1) << std::setw(7) << row.distance << std::setw(6) << row.detected << '/'
        << std::left << std::setw(3) << row.frames << std::right << std::setw(15) << row.range_median * 100.0
        << std::setw(12) << row.range_p95 * 100.0 << std::setw(18) << row.position_median * 100.0 << std::setw(12)
        << row.position_p95 * 100.0 << '\n';
  }
  out << "   worst range p95 up to " << m.thesis_distance << " m: " << m.worst_range_p95 * 100.0 << " cm ("
      << met(m.within_target) << ")\n";
}

void print_reasons(std::ostream& out, const std::map<std::string, int>& reasons) {
  for (const auto& [reason, n] : reasons) out << "     " << n << " x " << reason << '\n';
}

void print_picks(std::ostream& out, const eval::PickEvalResult& r) {
  const auto& p = r.picks;
  out << "3. pick cycle [Picker thesis, section 4.4, Algorithm 4]: " << r.params.pick_trials
      << " single-box picks over the plant's box stocks, each from a random slot of its pallet's near edge on a "
         "layer its count fills, then put down\n"
      << std::setprecision(1) << "   thesis: about " << p.thesis_pick
      << " s per simulated pick [section 5.3.3.1.2]; target: per box p95 <= " << p.thesis_pick
      << " s, success >= " << p.target_success * 100.0 << " %\n"
      << "   " << std::left << std::setw(7) << "place" << std::setw(6) << "item" << std::right << std::setw(6) << "kg"
      << std::setw(8) << "layers" << std::setw(8) << "picked" << std::setw(14) << "per box med s" << std::setw(8)
      << "p95 s" << std::setw(13) << "drop med s" << '\n';
  for (const auto& s : p.stocks) {
    out << "   " << std::left << std::setw(7) << s.place << std::setw(6) << s.item << std::right << std::setw(6)
        << s.mass << std::setw(8) << s.layers << std::setw(5) << s.successes << '/' << std::left << std::setw(2)
        << s.trials << std::right << std::setw(14) << s.per_box_median << std::setw(8) << s.per_box_p95 << std::setw(13)
        << s.drop_median << (s.pickable ? "" : "  (over the pickers' max)") << '\n';
  }
  out << "   by place on the pallet (slot 0 in front of the arm, 1 ahead, 2 behind; layer 0 on the pallet):";
  for (const auto& pos : p.positions) {
    out << "  " << pos.slot << '/' << pos.layer << ": " << pos.successes << " of " << pos.trials;
  }
  out << '\n';
  out << "   boxes up to " << p.max_box_mass << " kg: " << p.successes << " of " << p.trials << " picked ("
      << std::setprecision(2) << p.success_rate * 100.0 << " %)" << std::setprecision(1) << "; per box median "
      << p.per_box_median << " s, p95 " << p.per_box_p95 << " s, max " << p.per_box_max << " s; put down median "
      << p.drop_median << " s, p95 " << p.drop_p95 << " s (" << met(p.within_target) << ")\n";
  if (!p.refusals.empty()) {
    out << "   refused:\n";
    print_reasons(out, p.refusals);
  }
  if (p.heavy_trials > 0) {
    out << "   boxes over " << p.max_box_mass << " kg (pick lines may not ask for them): " << p.heavy_trials
        << " picks tried\n";
    print_reasons(out, p.heavy_refusals);
  }
}

void print_job(std::ostream& out, const eval::PickEvalResult& r) {
  const auto& j = r.job;
  out << "4. job cycle of one picker: " << j.pick_list << ", " << j.lines << " lines, " << j.boxes << " boxes, "
      << j.tours.size() << " tours, dropped at " << j.drop_place << '\n'
      << "   thesis: one job of pick and drop about " << j.thesis_cycle / 60.0
      << " min [section 5.3.3.1.3]; target: every tour <= " << j.thesis_cycle / 60.0
      << " min, >= " << j.target_items_per_hour << " items/h (IAM Robotics' published rate)\n"
      << "   " << std::setw(4) << "tour"
      << "  " << std::left << std::setw(14) << "places" << std::right << std::setw(6) << "boxes" << std::setw(11)
      << "travel m" << std::setw(11) << "travel s" << std::setw(9) << "pick s" << std::setw(9) << "drop s"
      << std::setw(10) << "cycle s" << '\n';
  for (std::size_t i = 0; i < j.tours.size(); ++i) {
    const auto& t = j.tours[i];
    std::string places;
    for (const auto& p : t.places) places += (places.empty() ? "" : ",") + p;
    out << "   " << std::setw(4) << i + 1 << "  " << std::left << std::setw(14) << places << std::right << std::setw(6)
        << t.boxes << std::setw(11) << t.travel_distance << std::setw(11) << t.travel_time << std::setw(9)
        << t.pick_time << std::setw(9) << t.drop_time << std::setw(10) << t.cycle_time << '\n';
    if (!t.ok) out << "         not delivered: " << t.reason << '\n';
  }
  out << "   tour cycle median " << j.cycle_median << " s (" << j.cycle_median / 60.0 << " min), max " << j.cycle_max
      << " s (" << j.cycle_max / 60.0 << " min); " << j.delivered << " boxes in " << j.total_time
      << " s: " << j.items_per_hour << " items/h (" << met(j.within_target) << ")\n"
      << "   per delivered box: arm " << j.arm_per_box << " s (alone, with no driving: " << j.arm_bound_items_per_hour
      << " items/h), driving " << j.travel_per_box
      << " s (alone, with an arm that took no time: " << j.travel_bound_items_per_hour
      << " items/h); a tour carries at most " << j.tour_capacity << " boxes\n"
      << "   assumptions:\n";
  for (const auto& a : j.assumptions) out << "     - " << a << '\n';
}

void print_loader(std::ostream& out, const eval::PickEvalResult& r) {
  const auto& l = r.loader;
  out << "5. the loader with a transporter behind it [section 4.3.3.1, not built by the thesis]: the same list, "
      << l.deck.size() << " places on the transporter's pallet, " << l.runs << " transporters filled\n";
  if (l.deck.empty()) {
    out << "   the arm reaches no place behind the base\n";
    return;
  }
  out << "   " << l.delivered << " of " << l.boxes << " boxes in " << l.total_time << " s: arm " << l.arm_time << " s ("
      << l.arm_per_box << " s a box), driving " << l.travel_time << " s, transporters moving up " << l.swap_time
      << " s: " << l.items_per_hour << " items/h (target " << l.target_items_per_hour << ": "
      << (l.items_per_hour >= l.target_items_per_hour ? "met" : "missed") << ")\n";
  for (const auto& f : l.failures) out << "   refused: " << f << '\n';
  out << "   assumptions:\n";
  for (const auto& a : l.assumptions) out << "     - " << a << '\n';
}

nlohmann::json loader_json(const eval::LoaderCycleResult& l) {
  nlohmann::json deck = nlohmann::json::array();
  for (const auto& p : l.deck) deck.push_back({p.x(), p.y(), p.z()});
  return {{"deck", deck},
          {"runs", l.runs},
          {"boxes", l.boxes},
          {"delivered", l.delivered},
          {"arm_s", l.arm_time},
          {"arm_s_per_box", l.arm_per_box},
          {"travel_s", l.travel_time},
          {"swap_s", l.swap_time},
          {"swap_m", l.swap_distance},
          {"total_s", l.total_time},
          {"items_per_hour", l.items_per_hour},
          {"target_items_per_hour", l.target_items_per_hour},
          {"failures", l.failures},
          {"assumptions", l.assumptions}};
}

nlohmann::json aisle_json(const eval::PickEvalResult& r) {
  nlohmann::json tests = nlohmann::json::array();
  for (const auto& a : r.aisle) {
    const auto& f = a.figures;
    tests.push_back({{"test", a.test.name},
                     {"source", a.test.source},
                     {"thesis", a.test.thesis},
                     {"thesis_settle_s", number_or_null(a.test.thesis_settle)},
                     {"settle_s", number_or_null(f.settle)},
                     {"lateral_5cm_s", number_or_null(f.lateral_5cm)},
                     {"heading_1deg_s", number_or_null(f.heading_1deg)},
                     {"final_lateral_m", f.final_lateral},
                     {"final_heading_deg", f.final_heading / kDeg},
                     {"final_along_m", f.final_along},
                     {"peak_lateral_mps", f.peak_lateral},
                     {"peak_forward_mps", f.peak_forward},
                     {"peak_yaw_rate_radps", f.peak_yaw_rate},
                     {"within_target", a.within_target}});
  }
  return {{"target",
           {{"final_lateral_m", r.aisle_targets.final_lateral},
            {"final_heading_deg", r.aisle_targets.final_heading / kDeg}}},
          {"tests", tests}};
}

nlohmann::json markers_json(const eval::MarkerSweepResult& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& row : m.rows) {
    rows.push_back({{"distance_m", row.distance},
                    {"frames", row.frames},
                    {"detected", row.detected},
                    {"range_median_m", row.range_median},
                    {"range_p95_m", row.range_p95},
                    {"position_median_m", row.position_median},
                    {"position_p95_m", row.position_p95}});
  }
  return {{"thesis",
           {{"error_m", m.thesis_error},
            {"up_to_m", m.thesis_distance},
            {"far_error_m", m.thesis_far_error},
            {"far_distance_m", m.thesis_far_distance}}},
          {"worst_range_p95_m", m.worst_range_p95},
          {"within_target", m.within_target},
          {"rows", rows}};
}

nlohmann::json picks_json(const eval::PickCycleResult& p) {
  nlohmann::json stocks = nlohmann::json::array();
  for (const auto& s : p.stocks) {
    stocks.push_back({{"place", s.place},
                      {"item", s.item},
                      {"mass_kg", s.mass},
                      {"pickable", s.pickable},
                      {"layers", s.layers},
                      {"trials", s.trials},
                      {"successes", s.successes},
                      {"per_box_median_s", s.per_box_median},
                      {"per_box_p95_s", s.per_box_p95},
                      {"drop_median_s", s.drop_median}});
  }
  nlohmann::json positions = nlohmann::json::array();
  for (const auto& pos : p.positions) {
    positions.push_back(
        {{"slot", pos.slot}, {"layer", pos.layer}, {"trials", pos.trials}, {"successes", pos.successes}});
  }
  return {{"max_box_mass_kg", p.max_box_mass},
          {"trials", p.trials},
          {"successes", p.successes},
          {"success_rate", p.success_rate},
          {"per_box_median_s", p.per_box_median},
          {"per_box_p95_s", p.per_box_p95},
          {"per_box_max_s", p.per_box_max},
          {"drop_median_s", p.drop_median},
          {"drop_p95_s", p.drop_p95},
          {"refusals", p.refusals},
          {"heavy_trials", p.heavy_trials},
          {"heavy_refusals", p.heavy_refusals},
          {"thesis_pick_s", p.thesis_pick},
          {"target_success", p.target_success},
          {"within_target", p.within_target},
          {"stocks", stocks},
          {"positions", positions}};
}

nlohmann::json job_json(const eval::JobCycleResult& j) {
  nlohmann::json tours = nlohmann::json::array();
  for (const auto& t : j.tours) {
    nlohmann::json legs = nlohmann::json::array();
    for (const auto& l : t.legs) {
      legs.push_back({{"from", l.from}, {"to", l.to}, {"distance_m", number_or_null(l.distance)}, {"time_s", l.time}});
    }
    nlohmann::json tour{{"places", t.places},
                        {"boxes", t.boxes},
                        {"legs", legs},
                        {"travel_m", number_or_null(t.travel_distance)},
                        {"travel_s", number_or_null(t.travel_time)},
                        {"pick_s", t.pick_time},
                        {"drop_s", t.drop_time},
                        {"cycle_s", number_or_null(t.cycle_time)},
                        {"ok", t.ok}};
    if (!t.ok) tour["reason"] = t.reason;
    tours.push_back(tour);
  }
  return {{"pick_list", j.pick_list},
          {"drop_place", j.drop_place},
          {"fleet", j.fleet},
          {"max_speed_mps", j.max_speed},
          {"max_acceleration_mps2", j.max_acceleration},
          {"lines", j.lines},
          {"boxes", j.boxes},
          {"delivered", j.delivered},
          {"cycle_median_s", j.cycle_median},
          {"cycle_max_s", j.cycle_max},
          {"total_s", j.total_time},
          {"items_per_hour", j.items_per_hour},
          {"arm_s_per_box", j.arm_per_box},
          {"travel_s_per_box", j.travel_per_box},
          {"arm_bound_items_per_hour", j.arm_bound_items_per_hour},
          {"travel_bound_items_per_hour", j.travel_bound_items_per_hour},
          {"tour_capacity", j.tour_capacity},
          {"thesis_cycle_s", j.thesis_cycle},
          {"target_items_per_hour", j.target_items_per_hour},
          {"within_target", j.within_target},
          {"assumptions", j.assumptions},
          {"tours", tours}};
}

}  // namespace

int pick_eval_command(const CommandArgs& args, std::ostream& out, std::ostream& err) {
  const CommandFlags flags("pick-eval", "", args.args);
  if (flags.asks_for_usage()) {
    out << flags.usage();
    return kExitOk;
  }
  eval::PickEvalParams params;
  params.files = eval::plant_pick_eval_files(args.source_dir);
  const bool json = args.json;
  params.seed = flags.u64("seed").value_or(params.seed);
  params.drop_place = flags.value("drop").value_or("");

  eval::PickEvalResult r;
  try {
    r = eval::run_pick_eval(params);
  } catch (const InputError& e) {
    err << "pick-eval: " << e.what() << '\n';
    return kExitBadInput;
  } catch (const std::exception& e) {
    err << "pick-eval: " << e.what() << '\n';
    return kExitFailed;
  }

  out << "pick-eval: seed " << params.seed << ", the picker of [Picker thesis] on core/ alone\n";
  print_aisle(out, r);
  print_markers(out, r);
  print_picks(out, r);
  print_job(out, r);
  print_loader(out, r);
  out << "targets: " << (r.within_targets() ? "all met" : "some MISSED (exit 1)") << '\n';

  if (json) {
    nlohmann::json j{{"seed", params.seed},
                     {"aisle", aisle_json(r)},
                     {"markers", markers_json(r.markers)},
                     {"picks", picks_json(r.picks)},
                     {"job", job_json(r.job)},
                     {"loader", loader_json(r.loader)},
                     {"within_targets", r.within_targets()}};
    out << j.dump() << '\n';
  }
  // A target missed makes the run a failure, as dock-eval's.
  return r.within_targets() ? kExitOk : kExitFailed;
}

}  // namespace fleet::cli
