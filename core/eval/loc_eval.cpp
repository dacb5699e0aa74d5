#include "eval/loc_eval.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <numbers>
#include <random>
#include <sstream>
#include <stdexcept>

namespace fleet::eval {

namespace {

using geometry::Pose2;
using geometry::Vec2;
constexpr double kPi = std::numbers::pi;
constexpr double kRadToDeg = 180.0 / kPi;

// A closed reference loop sampled densely, looked up by arc length.
class ReferenceLoop {
 public:
  explicit ReferenceLoop(std::vector<Vec2> points) : points_(std::move(points)) {
    s_.push_back(0.0);
    for (std::size_t i = 1; i <= points_.size(); ++i) {
      s_.push_back(s_.back() + geometry::distance(points_[i - 1], points_[i % points_.size()]));
    }
  }

  double length() const { return s_.back(); }

  // Position, tangent heading and curvature at arc length s (wrapped onto the loop).
  Pose2 pose(double s, double* curvature) const {
    s = std::fmod(s, length());
    if (s < 0.0) s += length();
    const auto it = std::upper_bound(s_.begin(), s_.end(), s);
    const std::size_t i = static_cast<std::size_t>(std::max<std::ptrdiff_t>(it - s_.begin() - 1, 0));
    const std::size_t n = points_.size();
    const Vec2 a = points_[i % n];
    const Vec2 b = points_[(i + 1) % n];
    const double seg = s_[i + 1] - s_[i];
    const double f = seg > 0.0 ? (s - s_[i]) / seg : 0.0;
    const Vec2 p = a + f * (b - a);
    const double h0 = heading(i);
    const double h1 = heading(i + 1);
    const double yaw = h0 + f * geometry::angle_diff(h1, h0);
    if (curvature) {
      const double hp = heading(i + n - 1);
      const double ds = 0.5 * (s_[i + 1] - s_[i]) + 0.5 * (s_[i] - s_[(i + n - 1) % n]);
      *curvature = ds > 0.0 ? geometry::angle_diff(h1, hp) / (2.0 * ds) : 0.0;
    }
    return {p.x, p.y, geometry::normalize_angle(yaw)};
  }

 private:
  double heading(std::size_t i) const {
    const std::size_t n = points_.size();
    const Vec2 d = points_[(i + 1) % n] - points_[i % n];
    return std::atan2(d.y, d.x);
  }
  std::vector<Vec2> points_;
  std::vector<double> s_;
};

// Straight sides with quarter-circle corners, counter-clockwise, starting mid-way along the
// bottom side heading +x.
std::vector<Vec2> rounded_rectangle(double min_x, double min_y, double max_x, double max_y, double radius) {
  std::vector<Vec2> pts;
  const double step = 0.005;
  auto line = [&](Vec2 a, Vec2 b) {
    const int n = std::max(1, static_cast<int>(std::ceil(geometry::distance(a, b) / step)));
    for (int i = 0; i < n; ++i) pts.push_back(a + (static_cast<double>(i) / n) * (b - a));
  };
  auto arc = [&](Vec2 c, double from) {
    const int n = std::max(2, static_cast<int>(std::ceil(radius * kPi / 2.0 / step)));
    for (int i = 0; i < n; ++i) {
      const double a = from + (kPi / 2.0) * i / n;
      pts.push_back({c.x + radius * std::cos(a), c.y + radius * std::sin(a)});
    }
  };
  const double mid = 0.5 * (min_x + max_x);
  line({mid, min_y}, {max_x - radius, min_y});
  arc({max_x - radius, min_y + radius}, -kPi / 2.0);
  line({max_x, min_y + radius}, {max_x, max_y - radius});
  arc({max_x - radius, max_y - radius}, 0.0);
  line({max_x - radius, max_y}, {min_x + radius, max_y});
  arc({min_x + radius, max_y - radius}, kPi / 2.0);
  line({min_x, max_y - radius}, {min_x, min_y + radius});
  arc({min_x + radius, min_y + radius}, kPi);
  line({min_x + radius, min_y}, {mid, min_y});
  return pts;
}

ReferenceLoop make_loop(Trajectory t) {
  switch (t) {
    case Trajectory::kSquare:
      return ReferenceLoop(rounded_rectangle(0.5, 0.5, 2.5, 2.5, 0.25));
    case Trajectory::kTableALoop:
      // table_a's outer road loop (road centre lines about 0.4 m inside the 3 m table edge).
      return ReferenceLoop(rounded_rectangle(0.4, 0.4, 2.6, 2.6, 0.3));
    case Trajectory::kFigure8: {
      // Lissajous 1:2 figure of eight centred on the table. It starts at the crossing, heading
      // about 40 degrees: not the thesis's mandatory heading 0, so heading initialisation matters.
      std::vector<Vec2> pts;
      const int n = 4000;
      for (int i = 0; i < n; ++i) {
        const double phi = 2.0 * kPi * i / n;
        pts.push_back({1.5 + 1.1 * std::sin(phi), 1.5 + 0.45 * std::sin(2.0 * phi)});
      }
      return ReferenceLoop(std::move(pts));
    }
  }
  throw std::invalid_argument("unknown trajectory");
}

std::mt19937_64 engine(std::uint64_t seed, std::uint64_t stream) {
  std::seed_seq seq{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32),
                    static_cast<std::uint32_t>(stream)};
  return std::mt19937_64(seq);
}

enum class EventKind { kGyro, kUwb };

struct Event {
  EventKind kind = EventKind::kGyro;
  double t = 0.0;
  double gyro = 0.0;
  localization::BodyVelocity command;
  localization::BodyVelocity encoders;
  bool has_encoders = false;
  std::optional<sim::UwbFix> fix;
  Pose2 truth;
};

struct Accumulator {
  double pos_sq = 0.0;
  double pos_max = 0.0;
  double th_sq = 0.0;
  double th_max = 0.0;
  int n = 0;
  int nth = 0;

  void add_position(double e) {
    pos_sq += e * e;
    pos_max = std::max(pos_max, e);
    ++n;
  }
  void add_heading(double e) {
    th_sq += e * e;
    th_max = std::max(th_max, std::abs(e));
    ++nth;
  }
  ErrorStats stats() const {
    ErrorStats s;
    s.samples = n;
    s.heading_samples = nth;
    s.pos_rmse = n > 0 ? std::sqrt(pos_sq / n) : 0.0;
    s.pos_max = pos_max;
    s.heading_rmse_deg = nth > 0 ? std::sqrt(th_sq / nth) * kRadToDeg : 0.0;
    s.heading_max_deg = th_max * kRadToDeg;
    return s;
  }
};

VariantResult replay(const std::string& name, const localization::EkfParams& params, const std::vector<Event>& events,
                     std::vector<Pose2>* track) {
  localization::Ekf ekf(params);
  VariantResult r;
  r.name = name;
  r.params = params;
  Accumulator acc;
  double last_gyro_t = -1.0;
  double score_sum = 0.0;
  for (const Event& e : events) {
    if (e.kind == EventKind::kUwb) {
      if (!e.fix) continue;
      const auto status = ekf.update_uwb(e.fix->position, e.fix->covariance);
      if (status == localization::UpdateStatus::kGated) ++r.fixes_gated;
      continue;
    }
    // Fig. 4.3: an IMU reading triggers prediction and publishes the pose.
    if (last_gyro_t >= 0.0) ekf.predict(e.gyro, e.t - last_gyro_t);
    last_gyro_t = e.t;
    ekf.update_commanded(e.command);
    if (e.has_encoders) ekf.update_encoders(e.encoders);
    if (!ekf.initialized()) continue;
    if (ekf.heading_resolved() && r.heading_resolved_at < 0.0) r.heading_resolved_at = e.t;
    const Pose2 est = ekf.pose();
    acc.add_position(geometry::distance(est.position(), e.truth.position()));
    if (ekf.heading_resolved()) acc.add_heading(geometry::angle_diff(est.yaw, e.truth.yaw));
    score_sum += ekf.score();
    if (track) track->push_back(est);
  }
  r.ekf = acc.stats();
  r.mean_score = acc.n > 0 ? score_sum / acc.n : 0.0;
  return r;
}

std::string fmt(double v, int precision = 3) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(precision) << v;
  return os.str();
}

}  // namespace

std::optional<Trajectory> parse_trajectory(const std::string& name) {
  if (name == "square") return Trajectory::kSquare;
  if (name == "figure8") return Trajectory::kFigure8;
  if (name == "table_a_loop") return Trajectory::kTableALoop;
  return std::nullopt;
}

std::string to_string(Trajectory t) {
  switch (t) {
    case Trajectory::kSquare:
      return "square";
    case Trajectory::kFigure8:
      return "figure8";
    case Trajectory::kTableALoop:
      return "table_a_loop";
  }
  return "?";
}

std::vector<map::UwbAnchor> default_anchors() {
  return {{"U1", 0.0, 0.0, 1.0}, {"U2", 3.0, 0.0, 1.0}, {"U3", 3.0, 3.0, 1.0}, {"U4", 0.0, 3.0, 1.0}};
}

LocEvalResult run_loc_eval(const LocEvalParams& params) {
  if (!(params.duration > 0.0) || !std::isfinite(params.duration)) {
    throw std::invalid_argument("duration must be a positive number of seconds");
  }
  if (!(params.nlos_fraction >= 0.0 && params.nlos_fraction <= 1.0)) {
    throw std::invalid_argument("nlos fraction must be in [0, 1]");
  }
  if (!(params.speed > 0.0)) throw std::invalid_argument("speed must be positive");

  LocEvalResult result;
  result.params = params;
  result.anchors = params.anchors.empty() ? default_anchors() : params.anchors;

  const ReferenceLoop loop = make_loop(params.trajectory);
  double kappa = 0.0;
  const Pose2 start = loop.pose(0.0, &kappa);

  sim::UwbParams uwb_params = params.uwb;
  uwb_params.random_nlos_probability = params.nlos_fraction;
  sim::ForkliftBody body(params.forklift, start, engine(params.seed, 1));
  sim::UwbTag tag(result.anchors, uwb_params, engine(params.seed, 2));
  sim::Gyro gyro(params.gyro, engine(params.seed, 3));
  sim::WheelEncoders encoders(params.encoders, engine(params.seed, 4));

  // One master tick at 140 Hz serves the 70 Hz IMU / path tracker and the 20 Hz UWB exactly.
  const double tick = 1.0 / 140.0;
  const int ticks = static_cast<int>(std::ceil(params.duration / tick));
  const int gyro_every = std::max(1, static_cast<int>(std::lround(140.0 / params.gyro.rate_hz)));
  const int uwb_every = std::max(1, static_cast<int>(std::lround(140.0 / uwb_params.rate_hz)));
  const int substeps = std::max(1, static_cast<int>(std::lround(tick / params.physics_dt)));

  std::vector<Event> events;
  sim::BodyTwist cmd;
  double range_err_sum = 0.0;
  double range_err_sq = 0.0;
  int range_los = 0;
  Accumulator uwb_acc;

  for (int k = 0; k <= ticks; ++k) {
    const double t = k * tick;
    if (k > 0) {
      for (int i = 0; i < substeps; ++i) body.step(cmd, tick / substeps);
    }
    const Pose2 truth = body.pose();

    if (k % uwb_every == 0) {
      Event e;
      e.kind = EventKind::kUwb;
      e.t = t;
      e.truth = truth;
      const auto readings = tag.measure_ranges(truth);
      std::vector<sim::AnchorRange> ranges;
      for (const auto& r : readings) {
        ranges.push_back({r.anchor, r.range});
        ++result.ranges;
        if (r.nlos) {
          ++result.nlos_ranges;
        } else {
          const double err = r.range - r.true_range;
          range_err_sum += err;
          range_err_sq += err * err;
          ++range_los;
        }
      }
      e.fix = sim::solve_multilateration(
          result.anchors, ranges, uwb_params.solver,
          result.uwb_positions.empty() ? std::nullopt : std::optional<Vec2>(result.uwb_positions.back()));
      if (e.fix) {
        e.fix->stamp = t;
        ++result.uwb_fixes;
        result.uwb_positions.push_back(e.fix->position);
        uwb_acc.add_position(geometry::distance(e.fix->position, tag.antenna_position(truth)));
      } else {
        ++result.uwb_missing;
      }
      events.push_back(std::move(e));
    }

    if (k % gyro_every == 0) {
      // Path tracker: feed-forward along the loop plus feedback on the true pose, so that every
      // filter variant is judged on the same motion, independent of its own estimate.
      const double s = params.speed * t;
      const Pose2 ref = loop.pose(s, &kappa);
      const Vec2 e_body = geometry::map_to_body(truth, ref.position());
      const double e_th = geometry::angle_diff(ref.yaw, truth.yaw);
      cmd.vx = params.speed * std::cos(e_th) + 1.0 * e_body.x;
      cmd.vy = 1.0 * e_body.y;
      cmd.omega = params.speed * kappa + 2.0 * e_th;

      Event e;
      e.kind = EventKind::kGyro;
      e.t = t;
      e.truth = truth;
      e.gyro = gyro.measure(body.twist().omega, 1.0 / params.gyro.rate_hz);
      e.command = {cmd.vx, cmd.vy, cmd.omega};
      if (params.encoders.enabled) {
        const sim::WheelSpeeds w = encoders.measure(body.wheel_speeds(), 1.0 / params.gyro.rate_hz);
        const sim::BodyTwist v = body.kinematics().forward(w);
        e.encoders = {v.vx, v.vy, v.omega};
        e.has_encoders = true;
      }
      events.push_back(e);
      result.truth.push_back(truth);
    }
  }

  result.uwb = uwb_acc.stats();
  if (range_los > 1) {
    const double mean = range_err_sum / range_los;
    result.range_noise_std = std::sqrt(std::max(0.0, range_err_sq / range_los - mean * mean));
  }

  result.full = replay("full", params.ekf, events, &result.ekf_track);
  if (params.variants) {
    localization::EkfParams p = params.ekf;
    p.gating = false;
    result.variants.push_back(replay("no_gating", p, events, nullptr));
    // Gating and the solver's covariance both guard against NLOS fixes; with Q_t fixed as in the
    // seed, gating alone carries that load.
    p = params.ekf;
    p.use_fix_covariance = false;
    result.variants.push_back(replay("fixed_q", p, events, nullptr));
    p.gating = false;
    result.variants.push_back(replay("fixed_q_no_gating", p, events, nullptr));
    p = params.ekf;
    p.velocity_source = localization::VelocitySource::kNone;
    result.variants.push_back(replay("no_velocity", p, events, nullptr));
    p = params.ekf;
    p.heading_init = false;
    result.variants.push_back(replay("no_heading_init", p, events, nullptr));
    if (params.encoders.enabled) {
      p = params.ekf;
      p.velocity_source = localization::VelocitySource::kEncoders;
      result.variants.push_back(replay("encoders", p, events, nullptr));
    }
    result.variants.push_back(replay("seed", localization::EkfParams::seed(), events, nullptr));
  }
  return result;
}

std::string loc_eval_svg(const LocEvalResult& r) {
  // Map frame to pixels: y up in the map, down in SVG.
  double min_x = 0.0, min_y = 0.0, max_x = 3.0, max_y = 3.0;
  for (const auto& a : r.anchors) {
    min_x = std::min(min_x, a.x);
    min_y = std::min(min_y, a.y);
    max_x = std::max(max_x, a.x);
    max_y = std::max(max_y, a.y);
  }
  const double margin = 0.15;
  min_x -= margin;
  min_y -= margin;
  max_x += margin;
  max_y += margin;
  const double scale = 200.0;  // px per metre
  const double header = 70.0;
  const double w = (max_x - min_x) * scale;
  const double h = (max_y - min_y) * scale + header;
  auto px = [&](double x) { return fmt((x - min_x) * scale, 1); };
  auto py = [&](double y) { return fmt(header + (max_y - y) * scale, 1); };
  auto polyline = [&](const std::vector<Pose2>& poses, const std::string& colour, double width) {
    std::ostringstream os;
    os << "<polyline fill=\"none\" stroke=\"" << colour << "\" stroke-width=\"" << width << "\" points=\"";
    const std::size_t stride = std::max<std::size_t>(1, poses.size() / 4000);
    for (std::size_t i = 0; i < poses.size(); i += stride) os << px(poses[i].x) << ',' << py(poses[i].y) << ' ';
    os << "\"/>\n";
    return os.str();
  };

  std::ostringstream os;
  os << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << fmt(w, 0) << "\" height=\"" << fmt(h, 0)
     << "\" viewBox=\"0 0 " << fmt(w, 0) << ' ' << fmt(h, 0) << "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  os << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  os << "<text x=\"8\" y=\"18\" font-size=\"14\">loc-eval " << to_string(r.params.trajectory) << ", "
     << fmt(r.params.duration, 0) << " s, seed " << r.params.seed << ", NLOS " << fmt(r.params.nlos_fraction * 100.0, 0)
     << " %</text>\n";
  os << "<text x=\"8\" y=\"36\">UWB RMSE " << fmt(r.uwb.pos_rmse * 100.0, 1) << " cm, EKF RMSE "
     << fmt(r.full.ekf.pos_rmse * 100.0, 1) << " cm, heading RMSE " << fmt(r.full.ekf.heading_rmse_deg, 2)
     << " deg</text>\n";
  os << "<line x1=\"8\" y1=\"52\" x2=\"28\" y2=\"52\" stroke=\"black\" stroke-width=\"2\"/><text x=\"32\" "
        "y=\"56\">truth</text>\n";
  os << "<circle cx=\"90\" cy=\"52\" r=\"2\" fill=\"#d62728\"/><text x=\"96\" y=\"56\">UWB fixes</text>\n";
  os << "<line x1=\"170\" y1=\"52\" x2=\"190\" y2=\"52\" stroke=\"#1f77b4\" stroke-width=\"2\"/><text x=\"194\" "
        "y=\"56\">EKF</text>\n";
  os << "<text x=\"240\" y=\"56\"><tspan fill=\"#2ca02c\">&#9650;</tspan> anchors</text>\n";
  // The 3 m x 3 m table.
  os << "<rect x=\"" << px(0.0) << "\" y=\"" << py(3.0) << "\" width=\"" << fmt(3.0 * scale, 1) << "\" height=\""
     << fmt(3.0 * scale, 1) << "\" fill=\"#f4f4f4\" stroke=\"#999\"/>\n";
  for (const auto& a : r.anchors) {
    const double x = (a.x - min_x) * scale;
    const double y = header + (max_y - a.y) * scale;
    os << "<polygon points=\"" << fmt(x, 1) << ',' << fmt(y - 7, 1) << ' ' << fmt(x - 6, 1) << ',' << fmt(y + 5, 1)
       << ' ' << fmt(x + 6, 1) << ',' << fmt(y + 5, 1) << "\" fill=\"#2ca02c\"/>\n";
  }
  for (const Vec2& p : r.uwb_positions) {
    os << "<circle cx=\"" << px(p.x) << "\" cy=\"" << py(p.y)
       << "\" r=\"1.6\" fill=\"#d62728\" fill-opacity=\"0.6\"/>\n";
  }
  os << polyline(r.truth, "black", 2.0);
  os << polyline(r.ekf_track, "#1f77b4", 1.2);
  os << "</svg>\n";
  return os.str();
}

}  // namespace fleet::eval
