#include "arm/vacuum_gripper.hpp"

#include <gtest/gtest.h>

#include <numbers>
#include <stdexcept>

using namespace fleet::arm;

TEST(VacuumGripper, ReproducesTheThesisFigures) {
  const VacuumGripper gripper;
  const GripForces f = gripper.forces(5.0);
  EXPECT_NEAR(f.lift, 103.1, 1e-9);               // [Picker thesis, eq. 3.11]
  EXPECT_NEAR(f.hold, 108.1, 1e-9);               // [Picker thesis, eq. 3.13]
  EXPECT_NEAR(f.per_cup, 27.025, 1e-9);           // [Picker thesis, eq. 3.14]
  EXPECT_NEAR(f.vacuum, 0.215, 5e-4);             // [Picker thesis, eq. 3.15], printed to three places
  EXPECT_NEAR(f.absolute_pressure, 0.798, 5e-4);  // [Picker thesis, eq. 3.16]
  EXPECT_NEAR(gripper.cup_area(), std::numbers::pi * 0.02 * 0.02, 1e-15);
}

TEST(VacuumGripper, HoldingForceGovernsWhileFrictionIsBelowOne) {
  VacuumGripperConfig config;
  config.friction = 2.0;  // better than glue: the lift then governs
  const VacuumGripper sticky(config);
  const GripForces f = sticky.forces(5.0);
  EXPECT_GT(f.lift, f.hold);
  EXPECT_NEAR(f.per_cup, f.lift / 4.0, 1e-12);
}

TEST(VacuumGripper, HoldsTheDesignBox) {
  const VacuumGripper gripper;
  const GripCheck check = gripper.can_hold({5.0, 0.20, 0.20, 0.20});
  EXPECT_TRUE(check.ok) << check.reason;
  EXPECT_TRUE(check.reason.empty());
}

TEST(VacuumGripper, RefusesABoxTooHeavy) {
  const VacuumGripper gripper;
  const GripCheck check = gripper.can_hold({5.5, 0.30, 0.30, 0.30});
  EXPECT_FALSE(check.ok);
  EXPECT_NE(check.reason.find("payload"), std::string::npos) << check.reason;
  EXPECT_FALSE(gripper.can_hold({0.0, 0.30, 0.30, 0.30}).ok);
}

TEST(VacuumGripper, RefusesSidesOutsideTheHandledRange) {
  const VacuumGripper gripper;
  EXPECT_FALSE(gripper.can_hold({2.0, 0.45, 0.30, 0.30}).ok);
  EXPECT_FALSE(gripper.can_hold({2.0, 0.30, 0.30, 0.08}).ok);
  EXPECT_TRUE(gripper.can_hold({2.0, 0.40, 0.40, 0.10}).ok);
}

TEST(VacuumGripper, TheFaceMustCoverTheCupsAsTurned) {
  const VacuumGripper gripper;
  // A 10 x 10 cm face, the smallest of the thesis's range, is narrower than the 12 cm plate.
  const GripCheck small = gripper.can_hold({1.0, 0.10, 0.10, 0.10});
  EXPECT_FALSE(small.ok);
  EXPECT_NE(small.reason.find("cover"), std::string::npos) << small.reason;
  // 10 x 13 cm takes the plate only across its length.
  const Box narrow{1.0, 0.10, 0.13, 0.10};
  EXPECT_FALSE(gripper.can_hold(narrow, 0.0).ok);
  EXPECT_TRUE(gripper.can_hold(narrow, std::numbers::pi / 2.0).ok);
  // Turned 45° the plate spans 14.1 cm each way.
  EXPECT_TRUE(gripper.can_hold({1.0, 0.15, 0.15, 0.15}, std::numbers::pi / 4.0).ok);
  EXPECT_FALSE(gripper.can_hold({1.0, 0.14, 0.14, 0.14}, std::numbers::pi / 4.0).ok);
}

TEST(VacuumGripper, AWeakSourceRefusesHeavyBoxesFirst) {
  VacuumGripperConfig config;
  config.source_vacuum = 0.15;  // bar
  const VacuumGripper weak(config);
  const GripCheck heavy = weak.can_hold({5.0, 0.30, 0.30, 0.30});
  EXPECT_FALSE(heavy.ok);
  EXPECT_NE(heavy.reason.find("vacuum"), std::string::npos) << heavy.reason;
  EXPECT_TRUE(weak.can_hold({3.0, 0.30, 0.30, 0.30}).ok);
  // By default the source is sized for the 5 kg design box.
  EXPECT_NEAR(VacuumGripper{}.source_vacuum(), VacuumGripper{}.forces(5.0).vacuum, 1e-15);
}

TEST(VacuumGripper, InvalidConfigurationThrows) {
  VacuumGripperConfig config;
  config.cup_count = 0;
  EXPECT_THROW(VacuumGripper{config}, std::invalid_argument);
  config = {};
  config.friction = 0.0;
  EXPECT_THROW(VacuumGripper{config}, std::invalid_argument);
  config = {};
  config.min_side = 0.5;
  EXPECT_THROW(VacuumGripper{config}, std::invalid_argument);
}
