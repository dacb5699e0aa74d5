#include "robot/forklift/simulated_forklift.hpp"

#include <algorithm>
#include <cmath>

namespace fleet::robot {

std::mt19937_64 seeded_engine(std::uint64_t seed, std::uint64_t stream) {
  std::seed_seq seq{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32),
                    static_cast<std::uint32_t>(stream), static_cast<std::uint32_t>(stream >> 32), 0x5eedu};
  return std::mt19937_64(seq);
}

localization::EkfParams SimulatedForklift::filter_params(const SimulatedForkliftParams& p,
                                                         const geometry::Pose2& start) {
  localization::EkfParams e = p.ekf;
  if (p.known_start_heading) {
    e.heading_init = false;
    e.initial_heading = start.yaw;
  }
  return e;
}

SimulatedForklift::SimulatedForklift(const SimulatedForkliftParams& params, const map::Site& site,
                                     const geometry::Pose2& start, std::uint64_t seed, std::uint64_t stream)
    : perfect_(params.perfect_localization),
      body_(params.forklift, start, seeded_engine(seed, stream + 1)),
      tag_(site, params.uwb, seeded_engine(seed, stream + 2)),
      gyro_(params.gyro, seeded_engine(seed, stream + 3)),
      ekf_(filter_params(params, start)),
      uwb_period_(1.0 / params.uwb.rate_hz),
      calibrate_(params.gyro_standstill_calibration) {
  if (params.marker_localization) {
    std::vector<perception::Marker> markers;
    for (const auto& m : site.markers) markers.push_back({m.id, m.pose});
    std::vector<geometry::Polygon> racks;
    for (const auto& r : site.racks) racks.push_back(r.polygon);
    markers_.emplace(params.markers, params.forklift.mecanum, start, std::move(markers), std::move(racks),
                     seeded_engine(seed, stream + 4));
  }
}

void SimulatedForklift::warm_up(double seconds, double dt) {
  for (double t = 0.0; t < seconds; t += dt) step({}, dt);
}

void SimulatedForklift::step(const control::BodyTwist& cmd, double dt, std::span<const geometry::Polygon> blockers,
                             std::span<const std::size_t> distrusted) {
  body_.step(sim::BodyTwist{cmd.vx, cmd.vy, cmd.omega}, dt);
  t_ += dt;
  if (markers_) {
    markers_->step(t_, dt, sim::BodyTwist{cmd.vx, cmd.vy, cmd.omega}, body_.wheel_speeds(), body_.pose(),
                   std::hypot(body_.twist().vx, body_.twist().vy), body_.twist().omega);
    return;
  }
  // Gyro at the control rate: predict, then the commanded velocity (what the robot knows).
  double rate = gyro_.measure(body_.twist().omega, dt);
  if (calibrate_) {
    // At rest (no command for a while, so the wheels have stopped) the gyro reads its bias;
    // average it and take it off every reading.
    const bool still = cmd.vx == 0.0 && cmd.vy == 0.0 && cmd.omega == 0.0;
    still_for_ = still ? still_for_ + dt : 0.0;
    if (still_for_ > kStillDelay) {
      const double k = dt / (kBiasTimeConstant + dt);
      bias_ += k * (rate - bias_);
    }
    rate -= bias_;
  }
  ekf_.predict(rate, dt);
  ekf_.update_commanded({cmd.vx, cmd.vy, cmd.omega});
  if (t_ >= next_uwb_) {
    next_uwb_ += uwb_period_;
    // After a long pause (a stopped process) do not replay every missed fix.
    next_uwb_ = std::max(next_uwb_, t_);
    if (const auto fix = tag_.measure(body_.pose(), t_, blockers, distrusted))
      ekf_.update_uwb(fix->position, fix->covariance);
  }
}

geometry::Pose2 SimulatedForklift::estimate() const {
  return perfect_ || !ekf().initialized() ? body_.pose() : ekf().pose();
}

std::array<double, 9> SimulatedForklift::covariance() const {
  std::array<double, 9> c{};
  if (perfect_ || !ekf().initialized()) return c;
  const auto& p = ekf().covariance();
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) c[static_cast<std::size_t>(3 * r + k)] = p(r, k);
  return c;
}

double SimulatedForklift::localization_score() const {
  return perfect_ ? 1.0 : (ekf().initialized() ? ekf().score() : 0.0);
}

}  // namespace fleet::robot
