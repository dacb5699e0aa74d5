#include "eval/ctrl_eval.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <random>
#include <sstream>
#include <stdexcept>

#include "common/percentile.hpp"
#include "control/pallet_search.hpp"
#include "map/site_map.hpp"
#include "perception/pallet_world.hpp"
#include "planning/road_planner.hpp"
#include "planning/route_planner.hpp"
#include "robot/forklift/simulated_forklift.hpp"

namespace fleet::eval {

using geometry::Pose2;
using geometry::Vec2;

namespace {

/// Independent, reproducible engine per noise source (same construction as loc-eval).

/// The simulated forklift of an agent (core/robot), set up from the evaluation's parameters.
robot::SimulatedForklift make_robot(const CtrlEvalParams& p, const map::Site& site, const Pose2& start, bool perfect,
                                    std::uint64_t stream) {
  robot::SimulatedForkliftParams sp;
  sp.forklift = p.forklift;
  sp.uwb = p.uwb;
  sp.gyro = p.gyro;
  sp.ekf = p.ekf;
  sp.known_start_heading = true;  // the evaluation measures control, not heading initialisation
  sp.gyro_standstill_calibration = p.gyro_standstill_calibration;
  sp.perfect_localization = perfect;
  return robot::SimulatedForklift(sp, site, start, p.seed, stream);
}

Percentiles percentiles(std::vector<double> v) {
  Percentiles p;
  if (v.empty()) return p;
  p.p50 = common::percentile(v, 0.50);
  p.p95 = common::percentile(v, 0.95);
  p.max = *std::max_element(v.begin(), v.end());
  return p;
}

struct OrderStats {
  std::vector<OrderRun> orders;
  Percentiles place_error;
  Percentiles place_yaw_error;
  int picks = 0;
  int places = 0;
  double pick_success = 0.0;
};

struct Accum {
  double sum2 = 0.0;
  double max = 0.0;
  long n = 0;
  void add(double e) {
    sum2 += e * e;
    max = std::max(max, std::abs(e));
    ++n;
  }
  double rms() const { return n > 0 ? std::sqrt(sum2 / static_cast<double>(n)) : 0.0; }
};

TrackingRun track(const CtrlEvalParams& p, const map::Site& site, const NamedPath& path, bool regulated, bool perfect,
                  std::uint64_t stream) {
  TrackingRun r;
  r.path = path.name;
  r.follower = regulated ? "regulated" : "seed";
  r.localization = perfect ? "perfect" : "ekf";
  control::FollowerParams fp = regulated ? p.regulated_follower : p.seed_follower;
  fp.v_max = p.speed;
  control::PathFollower follower(fp);
  const double dt = 1.0 / p.control_rate_hz;
  robot::SimulatedForklift robot = make_robot(p, site, path.poses.front(), perfect, stream);
  robot.warm_up(2.0, dt);
  follower.set_path(path.poses);
  for (std::size_t i = 1; i < path.poses.size(); ++i) {
    r.length += geometry::distance(path.poses[i - 1].position(), path.poses[i].position());
  }
  Accum cross;
  Accum loc;
  control::BodyTwist prev;
  r.path_poses = path.poses;
  long step_count = 0;
  const double t0 = robot.time();
  const double limit = r.length / 0.03 + 30.0;
  bool first = true;
  while (robot.time() - t0 < limit) {
    const Pose2 est = robot.estimate();
    const control::BodyTwist cmd = follower.step({est, first ? 0.0 : dt});
    if (follower.arrived()) {
      r.arrived = true;
      break;
    }
    if (!first && follower.status() == control::FollowerStatus::kTracking) {
      r.omega_jump_max = std::max(r.omega_jump_max, std::abs(cmd.omega - prev.omega));
    }
    first = false;
    prev = cmd;
    robot.step(cmd, dt);
    if (follower.status() == control::FollowerStatus::kTracking) {
      cross.add(distance_to_path(path.poses, robot.truth().position()));
    }
    loc.add(geometry::distance(robot.truth().position(), robot.estimate().position()));
    if (step_count++ % 7 == 0) {
      r.truth_track.push_back(robot.truth());
      r.estimate_track.push_back(robot.estimate());
    }
  }
  r.duration = robot.time() - t0;
  r.cross_track_rms = cross.rms();
  r.cross_track_max = cross.max;
  r.loc_rms = loc.rms();
  return r;
}

/// N orders one after another with one robot, the pallets staying where they are put.
OrderStats run_orders(const CtrlEvalParams& params, const map::SiteMap& sm, bool perfect) {
  OrderStats stats;
  const map::Site& site = sm.site;
  if (site.homes.empty()) throw std::invalid_argument("ctrl-eval: site has no home");
  if (site.loading_areas.size() < 2) throw std::invalid_argument("ctrl-eval: site needs two loading areas");
  const double dt = 1.0 / params.control_rate_hz;
  std::mt19937_64 rng = robot::seeded_engine(params.seed, 7);
  std::normal_distribution<double> gauss(0.0, 1.0);

  task::ExecutorParams tp = params.task;
  tp.follower = params.use_regulated ? params.regulated_follower : params.seed_follower;
  tp.follower.v_max = params.speed;
  perception::PalletWorldParams wp;
  wp.carry_x = tp.geometry.carry_x;
  wp.marker_offset = tp.geometry.marker_offset;
  perception::PalletWorld world(wp);
  perception::MarkerCameraParams cp = params.camera;
  cp.camera_x = tp.geometry.camera_x;
  perception::MarkerCamera camera(cp, params.seed * 7919 + 11);

  // Pallet id -> the area it stands on.
  std::map<int, std::size_t> pallet_area;
  auto jittered = [&](const Pose2& a) {
    return Pose2{a.x + params.pallet_jitter * gauss(rng), a.y + params.pallet_jitter * gauss(rng),
                 geometry::normalize_angle(a.yaw + params.pallet_yaw_jitter * gauss(rng))};
  };
  for (std::size_t i = 0; i < site.loading_areas.size(); ++i) {
    if (site.loading_areas[i].pallet_at_start) pallet_area[world.add(jittered(site.loading_areas[i].pose))] = i;
  }
  if (pallet_area.empty()) pallet_area[world.add(jittered(site.loading_areas[0].pose))] = 0;

  const Pose2 home = site.homes.front().pose;
  robot::SimulatedForklift robot = make_robot(params, site, home, perfect, perfect ? 101 : 1);
  robot.warm_up(2.0, dt);
  task::TaskExecutor exec(tp, home);
  planning::RoadPlanner planner(sm.graph.graph);

  for (int run = 0; run < params.runs; ++run) {
    // A random standing pallet to a random free area.
    std::vector<int> ids;
    for (const auto& [id, area] : pallet_area) ids.push_back(id);
    const int pallet_id = ids[std::uniform_int_distribution<std::size_t>(0, ids.size() - 1)(rng)];
    const std::size_t from = pallet_area[pallet_id];
    std::vector<std::size_t> free;
    for (std::size_t i = 0; i < site.loading_areas.size(); ++i) {
      bool taken = false;
      for (const auto& [id, area] : pallet_area) taken = taken || area == i;
      if (!taken) free.push_back(i);
    }
    if (free.empty()) throw std::invalid_argument("ctrl-eval: every loading area holds a pallet");
    const std::size_t to = free[std::uniform_int_distribution<std::size_t>(0, free.size() - 1)(rng)];
    const auto& a_from = site.loading_areas[from];
    const auto& a_to = site.loading_areas[to];

    OrderRun o;
    o.pick_area = a_from.id;
    o.drop_area = a_to.id;
    std::string why;
    if (!exec.submit({"eval-" + std::to_string(run + 1), a_from.id, a_from.pose, a_to.id, a_to.pose}, &why)) {
      throw std::logic_error("ctrl-eval: order refused: " + why);
    }
    const double t0 = robot.time();
    bool finished = false;
    while (!finished && robot.time() - t0 < params.order_timeout) {
      const Pose2 est = robot.estimate();
      std::vector<perception::MarkerDetection> dets;
      if (camera.frame_due(robot.time())) {
        const auto markers = world.markers();
        dets = camera.capture(robot.time(), robot.truth(), markers);
      }
      const task::TaskOutput out = exec.step({robot.time(), est, dets});
      const perception::ForkEvent ev = world.update(0, robot.truth(), out.fork_up);
      if (ev.kind == perception::ForkEvent::Kind::kLifted) {
        o.picked = ev.pallet_id == pallet_id;
        o.pick_offset_lateral = ev.offset.y;
        o.pick_offset_yaw = geometry::angle_diff(ev.offset.yaw, std::numbers::pi);
        if (!o.picked) o.failure = "lifted the wrong pallet";
      } else if (ev.kind == perception::ForkEvent::Kind::kLiftMissed) {
        o.failure = "forks rose under no pallet";
      } else if (ev.kind == perception::ForkEvent::Kind::kPutDown) {
        const perception::SimPallet* pl = world.find(ev.pallet_id);
        o.placed = true;
        o.place_error = geometry::distance(pl->pose.position(), a_to.pose.position());
        o.place_yaw_error = std::abs(geometry::angle_diff(pl->pose.yaw, a_to.pose.yaw));
        o.loc_error_at_drop = geometry::distance(est.position(), robot.truth().position());
        o.loc_yaw_error_at_drop = geometry::angle_diff(est.yaw, robot.truth().yaw);
        pallet_area[ev.pallet_id] = to;
      }
      robot.step(out.twist, dt);
      if (auto req = exec.take_plan_request()) {
        const planning::RoadPlan plan = planner.plan(robot.estimate(), req->goal);
        if (plan.status == planning::PlanStatus::kFound && !plan.points.empty()) {
          exec.path_received(req->id, planning::poses_along(plan.points));
        } else {
          exec.plan_failed(req->id);
        }
      }
      for (const task::TaskReport& rep : exec.take_reports()) {
        using K = task::TaskReport::Kind;
        if (rep.kind == K::kPicked) o.reported_picked = true;
        if (rep.kind == K::kDropped || rep.kind == K::kAreaEmpty) finished = true;
        if (rep.kind == K::kAreaEmpty && o.failure.empty()) o.failure = "area reported empty";
        if (rep.kind == K::kFailed) {
          finished = true;
          if (o.failure.empty()) o.failure = rep.detail;
        }
      }
    }
    o.duration = robot.time() - t0;
    if (!finished && o.failure.empty()) o.failure = "order timed out in " + std::string(task::to_string(exec.state()));
    if (exec.state() == task::State::kError || !finished) {
      // Start the next order from a clean slate; a pallet left on the forks goes back to its area.
      if (exec.carrying() || !finished) {
        exec.fault("evaluation reset");
      }
      exec.reset();
    }
    for (const perception::SimPallet& pl : world.pallets()) {
      if (pl.carried) {
        // Only after a failed order: put it down where it is and let it count as standing there.
        world.update(0, robot.truth(), false);
      }
    }
    if (o.picked) ++stats.picks;
    if (o.placed && o.picked) ++stats.places;
    stats.orders.push_back(std::move(o));
  }
  std::vector<double> pos;
  std::vector<double> yaw;
  for (const OrderRun& o : stats.orders) {
    if (!(o.placed && o.picked)) continue;
    pos.push_back(o.place_error);
    yaw.push_back(o.place_yaw_error * 180.0 / std::numbers::pi);
  }
  stats.place_error = percentiles(pos);
  stats.place_yaw_error = percentiles(yaw);
  stats.pick_success = static_cast<double>(stats.picks) / params.runs;
  return stats;
}

}  // namespace

double distance_to_path(const std::vector<Pose2>& path, Vec2 p) {
  if (path.empty()) return std::numeric_limits<double>::infinity();
  double best = geometry::distance(path.front().position(), p);
  for (std::size_t i = 1; i < path.size(); ++i) {
    const Vec2 a = path[i - 1].position();
    const Vec2 ab = path[i].position() - a;
    const double len2 = geometry::dot(ab, ab);
    const double t = len2 > 0.0 ? std::clamp(geometry::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
    best = std::min(best, geometry::distance(a + t * ab, p));
  }
  return best;
}

std::vector<NamedPath> standard_paths(const std::string& site_file) {
  const map::SiteMap sm = map::load_site_map(site_file);
  planning::RoadPlanner planner(sm.graph.graph);
  std::vector<std::pair<std::string, std::vector<Pose2>>> routes;
  if (sm.site.name == "table_a") {
    // Way-points on the lane centres of table_a's roads (ring at 0.45 / 2.55, cross at 1.5).
    routes = {
        {"ring_lap", {{0.75, 0.45, 0.0}, {2.55, 0.75, 0.0}, {2.25, 2.55, 0.0}, {0.45, 2.25, 0.0}, {0.45, 0.75, 0.0}}},
        {"cross_turns",
         {{0.75, 0.45, 0.0},
          {1.5, 1.05, 0.0},
          {2.1, 1.5, 0.0},
          {2.55, 2.1, 0.0},
          {1.95, 2.55, 0.0},
          {1.5, 1.95, 0.0},
          {0.9, 1.5, 0.0}}},
    };
  } else {
    // Any other site: one route visiting the road in front of each loading area in turn.
    std::vector<Pose2> tour;
    for (const auto& area : sm.site.loading_areas) tour.push_back(control::PalletSearch::search_pose(area.pose, 0.30));
    if (tour.size() < 2) throw std::invalid_argument("ctrl-eval: " + site_file + " has fewer than two loading areas");
    routes = {{"area_tour", tour}};
  }
  std::vector<NamedPath> out;
  for (const auto& [name, waypoints] : routes) {
    std::vector<Vec2> points;
    for (std::size_t i = 1; i < waypoints.size(); ++i) {
      const planning::RoadPlan plan = planner.plan(waypoints[i - 1], waypoints[i]);
      if (plan.status != planning::PlanStatus::kFound) {
        throw std::invalid_argument("ctrl-eval: no route for standard path '" + name + "' in " + site_file);
      }
      for (const Vec2& q : plan.points) {
        if (points.empty() || geometry::distance(points.back(), q) > 1e-6) points.push_back(q);
      }
    }
    out.push_back({name, planning::poses_along(points)});
  }
  return out;
}

std::string ctrl_eval_svg(const CtrlEvalResult& result) {
  const double scale = 200.0;  // px per metre
  const double header = 60.0;
  double min_x = 0.0, min_y = 0.0, max_x = 3.0, max_y = 3.0;
  for (const TrackingRun& t : result.tracking) {
    for (const Pose2& p : t.path_poses) {
      min_x = std::min(min_x, p.x - 0.3);
      min_y = std::min(min_y, p.y - 0.3);
      max_x = std::max(max_x, p.x + 0.3);
      max_y = std::max(max_y, p.y + 0.3);
    }
  }
  const double w = std::max((max_x - min_x) * scale, 700.0);  // room for the title
  const double h = (max_y - min_y) * scale + header;
  auto num = [](double v) {
    std::ostringstream os;
    os << std::fixed << std::setprecision(1) << v;
    return os.str();
  };
  auto points = [&](const std::vector<Pose2>& poses) {
    std::ostringstream os;
    for (const Pose2& p : poses) os << num((p.x - min_x) * scale) << ',' << num(header + (max_y - p.y) * scale) << ' ';
    return os.str();
  };
  auto polyline = [&](const std::vector<Pose2>& poses, const std::string& colour, double width) {
    return "<polyline fill=\"none\" stroke-linejoin=\"round\" stroke=\"" + colour + "\" stroke-width=\"" + num(width) +
           "\" points=\"" + points(poses) + "\"/>\n";
  };
  const std::string follower = result.params.use_regulated ? "regulated" : "seed";
  std::ostringstream os;
  os << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << num(w) << "\" height=\"" << num(h)
     << "\" font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  os << "<text x=\"8\" y=\"18\" font-size=\"14\">ctrl-eval: " << follower << " follower with the EKF, seed "
     << result.params.seed << ", cross-track rms " << num(result.cross_track_rms * 100.0) << " cm, max "
     << num(result.cross_track_max * 100.0) << " cm</text>\n";
  os << "<text x=\"8\" y=\"40\"><tspan fill=\"#ccc\">&#9632;</tspan> road, 30 cm   <tspan fill=\"black\">&#9632;"
        "</tspan> true track   <tspan fill=\"#1f77b4\">&#9632;</tspan> EKF estimate</text>\n";
  for (const TrackingRun& t : result.tracking) {
    if (t.follower != follower || t.localization != "ekf") continue;
    os << polyline(t.path_poses, "#e4e4e4", 0.30 * scale) << polyline(t.path_poses, "#999", 0.8)
       << polyline(t.estimate_track, "#1f77b4", 1.0) << polyline(t.truth_track, "black", 1.5);
  }
  os << "</svg>\n";
  return os.str();
}

CtrlEvalResult run_ctrl_eval(const CtrlEvalParams& params) {
  if (params.runs < 0) throw std::invalid_argument("ctrl-eval: runs must be >= 0");
  if (!(params.speed > 0.0)) throw std::invalid_argument("ctrl-eval: speed must be > 0");
  if (params.site_file.empty()) throw std::invalid_argument("ctrl-eval: no site file");
  CtrlEvalResult result;
  result.params = params;
  const map::SiteMap sm = map::load_site_map(params.site_file);
  const map::Site& site = sm.site;

  // --- path tracking with perfect localization [Forklift thesis, Fig. 6.4] and with the EKF [Forklift thesis,
  // Fig. 6.5] ---
  const auto paths = standard_paths(params.site_file);
  std::uint64_t stream = 1000;
  Accum headline;
  Accum headline_perfect;
  for (const NamedPath& path : paths) {
    for (bool regulated : {false, true}) {
      for (bool perfect : {true, false}) {
        TrackingRun r = track(params, site, path, regulated, perfect, stream);
        stream += 10;
        if (regulated == params.use_regulated) {
          Accum& h = perfect ? headline_perfect : headline;
          // Combine runs by their sums of squares, weighted by duration (samples at a fixed rate).
          const double n = r.duration * params.control_rate_hz;
          h.sum2 += r.cross_track_rms * r.cross_track_rms * n;
          h.n += static_cast<long>(n);
          h.max = std::max(h.max, r.cross_track_max);
        }
        result.tracking.push_back(std::move(r));
      }
    }
  }
  result.cross_track_rms = headline.rms();
  result.cross_track_max = headline.max;
  result.cross_track_rms_perfect = headline_perfect.rms();
  result.cross_track_max_perfect = headline_perfect.max;

  // --- pick and drop, with the EKF and, to separate control from localization, perfect ---
  if (params.runs > 0) {
    OrderStats ekf = run_orders(params, sm, false);
    OrderStats perfect = run_orders(params, sm, true);
    result.orders = std::move(ekf.orders);
    result.place_error = ekf.place_error;
    result.place_yaw_error = ekf.place_yaw_error;
    result.picks = ekf.picks;
    result.places = ekf.places;
    result.pick_success = ekf.pick_success;
    result.perfect_place_error = perfect.place_error;
    result.perfect_place_yaw_error = perfect.place_yaw_error;
    result.perfect_pick_success = perfect.pick_success;
  }
  return result;
}

}  // namespace fleet::eval
