// A loader job: the walk, where the transporter stands, and who does what as the robots report.
#include "orders/loader_job.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "common/errors.hpp"

namespace fleet::orders {
namespace {

PickLine line(const std::string& place, int quantity) {
  return {.place = place, .item = "I" + place, .quantity = quantity, .line = 1};
}

std::vector<LoaderInstruction> of(const LoaderJob& job) {
  return job.instructions();
}

LoaderInstruction for_robot(const LoaderJob& job, const std::string& robot) {
  for (const auto& i : job.instructions()) {
    if (i.robot_id == robot) return i;
  }
  return {.robot_id = "(none)"};
}

// Places on a line along x, one aisle: the distance is along it.
const std::map<std::string, geometry::Pose2> kPoses = {
    {"A", {0, 0, 0}}, {"B", {3.5, 0, 0}}, {"C", {7, 0, 0}}, {"D", {10.5, 0, 0}}};
double along(const std::string& from, const std::string& to) {
  return std::abs(kPoses.at(from).x - kPoses.at(to).x);
}

TEST(LoaderWalk, StartsInAisleOrderGoesOnToTheNearestAndCutsLinesToAPallet) {
  // Listed out of order, one line larger than a pallet, two lines on one place; the places lie
  // 3.5 m apart in aisle order A, B, C, D, and the walk starts at A.
  const auto walk = loader_walk({line("D", 2), line("A", 7), line("C", 1), line("C", 1)}, 5, kPoses, along);
  std::vector<std::pair<std::string, int>> stops;
  for (const auto& l : walk) stops.emplace_back(l.place, l.quantity);
  // Cut where a pallet fills in aisle order: A 5 | A 2, C 2, D 1 | D 1.
  EXPECT_EQ(stops, (std::vector<std::pair<std::string, int>>{{"A", 5}, {"A", 2}, {"C", 2}, {"D", 1}, {"D", 1}}));

  // Nearest by road, not by aisle order: with a short cut from A to C, C comes before B.
  const auto back = loader_walk({line("A", 1), line("C", 1), line("B", 1)}, 5, kPoses,
                                [](const std::string& from, const std::string& to) {
                                  if (from == "A" && to == "C") return 1.0;  // a short cut
                                  return along(from, to);
                                });
  ASSERT_EQ(back.size(), 3u);
  EXPECT_EQ(back[1].place, "C");
  EXPECT_EQ(back[2].place, "B");

  // A one-way lane from D down to A: back up it is a loop of 60 m. The walk starts at D.
  const auto down = loader_walk({line("A", 1), line("C", 1), line("D", 1)}, 5, kPoses,
                                [](const std::string& from, const std::string& to) {
                                  const double d = along(from, to);
                                  return from > to ? d : 60.0 - d;
                                });
  ASSERT_EQ(down.size(), 3u);
  EXPECT_EQ(down[0].place, "D");
  EXPECT_EQ(down[1].place, "C");
  EXPECT_EQ(down[2].place, "A");
}

TEST(LoaderWalk, TransporterStandsFacingAwayWithItsPalletWhereTheArmReachesBehindThePicker) {
  const geometry::Pose2 picker{2.0, 1.0, std::numbers::pi / 2};  // heading +y
  const geometry::Pose2 t = transporter_pose(picker, -0.85, 0.6);
  EXPECT_NEAR(t.x, 2.0, 1e-9);
  EXPECT_NEAR(t.y, 1.0 - 1.45, 1e-9);
  EXPECT_NEAR(geometry::normalize_angle(t.yaw + std::numbers::pi / 2), 0.0, 1e-9);  // heading -y
  // Its pallet's centre, 0.6 m behind it (along +y), is 0.85 m behind the picker.
  EXPECT_NEAR(t.y - 0.6 * std::sin(t.yaw), 1.0 - 0.85, 1e-9);
}

// Before any picker has the walk its pallet goes ahead to the first stop; a picker added once it
// stands there drives straight to the stop.
TEST(LoaderJob, ThePalletGoesAheadToTheFirstStopBeforeAPickerHasTheWalk) {
  LoaderJob job({line("A", 2), line("B", 1)}, 5, "");
  EXPECT_TRUE(job.wants_picker());
  job.add_transporter("st1");
  EXPECT_EQ(of(job), (std::vector<LoaderInstruction>{{"st1", LoaderTask::kFollow, 0, 0}}));
  EXPECT_FALSE(job.pallet_in_place());
  job.transporter_in_place("st1", 1);
  EXPECT_FALSE(job.pallet_in_place()) << "behind another stop than the next";
  job.transporter_in_place("st1", 0);
  EXPECT_TRUE(job.pallet_in_place());
  job.add_picker("pk1");
  EXPECT_EQ(for_robot(job, "pk1"), (LoaderInstruction{"pk1", LoaderTask::kGoToStop, 0, 0}));
}

TEST(LoaderJob, APickerFillsOneTransporterTheNextMovesUpAndBothDeliver) {
  LoaderJob job({line("A", 2), line("B", 3), line("C", 2)}, 5, "pk1");
  EXPECT_EQ(of(job), (std::vector<LoaderInstruction>{{"pk1", LoaderTask::kWait, 0, 0}}));
  EXPECT_TRUE(job.wants_transporter());
  job.add_transporter("st1");
  EXPECT_TRUE(job.wants_transporter()) << "7 boxes left, 5 on a pallet: the next is asked for early";
  job.add_transporter("st2");
  EXPECT_FALSE(job.wants_transporter());
  EXPECT_EQ(for_robot(job, "st1"), (LoaderInstruction{"st1", LoaderTask::kFollow, 0, 0}));
  EXPECT_EQ(for_robot(job, "st2").task, LoaderTask::kWaitBehind);

  EXPECT_EQ(for_robot(job, "pk1").task, LoaderTask::kWait) << "not to the stop before the pallet stands behind it";
  job.transporter_in_place("st1", 0);
  EXPECT_EQ(for_robot(job, "pk1"), (LoaderInstruction{"pk1", LoaderTask::kGoToStop, 0, 0}));
  job.picker_at("pk1", 0);
  EXPECT_EQ(for_robot(job, "pk1"), (LoaderInstruction{"pk1", LoaderTask::kLoad, 0, 2}));
  job.loaded(0, 2);
  EXPECT_EQ(for_robot(job, "pk1"), (LoaderInstruction{"pk1", LoaderTask::kWait, 1, 0})) << "the pallet moves up first";
  EXPECT_EQ(for_robot(job, "st1"), (LoaderInstruction{"st1", LoaderTask::kFollow, 1, 0}));
  job.picker_at("pk1", 1);
  job.transporter_in_place("st1", 1);
  job.loaded(1, 3);
  // Full: st1 leaves, st2 moves up behind the next stop.
  EXPECT_EQ(for_robot(job, "st1"), (LoaderInstruction{"st1", LoaderTask::kDeliver, -1, 5}));
  EXPECT_EQ(for_robot(job, "st2"), (LoaderInstruction{"st2", LoaderTask::kFollow, 2, 0}));
  EXPECT_FALSE(job.wants_transporter());
  job.transporter_in_place("st1", 2);  // not the current transporter any more: no effect
  EXPECT_EQ(for_robot(job, "pk1").task, LoaderTask::kWait);
  job.transporter_in_place("st2", 2);
  EXPECT_EQ(for_robot(job, "pk1").task, LoaderTask::kGoToStop);
  job.picker_at("pk1", 2);
  job.loaded(2, 2);
  EXPECT_EQ(for_robot(job, "pk1").task, LoaderTask::kRelease);
  EXPECT_EQ(for_robot(job, "st2"), (LoaderInstruction{"st2", LoaderTask::kDeliver, -1, 2}));
  EXPECT_FALSE(job.done());
  job.delivered("st1");
  job.delivered("st2");
  EXPECT_TRUE(job.done());
  EXPECT_EQ(job.boxes_loaded(), 7);
  ASSERT_EQ(job.runs().size(), 2u);
  EXPECT_EQ(job.runs()[0].boxes, 5);
  EXPECT_EQ(job.runs()[1].boxes, 2);
}

TEST(LoaderJob, ThePickerFollowsItsPalletMovingUpAndLoadsOnceItStands) {
  LoaderJob job({line("A", 2), line("B", 2), line("C", 1)}, 5, "pk1");
  job.add_transporter("st1");
  job.transporter_in_place("st1", 0);
  job.picker_at("pk1", 0);
  job.loaded(0, 2);
  EXPECT_EQ(for_robot(job, "pk1").task, LoaderTask::kWait) << "the pallet has not moved yet";
  job.transporter_moving_up("st2", 1);
  EXPECT_EQ(for_robot(job, "pk1").task, LoaderTask::kWait) << "another transporter moving says nothing of this one";
  job.transporter_moving_up("st1", 2);
  EXPECT_EQ(for_robot(job, "pk1").task, LoaderTask::kWait) << "moving up to another stop";
  job.transporter_moving_up("st1", 1);
  EXPECT_EQ(for_robot(job, "pk1"), (LoaderInstruction{"pk1", LoaderTask::kApproach, 1, 0}));
  job.picker_at("pk1", 1);
  EXPECT_EQ(for_robot(job, "pk1").task, LoaderTask::kApproach) << "at the stop, it waits for the pallet to stand";
  job.transporter_in_place("st1", 1);
  EXPECT_EQ(for_robot(job, "pk1"), (LoaderInstruction{"pk1", LoaderTask::kLoad, 1, 2}));
  job.loaded(1, 2);
  EXPECT_EQ(for_robot(job, "pk1").task, LoaderTask::kWait) << "the fact was for the last stop";
}

TEST(LoaderJob, NoPickerFollowsAPalletItHasNotLoaded) {
  // The first pallet goes ahead of the picker; a new transporter moves up behind the stop past
  // where the picker stands: the picker is out of its way, not following it.
  LoaderJob job({line("A", 2), line("B", 2)}, 2, "pk1");
  job.add_transporter("st1");
  job.transporter_moving_up("st1", 0);
  EXPECT_EQ(for_robot(job, "pk1").task, LoaderTask::kWait);
  job.transporter_in_place("st1", 0);
  job.picker_at("pk1", 0);
  job.loaded(0, 2);
  job.add_transporter("st2");
  job.transporter_moving_up("st2", 1);
  EXPECT_EQ(for_robot(job, "pk1").task, LoaderTask::kWait);
}

TEST(LoaderJob, TheSecondStopOfOnePlaceNeedsNoDrivingButAFreshPallet) {
  LoaderJob job({line("A", 4), line("A", 3)}, 5, "pk1");
  job.add_transporter("st1");
  job.add_transporter("st2");
  job.picker_at("pk1", 0);
  job.transporter_in_place("st1", 0);
  job.loaded(0, 4);
  // 3 more do not fit beside 4: st1 leaves, st2 moves up; the picker waits for it.
  EXPECT_EQ(for_robot(job, "st1").task, LoaderTask::kDeliver);
  EXPECT_EQ(for_robot(job, "pk1"), (LoaderInstruction{"pk1", LoaderTask::kWait, 1, 0}));
  job.transporter_in_place("st2", 1);
  EXPECT_EQ(for_robot(job, "pk1"), (LoaderInstruction{"pk1", LoaderTask::kLoad, 1, 3}));
}

TEST(LoaderJob, ALostTransporterKeepsItsBoxesOnItsPalletAndAnotherTakesOver) {
  LoaderJob job({line("A", 2), line("B", 2)}, 5, "pk1");
  job.add_transporter("st1");
  job.picker_at("pk1", 0);
  job.transporter_in_place("st1", 0);
  job.loaded(0, 2);
  job.robot_lost("st1");
  EXPECT_EQ(for_robot(job, "pk1").task, LoaderTask::kWait);
  EXPECT_EQ(for_robot(job, "st1").robot_id, "(none)");
  EXPECT_TRUE(job.wants_transporter());
  ASSERT_EQ(job.runs().size(), 1u);
  EXPECT_TRUE(job.runs()[0].lost);
  EXPECT_EQ(job.runs()[0].boxes, 2) << "the boxes belong to its pallet";

  job.add_transporter("st3");
  EXPECT_EQ(for_robot(job, "pk1"), (LoaderInstruction{"pk1", LoaderTask::kWait, 1, 0}));
  EXPECT_EQ(for_robot(job, "st3"), (LoaderInstruction{"st3", LoaderTask::kFollow, 1, 0}));
  job.picker_at("pk1", 1);
  job.transporter_in_place("st3", 1);
  job.loaded(1, 2);
  job.delivered("st3");
  EXPECT_TRUE(job.done());
  EXPECT_EQ(job.boxes_loaded(), 4) << "each box counted once";
  EXPECT_EQ(job.runs()[1].boxes, 2);
}

TEST(LoaderJob, ALostPickerLeavesItsStopToAnotherAndTheTransporterStaysBehindIt) {
  LoaderJob job({line("A", 3), line("B", 1)}, 5, "pk1");
  job.add_transporter("st1");
  job.picker_at("pk1", 0);
  job.transporter_in_place("st1", 0);
  job.loaded(0, 1);  // one box set, the second in its gripper when it is lost
  job.robot_lost("pk1");
  EXPECT_TRUE(job.wants_picker());
  EXPECT_EQ(for_robot(job, "st1"), (LoaderInstruction{"st1", LoaderTask::kFollow, 0, 0}));
  EXPECT_EQ(job.next_stop(), 0);
  EXPECT_TRUE(job.pallet_in_place()) << "the picker taking over finds the pallet there";

  job.add_picker("pk2");
  EXPECT_EQ(for_robot(job, "pk2"), (LoaderInstruction{"pk2", LoaderTask::kGoToStop, 0, 0}));
  EXPECT_EQ(for_robot(job, "st1").task, LoaderTask::kFollow);
  job.picker_at("pk2", 0);
  EXPECT_EQ(for_robot(job, "pk2"), (LoaderInstruction{"pk2", LoaderTask::kLoad, 0, 2})) << "only the boxes left";
  job.loaded(0, 2);
  EXPECT_EQ(job.boxes_loaded(), 3);
}

TEST(LoaderJob, AStopTheArmCannotDoIsLeftAndTheWalkGoesOn) {
  LoaderJob job({line("A", 2), line("B", 1)}, 5, "pk1");
  job.add_transporter("st1");
  job.picker_at("pk1", 0);
  job.transporter_in_place("st1", 0);
  job.loaded(0, 1);
  job.stop_failed(0);
  EXPECT_EQ(job.next_stop(), 1);
  EXPECT_EQ(for_robot(job, "pk1"), (LoaderInstruction{"pk1", LoaderTask::kWait, 1, 0}));
  EXPECT_EQ(job.boxes_loaded(), 1);
  EXPECT_EQ(job.boxes_asked(), 3);
}

TEST(LoaderJob, ALostTransporterWithAnEmptyPalletHasNothingToDeliver) {
  LoaderJob job({line("A", 2)}, 5, "pk1");
  job.add_transporter("st1");
  EXPECT_FALSE(job.wants_transporter());
  job.robot_lost("st1");  // lost before a box was set
  job.add_transporter("st2");
  job.picker_at("pk1", 0);
  job.transporter_in_place("st2", 0);
  job.loaded(0, 2);
  job.delivered("st2");
  EXPECT_TRUE(job.done());
}

TEST(LoaderJob, ATransporterWaitingBehindIsReleasedWhenTheWalkEndsEarly) {
  LoaderJob job({line("A", 2), line("B", 2), line("C", 3)}, 5, "pk1");
  job.add_transporter("st1");
  ASSERT_TRUE(job.wants_transporter());
  job.add_transporter("st2");
  job.picker_at("pk1", 0);
  job.transporter_in_place("st1", 0);
  job.loaded(0, 2);
  job.stop_failed(1);
  job.stop_failed(2);
  EXPECT_EQ(for_robot(job, "st1"), (LoaderInstruction{"st1", LoaderTask::kDeliver, -1, 2}));
  EXPECT_EQ(for_robot(job, "st2").task, LoaderTask::kRelease);
  EXPECT_EQ(for_robot(job, "pk1").task, LoaderTask::kRelease);
  job.delivered("st1");
  EXPECT_TRUE(job.done());
}

TEST(LoaderJob, StopsThatDoNotFitOnAPalletAreRefusedNamingThePlace) {
  EXPECT_THROW(LoaderJob({line("A", 1)}, 0, "pk1"), InputError);
  try {
    LoaderJob({line("A", 1), line("RB4", 6)}, 5, "pk1");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "loader stop at RB4 asks for 6 boxes; a stop takes 1 to 5 (one pallet)");
  }
}

}  // namespace
}  // namespace fleet::orders
