#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <numbers>

#include "localization/ekf.hpp"

namespace fleet::localization {
namespace {

MarkerSighting sighting_of(const StateVector& x, geometry::Vec2 marker) {
  MarkerSighting z;
  z.marker = marker;
  z.camera = {0.30, -0.22};
  z.camera_yaw = -0.9;
  const Eigen::Vector2d h = Ekf::marker_model(x, z);
  z.d = h(0);
  z.alpha = h(1);
  return z;
}

TEST(MarkerUpdate, JacobianMatchesNumericalDerivative) {
  StateVector x = StateVector::Zero();
  x << 2.0, 1.0, 0.4, 0.3, 0.0, 0.1, 0.0;
  const MarkerSighting z = sighting_of(x, {5.0, -2.0});
  const auto h = Ekf::marker_jacobian(x, z);
  constexpr double kStep = 1e-6;
  for (int i = 0; i < kStateSize; ++i) {
    StateVector plus = x;
    StateVector minus = x;
    plus(i) += kStep;
    minus(i) -= kStep;
    const Eigen::Vector2d numeric = (Ekf::marker_model(plus, z) - Ekf::marker_model(minus, z)) / (2 * kStep);
    EXPECT_NEAR(h(0, i), numeric(0), 1e-6) << "d by state " << i;
    EXPECT_NEAR(h(1, i), numeric(1), 1e-6) << "alpha by state " << i;
  }
}

TEST(MarkerUpdate, PullsAnOffsetEstimateOntoTheMarkersAndRejectsNonsense) {
  Ekf ekf(EkfParams::picker());
  MarkerSighting first;
  first.marker = {3.0, 0.0};
  first.d = 2.0;
  EXPECT_EQ(ekf.update_marker(first), UpdateStatus::kNotInitialized);

  // The filter starts 20 cm off in y; the robot truly stands at (1, 1) heading +x.
  ekf.initialize_at({1.0, 1.2, 0.0}, 0.3, 0.05);
  StateVector truth = StateVector::Zero();
  truth << 1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0;
  for (int k = 0; k < 20; ++k) {
    for (const geometry::Vec2 m : {geometry::Vec2{3.0, -1.0}, geometry::Vec2{5.0, 3.0}}) {
      MarkerSighting z = sighting_of(truth, m);
      z.sigma_d = 0.02;
      z.sigma_alpha = 0.005;
      EXPECT_EQ(ekf.update_marker(z), UpdateStatus::kAccepted);
    }
  }
  EXPECT_NEAR(ekf.pose().x, 1.0, 0.01);
  EXPECT_NEAR(ekf.pose().y, 1.0, 0.01);
  EXPECT_NEAR(ekf.pose().yaw, 0.0, 0.005);

  MarkerSighting bad = sighting_of(truth, {3.0, -1.0});
  bad.d = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(ekf.update_marker(bad), UpdateStatus::kRejectedNonFinite);
  bad = sighting_of(truth, {3.0, -1.0});
  bad.sigma_d = 0.0;
  EXPECT_EQ(ekf.update_marker(bad), UpdateStatus::kRejectedNonFinite);
  // A sighting 3 m off (a marker mistaken for another) is gated.
  MarkerSighting wrong = sighting_of(truth, {3.0, -1.0});
  wrong.d += 3.0;
  wrong.sigma_d = 0.02;
  EXPECT_EQ(ekf.update_marker(wrong), UpdateStatus::kGated);
}

}  // namespace
}  // namespace fleet::localization
