#include "eval/aisle_eval.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "aisle/hough_lines.hpp"
#include "aisle/rack_aisle_sim.hpp"
#include "geometry/polygon.hpp"
#include "geometry/pose.hpp"

namespace fleet::eval {

namespace {

constexpr double kPi = std::numbers::pi;
using ::fleet::geometry::kDeg;
constexpr double kNotStated = std::numeric_limits<double>::quiet_NaN();

}  // namespace

AisleRun run_aisle(const std::vector<PickerSetup>& setups, double duration, std::uint64_t seed) {
  const aisle::RackAisle rack_aisle;
  std::vector<sim::ForkliftBody> bodies;
  // The plant the thesis designed and ran the aisle laws on: first order, τ = 0.02 s [Picker thesis, eq. 4.29]. The
  // Summit-XLS default follows the measured step of Fig. 4.27 (τ = 0.075 s), on which Test III settles in ~12 s.
  sim::ForkliftParams body_params = sim::summit_xls_body_params();
  body_params.wheel_time_constant = 0.02;
  std::vector<aisle::PickerLidars> lidars;
  std::vector<aisle::RackLineDetector> detectors;
  std::vector<aisle::AisleFollower> followers;
  AisleRun result;
  for (std::size_t i = 0; i < setups.size(); ++i) {
    const PickerSetup& s = setups[i];
    bodies.emplace_back(body_params, s.start, std::mt19937_64(seed + 17 * i));
    lidars.emplace_back(aisle::picker_lidar_mounts(), 0.02, std::mt19937_64(seed + 17 * i + 1));
    detectors.emplace_back();
    followers.emplace_back(s.follower);
    followers.back().start(s.distance);
    PickerTrace trace;
    trace.setup = s;
    trace.travel_yaw = std::abs(s.start.yaw) < kPi / 2.0 ? 0.0 : kPi;
    const bool right_face_low = (trace.travel_yaw == 0.0) == (s.follower.side == aisle::RackSide::kRight);
    trace.lateral_ref =
        right_face_low ? s.follower.reference_distance : rack_aisle.params().width - s.follower.reference_distance;
    result.traces.push_back(trace);
  }
  const int steps = static_cast<int>(std::lround(duration / kAisleControlPeriod));
  for (int k = 0; k < steps; ++k) {
    std::vector<sim::BodyTwist> commands(bodies.size());
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      std::vector<geometry::Polygon> others;  // the other pickers are obstacles to this one's lidars
      for (std::size_t j = 0; j < bodies.size(); ++j) {
        if (j != i) others.push_back(bodies[j].footprint_polygon());
      }
      const auto scans = lidars[i].scan(bodies[i].pose(), rack_aisle, others);
      const aisle::RackLinePair pair = detectors[i].detect(scans, lidars[i].mounts());
      // The encoders: what the wheels turn at, through the forward kinematics (slip makes it differ from the truth).
      const sim::BodyTwist odometry = bodies[i].kinematics().forward(bodies[i].wheel_speeds());
      commands[i] = followers[i].update(pair, odometry, kAisleControlPeriod);
      result.traces[i].lines_found.push_back(pair.found());
    }
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      bodies[i].step(commands[i], kAisleControlPeriod);
      PickerTrace& t = result.traces[i];
      t.time.push_back((k + 1) * kAisleControlPeriod);
      t.pose.push_back(bodies[i].pose());
      t.twist.push_back(bodies[i].twist());
    }
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      for (std::size_t j = i + 1; j < bodies.size(); ++j) {
        result.min_gap = std::min(result.min_gap, geometry::convex_polygons_distance(bodies[i].footprint_polygon(),
                                                                                     bodies[j].footprint_polygon()));
      }
    }
  }
  return result;
}

double lateral_error(const PickerTrace& t, std::size_t k) {
  return t.pose[k].y - t.lateral_ref;
}

double heading_error(const PickerTrace& t, std::size_t k) {
  return geometry::angle_diff(t.pose[k].yaw, t.travel_yaw);
}

double along(const PickerTrace& t, std::size_t k) {
  const double dx = t.pose[k].x - t.setup.start.x;
  return t.travel_yaw == 0.0 ? dx : -dx;
}

double settle_time(const PickerTrace& t, double lateral_tol, double heading_tol) {
  for (std::size_t k = t.time.size(); k-- > 0;) {
    if (std::abs(lateral_error(t, k)) > lateral_tol || std::abs(heading_error(t, k)) > heading_tol) {
      return k + 1 == t.time.size() ? std::numeric_limits<double>::infinity() : t.time[k];
    }
  }
  return 0.0;
}

AisleFigures aisle_figures(const PickerTrace& t) {
  AisleFigures f;
  f.settle = settle_time(t, 0.03, 1.0 * kDeg);
  f.lateral_5cm = f.heading_1deg = std::numeric_limits<double>::infinity();
  int lost = 0;
  for (std::size_t k = 0; k < t.time.size(); ++k) {
    if (std::abs(lateral_error(t, k)) <= 0.05) f.lateral_5cm = std::min(f.lateral_5cm, t.time[k]);
    if (std::abs(heading_error(t, k)) <= 1.0 * kDeg) f.heading_1deg = std::min(f.heading_1deg, t.time[k]);
    f.peak_lateral = std::max(f.peak_lateral, std::abs(t.twist[k].vy));
    f.peak_forward = std::max(f.peak_forward, std::abs(t.twist[k].vx));
    f.peak_yaw_rate = std::max(f.peak_yaw_rate, std::abs(t.twist[k].omega));
    if (!t.lines_found[k]) ++lost;
  }
  const std::size_t last = t.time.size() - 1;
  f.final_lateral = lateral_error(t, last);
  f.final_heading = heading_error(t, last);
  f.final_along = along(t, last) - t.setup.distance;
  f.lost_fraction = static_cast<double>(lost) / static_cast<double>(t.time.size());
  return f;
}

PickerSetup seed_aisle_setup(const std::string& name, geometry::Pose2 start, double distance) {
  PickerSetup s;
  s.name = name;
  s.start = start;
  s.distance = distance;
  return s;
}

std::vector<SeedAisleCase> seed_aisle_cases() {
  std::vector<SeedAisleCase> cases;
  // [Picker thesis, Table 7]: parallel to the racks, 1 m off d_ref, no travel along the aisle; the plots show the
  // lateral error of 1 m converging with lateral motion only [Picker thesis, Figs 4.48-4.50].
  cases.push_back({"I", "Table 7", seed_aisle_setup("I (1 m lateral shift)", {0.0, 2.0, 0.0}, 0.0), 8.0, 101,
                   "lateral motion only, converges (plots)", kNotStated});
  // [Picker thesis, Table 8]: (-2.5, 1.5) -> (2.5, 1.0), parallel; lateral ~0.2 m/s for ~4 s, forward up to 0.3 m/s
  // [Picker thesis, Fig. 4.55].
  cases.push_back({"II", "Table 8", seed_aisle_setup("II (-2.5,1.5)->(2.5,1.0)", {-2.5, 1.5, 0.0}, 5.0), 22.0, 202,
                   "lateral 0.2 m/s ~4 s, forward to 0.3 m/s", 4.0});
  // [Picker thesis, Table 9]: as II turned 25 deg; orientation and lateral converged in under 5 s
  // [Picker thesis, Figs 4.63-4.64]. The thesis ran one sense; both are run here.
  for (const double yaw : {25.0, -25.0}) {
    const std::string name = yaw > 0 ? "III +25" : "III -25";
    const std::string label = yaw > 0 ? "III (+25 deg)" : "III (-25 deg)";
    cases.push_back({name, "Table 9", seed_aisle_setup(label, {-2.5, 1.5, yaw * kDeg}, 5.0), 22.0, 303,
                     yaw > 0 ? "heading and lateral converged < 5 s" : "not run (the thesis turned one way)",
                     yaw > 0 ? 5.0 : kNotStated});
  }
  return cases;
}

SeedAisleCase seed_aisle_case(const std::string& name) {
  for (const SeedAisleCase& c : seed_aisle_cases()) {
    if (c.name == name) return c;
  }
  throw std::out_of_range("no seed aisle test named '" + name + "'");
}

std::vector<AisleTestResult> run_seed_aisle_tests(std::uint64_t seed, const AisleTargets& targets) {
  std::vector<AisleTestResult> results;
  for (const SeedAisleCase& c : seed_aisle_cases()) {
    AisleTestResult r;
    r.test = c;
    const AisleRun run = run_aisle({c.setup}, c.duration, c.seed + (seed - 1) * 1000);
    r.figures = aisle_figures(run.traces.front());
    r.within_target = std::abs(r.figures.final_lateral) <= targets.final_lateral &&
                      std::abs(r.figures.final_heading) <= targets.final_heading;
    results.push_back(r);
  }
  return results;
}

}  // namespace fleet::eval
