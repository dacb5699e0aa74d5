// The picker's arm at a stop: the line's boxes located, picked and stowed on the tray; at the
// drop place taken off the tray and put down on the packing pallet [Picker thesis, section 4.4].
#include "robot/picker/picker_arm_work.hpp"

#include <gtest/gtest.h>

#include <cstdio>

namespace fleet::robot {
namespace {

PickerArmWork make_work(std::uint64_t seed = 1) {
  perception::DepthMarkerCameraParams camera;
  camera.mount = {0.25, 0.20, 1.50};  // the boom on the left, over the pallet
  return PickerArmWork(arm::PickMotionPlanner(arm::Ur5{}, arm::VacuumGripper{}), camera, {}, seed);
}

TEST(PickerArmWork, PicksALinesBoxesOntoTheTrayAndDropsThemOnThePallet) {
  PickerArmWork work = make_work();
  const map::BoxStock stock{"A1", 6, 0.30, 0.30, 0.25, 3.0};
  std::vector<map::BoxStock> tray;
  const ArmWork picked = work.pick(stock, 2, tray);
  ASSERT_TRUE(picked.ok) << picked.reason;
  EXPECT_EQ(picked.boxes, 2);
  const map::BoxStock smaller{"A3", 6, 0.30, 0.20, 0.15, 1.5};
  const ArmWork full = work.pick(smaller, 1, tray);
  EXPECT_FALSE(full.ok);
  EXPECT_EQ(full.reason, "the tray holds 2 boxes, 2 on it, 1 more asked for");
  ASSERT_EQ(tray.size(), 2u);
  const ArmWork dropped = work.drop(tray, 0);
  ASSERT_TRUE(dropped.ok) << dropped.reason;
  EXPECT_EQ(dropped.boxes, 2);
  // The thesis's simulated pick takes about 36 s [section 5.3.3.1.3]: here a box is located, picked
  // and stowed in well under that, at the UR5's default tool speed.
  const double per_box = picked.duration / 2.0;
  EXPECT_GT(per_box, 5.0);
  EXPECT_LT(per_box, 36.0);
  std::printf("per box: pick and stow %.1f s, unstow and drop %.1f s\n", per_box, dropped.duration / 2.0);
}

TEST(PickerArmWork, ALoaderStacksTwoLayersOnThePalletBehindIt) {
  // The deck as the loader's tray: the row behind the base, each box set on the one below it.
  PickerArmLayout layout;
  layout.tray = layout.deck;
  layout.tray_layers = layout.deck_layers;
  perception::DepthMarkerCameraParams camera;
  camera.mount = {0.25, 0.20, 1.50};
  PickerArmWork work(arm::PickMotionPlanner(arm::Ur5{}, arm::VacuumGripper{}), camera, layout, 3);
  // The plant's tallest box the gripper lifts (A4, 0.30 m, is too heavy for it).
  const map::BoxStock stock{"A1", 12, 0.30, 0.30, 0.25, 3.0};
  std::vector<map::BoxStock> deck;
  std::vector<double> per_stop;
  for (int stop = 0; stop < layout.deck_layers; ++stop) {
    const ArmWork loaded = work.pick(stock, 3, deck);
    ASSERT_TRUE(loaded.ok) << "layer " << stop + 1 << ": " << loaded.reason;
    per_stop.push_back(loaded.duration);
  }
  EXPECT_EQ(deck.size(), 6u);
  const ArmWork full = work.pick(stock, 1, deck);
  EXPECT_FALSE(full.ok);
  EXPECT_EQ(full.reason, "the tray holds 6 boxes, 6 on it, 1 more asked for");
  std::printf("three boxes on layer 1, 2: %.1f s, %.1f s\n", per_stop[0], per_stop[1]);
  // A third layer is out of the arm's reach.
  layout.tray_layers = 3;
  PickerArmWork higher(arm::PickMotionPlanner(arm::Ur5{}, arm::VacuumGripper{}), camera, layout, 3);
  const ArmWork third = higher.pick(stock, 3, deck);
  EXPECT_FALSE(third.ok);
  EXPECT_NE(third.reason.find("outside"), std::string::npos) << third.reason;
}

TEST(PickerArmWork, TheThousandthBoxTakesAsLongAsTheFirst) {
  // One arm for a robot's life: its camera's clock runs on from stop to stop.
  PickerArmWork work = make_work();
  const map::BoxStock stock{"A1", 6, 0.30, 0.30, 0.25, 3.0};
  double first = 0.0;
  double last = 0.0;
  for (int box = 0; box < 1000; ++box) {
    std::vector<map::BoxStock> tray;
    const ArmWork picked = work.pick(stock, 1, tray);
    ASSERT_TRUE(picked.ok) << "box " << box << ": " << picked.reason;
    (box == 0 ? first : last) = picked.duration;
  }
  EXPECT_NEAR(last, first, 1.0);
}

TEST(PickerArmWork, ABoxTooHeavyForTheGripperIsRefusedWithTheReason) {
  PickerArmWork work = make_work();
  std::vector<map::BoxStock> tray;
  const ArmWork heavy = work.pick({"A4", 6, 0.60, 0.40, 0.30, 12.0}, 1, tray);
  EXPECT_TRUE(tray.empty());
  EXPECT_FALSE(heavy.ok);
  EXPECT_NE(heavy.reason.find("box 1 of A4"), std::string::npos) << heavy.reason;
}

}  // namespace
}  // namespace fleet::robot
