#include "sim/uwb.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace fleet::sim {

namespace {

struct Timestamps {
  // Measured intervals, each in the clock of the device that measured it.
  double round_a = 0.0;
  double reply_a = 0.0;
  double round_b = 0.0;
  double reply_b = 0.0;
};

// Simulates the SDS-TWR message sequence of [Forklift thesis, Fig. 2.4] in true time, then reads each
// interval with the measuring device's clock. TWR (Forklift thesis, Fig. 2.3) is its first half.
Timestamps exchange(const RangingExchange& ex, const TimestampNoise& noise, std::mt19937_64& rng) {
  double j_a_resp = 0.0;   // jitter of A's reception of B's response
  double j_b_poll = 0.0;   // jitter of B's reception of A's poll
  double j_b_final = 0.0;  // jitter of B's reception of A's final message
  if (noise.rx_std > 0.0) {
    std::normal_distribution<double> n(0.0, noise.rx_std);
    j_a_resp = n(rng);
    j_b_poll = n(rng);
    j_b_final = n(rng);
  }
  const double tp = ex.time_of_flight;
  // True times: poll sent at 0.
  const double rx_poll_b = tp;
  const double tx_resp_b = rx_poll_b + ex.reply_b;
  const double rx_resp_a = tx_resp_b + tp;
  const double tx_final_a = rx_resp_a + ex.reply_a;
  const double rx_final_b = tx_final_a + tp;
  Timestamps t;
  t.round_a = (rx_resp_a + j_a_resp - 0.0) * (1.0 + ex.drift_a);
  t.reply_a = (tx_final_a - (rx_resp_a + j_a_resp)) * (1.0 + ex.drift_a);
  t.reply_b = (tx_resp_b - (rx_poll_b + j_b_poll)) * (1.0 + ex.drift_b);
  t.round_b = (rx_final_b + j_b_final - tx_resp_b) * (1.0 + ex.drift_b);
  return t;
}

Eigen::Vector3d anchor_xyz(const map::UwbAnchor& a) {
  return {a.x, a.y, a.z};
}

}  // namespace

double twr_time_of_flight(const RangingExchange& ex, const TimestampNoise& noise, std::mt19937_64& rng) {
  const Timestamps t = exchange(ex, noise, rng);
  return 0.5 * (t.round_a - t.reply_b);  // [Forklift thesis, eq. 2.2]
}

double sds_twr_time_of_flight(const RangingExchange& ex, const TimestampNoise& noise, std::mt19937_64& rng) {
  const Timestamps t = exchange(ex, noise, rng);
  return 0.25 * ((t.round_a - t.reply_a) + (t.round_b - t.reply_b));  // [Forklift thesis, eq. 2.6]
}

double ads_twr_time_of_flight(const RangingExchange& ex, const TimestampNoise& noise, std::mt19937_64& rng) {
  const Timestamps t = exchange(ex, noise, rng);
  // The products are ~1e-7 s^2 and their difference ~1e-11 s^2: well inside double precision
  // (relative 1e-16 of 1e-7 is 1e-23 s^2, i.e. 1e-20 s after the division, far below the jitter).
  return (t.round_a * t.round_b - t.reply_a * t.reply_b) / (t.round_a + t.round_b + t.reply_a + t.reply_b);
}

double ads_twr_drift_error(const RangingExchange& ex) {
  const double ka = 1.0 + ex.drift_a;
  const double kb = 1.0 + ex.drift_b;
  return ex.time_of_flight * (2.0 * ka * kb / (ka + kb) - 1.0);
}

double twr_drift_error(const RangingExchange& ex) {
  return 0.5 * ex.reply_b * (ex.drift_a - ex.drift_b);  // [Forklift thesis, eq. 2.4]
}

double sds_twr_drift_error_full(const RangingExchange& ex) {
  // [Forklift thesis, eq. 2.7]
  return 0.5 * ex.time_of_flight * (ex.drift_a + ex.drift_b) +
         0.25 * (ex.reply_b - ex.reply_a) * (ex.drift_a - ex.drift_b);
}

double sds_twr_drift_error(const RangingExchange& ex) {
  return 0.25 * (ex.reply_b - ex.reply_a) * (ex.drift_a - ex.drift_b);  // [Forklift thesis, eq. 2.8]
}

std::optional<UwbFix> solve_multilateration(const std::vector<map::UwbAnchor>& anchors,
                                            std::span<const AnchorRange> ranges, const MultilaterationParams& params,
                                            std::optional<geometry::Vec2> initial_guess) {
  std::vector<Eigen::Vector3d> a;
  std::vector<double> rho;
  for (const AnchorRange& r : ranges) {
    if (r.anchor >= anchors.size() || !std::isfinite(r.range) || r.range < 0.0) continue;
    a.push_back(anchor_xyz(anchors[r.anchor]));
    rho.push_back(r.range);
  }
  const int n = static_cast<int>(a.size());
  if (n < 3) return std::nullopt;

  // Anchor geometry: principal line through the anchors' horizontal positions. When every
  // anchor lies close to it, a range set is equally well explained by the mirror image of the
  // tag across the line.
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const auto& p : a) centroid += p.head<2>();
  centroid /= n;
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  for (const auto& p : a) {
    const Eigen::Vector2d d = p.head<2>() - centroid;
    scatter += d * d.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(scatter);
  const Eigen::Vector2d line_normal = eig.eigenvectors().col(0);  // smallest spread
  double max_off_line = 0.0;
  for (const auto& p : a) max_off_line = std::max(max_off_line, std::abs(line_normal.dot(p.head<2>() - centroid)));
  const bool collinear = max_off_line < params.collinear_tolerance;

  Eigen::Vector2d x;
  if (initial_guess && std::isfinite(initial_guess->x) && std::isfinite(initial_guess->y)) {
    x = {initial_guess->x, initial_guess->y};
  } else {
    // The centroid is a saddle point when the anchors are collinear; start off the line.
    x = centroid + (collinear ? 1.0 : 0.0) * line_normal;
  }

  auto residuals = [&](const Eigen::Vector2d& p, Eigen::VectorXd& res, Eigen::MatrixXd* jac) {
    for (int i = 0; i < n; ++i) {
      const Eigen::Vector3d d(p.x() - a[i].x(), p.y() - a[i].y(), params.tag_height - a[i].z());
      const double dist = std::max(d.norm(), 1e-9);
      res(i) = dist - rho[i];
      if (jac) jac->row(i) = d.head<2>().transpose() / dist;
    }
  };

  Eigen::VectorXd res(n);
  Eigen::MatrixXd jac(n, 2);
  residuals(x, res, &jac);
  double cost = res.squaredNorm();
  double lambda = 1e-3;
  for (int it = 0; it < params.max_iterations; ++it) {
    // Levenberg-damped Gauss-Newton step: plain Gauss-Newton when it reduces the cost, damped
    // towards gradient descent when the geometry makes J^T J nearly singular.
    const Eigen::Matrix2d jtj = jac.transpose() * jac;
    const Eigen::Vector2d g = jac.transpose() * res;
    Eigen::Matrix2d damped = jtj;
    damped.diagonal() += lambda * (jtj.diagonal().array() + 1e-9).matrix();
    const Eigen::Vector2d step = -damped.ldlt().solve(g);
    if (!step.allFinite()) return std::nullopt;
    const Eigen::Vector2d candidate = x + step;
    Eigen::VectorXd cres(n);
    Eigen::MatrixXd cjac(n, 2);
    residuals(candidate, cres, &cjac);
    const double ccost = cres.squaredNorm();
    if (ccost <= cost) {
      x = candidate;
      res = cres;
      jac = cjac;
      cost = ccost;
      lambda = std::max(lambda * 0.1, 1e-9);
      if (step.norm() < params.tolerance) break;
    } else {
      lambda *= 10.0;
      if (lambda > 1e9) break;
    }
  }
  if (!x.allFinite()) return std::nullopt;

  UwbFix fix;
  fix.position = {x.x(), x.y()};
  fix.ranges_used = n;
  fix.residual_rms = std::sqrt(cost / n);
  // Scatter of the residuals about the fit (n - 2 degrees of freedom), floored at the assumed
  // range noise: a biased (NLOS) range inflates the covariance instead of hiding in it.
  double sigma2 = params.range_std * params.range_std;
  if (n > 2) sigma2 = std::max(sigma2, cost / (n - 2));
  const Eigen::Matrix2d jtj = jac.transpose() * jac + 1e-12 * Eigen::Matrix2d::Identity();
  fix.covariance = sigma2 * jtj.inverse();
  if (collinear) {
    // Two candidates, mirror images across the anchor line, 2d apart: cover both.
    const double d = line_normal.dot(x - centroid);
    fix.covariance += (2.0 * d) * (2.0 * d) * line_normal * line_normal.transpose();
    fix.mirror_ambiguous = true;
  }
  if (!fix.covariance.allFinite()) return std::nullopt;
  return fix;
}

UwbTag::UwbTag(std::vector<map::UwbAnchor> anchors, const UwbParams& params, std::mt19937_64 rng)
    : anchors_(std::move(anchors)), params_(params), rng_(rng) {
  if (!(params_.rate_hz > 0.0) || !(params_.rx_timestamp_std >= 0.0) || !(params_.clock_ppm_std >= 0.0) ||
      !(params_.random_nlos_probability >= 0.0 && params_.random_nlos_probability <= 1.0)) {
    throw std::invalid_argument(
        "UwbParams: rate_hz > 0, rx_timestamp_std >= 0, clock_ppm_std >= 0 and "
        "random_nlos_probability in [0, 1] required");
  }
  std::normal_distribution<double> ppm(0.0, params_.clock_ppm_std * 1e-6);
  tag_drift_ = ppm(rng_);
  for (std::size_t i = 0; i < anchors_.size(); ++i) anchor_drift_.push_back(ppm(rng_));
}

UwbTag::UwbTag(const map::Site& site, const UwbParams& params, std::mt19937_64 rng)
    : UwbTag(site.uwb_anchors, params, rng) {}

geometry::Vec2 UwbTag::antenna_position(const geometry::Pose2& pose) const {
  return geometry::body_to_map(pose, params_.antenna_offset);  // [Forklift thesis, eq. 4.11]
}

std::vector<RangeReading> UwbTag::measure_ranges(const geometry::Pose2& truth,
                                                 std::span<const geometry::Polygon> blockers) {
  const geometry::Vec2 tag = antenna_position(truth);
  std::vector<RangeReading> out;
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::exponential_distribution<double> bias(params_.nlos_bias_mean > 0.0 ? 1.0 / params_.nlos_bias_mean : 1.0);
  const TimestampNoise noise{params_.rx_timestamp_std};
  for (std::size_t i = 0; i < anchors_.size(); ++i) {
    const map::UwbAnchor& an = anchors_[i];
    const double dz = params_.solver.tag_height - an.z;
    const double true_range = std::sqrt((tag.x - an.x) * (tag.x - an.x) + (tag.y - an.y) * (tag.y - an.y) + dz * dz);
    if (true_range > params_.max_range) continue;
    bool nlos = false;
    for (const geometry::Polygon& poly : blockers) {
      if (poly.size() >= 3 && geometry::segment_intersects_polygon({an.x, an.y}, tag, poly)) {
        nlos = true;
        break;
      }
    }
    // Drawn for every range, blocked or not, so that the random stream (and hence every other
    // noise value) does not depend on the blockers.
    const bool random_nlos = uniform(rng_) < params_.random_nlos_probability;
    const double extra = params_.nlos_bias_min + (params_.nlos_bias_mean > 0.0 ? bias(rng_) : 0.0);
    nlos = nlos || random_nlos;
    const RangingExchange ex{true_range / kSpeedOfLight, params_.reply_a, params_.reply_b, tag_drift_,
                             anchor_drift_[i]};
    const double tof = params_.ranging == RangingFormula::kAdsTwr ? ads_twr_time_of_flight(ex, noise, rng_)
                                                                  : sds_twr_time_of_flight(ex, noise, rng_);
    double range = kSpeedOfLight * tof;
    if (nlos) {
      if (params_.nlos_mode == NlosMode::kDrop) continue;
      range += extra;
    }
    out.push_back({i, range, true_range, nlos});
  }
  return out;
}

std::optional<UwbFix> UwbTag::measure(const geometry::Pose2& truth, double stamp,
                                      std::span<const geometry::Polygon> blockers,
                                      std::span<const std::size_t> distrusted) {
  const std::vector<RangeReading> readings = measure_ranges(truth, blockers);
  std::vector<AnchorRange> ranges;
  ranges.reserve(readings.size());
  for (const RangeReading& r : readings) {
    if (std::find(distrusted.begin(), distrusted.end(), r.anchor) == distrusted.end())
      ranges.push_back({r.anchor, r.range});
  }
  std::optional<UwbFix> fix = solve_multilateration(anchors_, ranges, params_.solver, last_fix_);
  if (fix) {
    fix->stamp = stamp;
    last_fix_ = fix->position;
  }
  return fix;
}

}  // namespace fleet::sim
