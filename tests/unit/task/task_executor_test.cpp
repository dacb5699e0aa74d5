#include "task/task_executor.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "executor_world.hpp"

namespace fleet::task {
namespace {

using namespace test_world;

TEST(TaskExecutor, CarriesAPalletFromPickToDropAndGoesHome) {
  World w;
  const int pallet = w.pallets.add(kA1);
  ASSERT_TRUE(w.exec.submit({"o1", "A1", kA1, "A2", kA2}));
  EXPECT_EQ(w.exec.state(), State::kTrackPath);
  EXPECT_EQ(w.exec.phase(), OrderPhase::kToPick);

  std::vector<State> visited{w.exec.state()};
  const bool done = w.run_until(
      [&] {
        if (visited.back() != w.exec.state()) visited.push_back(w.exec.state());
        return w.exec.state() == State::kIdle;
      },
      300.0);
  ASSERT_TRUE(done) << "stuck in " << to_string(w.exec.state()) << " " << w.exec.error_reason();
  const std::vector<State> fig69 = {State::kTrackPath,  State::kSearchPallet, State::kPickPallet, State::kTrackPath,
                                    State::kDropPallet, State::kGoHome,       State::kIdle};
  EXPECT_EQ(visited, fig69);
  EXPECT_GT(w.t, 20.0) << "about 3 m of road at 0.2 m/s plus the manoeuvres";
  // Every transition is handed out for publication, with its effect, in order (the first,
  // the order's acceptance, was drained by the first step).
  ASSERT_EQ(w.transitions.size(), 7u);
  EXPECT_EQ(w.transitions.front().effect, Effect::kPlanToPick);
  EXPECT_EQ(w.transitions.back().effect, Effect::kStop);
  for (std::size_t i = 0; i < w.transitions.size(); ++i) EXPECT_EQ(w.transitions[i].to, fig69[i]);
  EXPECT_EQ(w.kinds(), (std::vector<Kind>{Kind::kAccepted, Kind::kPicked, Kind::kDropped, Kind::kHomeReached}));
  EXPECT_EQ(w.reports[1].area_id, "A1");
  EXPECT_EQ(w.reports[2].area_id, "A2");
  EXPECT_EQ(w.reports[2].order_id, "o1");

  // The real pallet moved: it stands on A2 now, where the forks put it.
  const auto* p = w.pallets.find(pallet);
  ASSERT_NE(p, nullptr);
  EXPECT_FALSE(p->carried);
  EXPECT_LT(geometry::distance(p->pose.position(), kA2.position()), 0.02);
  EXPECT_LT(std::abs(geometry::angle_diff(p->pose.yaw, kA2.yaw)), 0.06);
  EXPECT_LT(geometry::distance(w.truth.position(), kHome.position()), 0.03);
  EXPECT_FALSE(w.exec.carrying());
}

TEST(TaskExecutor, EmptyAreaIsReportedAndANewOrderIsTakenOnTheWayHome) {
  World w;
  ASSERT_TRUE(w.exec.submit({"o1", "A1", kA1, "A2", kA2}));
  ASSERT_TRUE(w.run_until([&] { return w.exec.state() == State::kGoHome; }, 120.0));
  EXPECT_EQ(w.kinds(), (std::vector<Kind>{Kind::kAccepted, Kind::kAreaEmpty}));
  EXPECT_EQ(w.reports[1].area_id, "A1");
  EXPECT_EQ(w.exec.phase(), OrderPhase::kNone);
  EXPECT_FALSE(w.exec.order().has_value());
  // IDLE_GO_HOME accepts new orders.
  std::string why;
  EXPECT_TRUE(w.exec.submit({"o2", "A2", kA2, "A1", kA1}, &why)) << why;
  EXPECT_EQ(w.exec.state(), State::kTrackPath);
}

TEST(TaskExecutor, RejectsAnOrderWhileBusy) {
  World w;
  w.pallets.add(kA1);
  ASSERT_TRUE(w.exec.submit({"o1", "A1", kA1, "A2", kA2}));
  std::string why;
  EXPECT_FALSE(w.exec.submit({"o2", "A2", kA2, "A1", kA1}, &why));
  EXPECT_EQ(why, "order not accepted in TRACK_PATH");
  ASSERT_TRUE(w.run_until([&] { return w.exec.state() == State::kPickPallet; }, 120.0));
  EXPECT_FALSE(w.exec.submit({"o2", "A2", kA2, "A1", kA1}, &why));
  EXPECT_EQ(w.exec.order()->order_id, "o1");
}

TEST(TaskExecutor, NoPlanWaitsAndAsksAgain) {
  World w;
  w.pallets.add(kA1);
  w.answer_plans = false;
  ASSERT_TRUE(w.exec.submit({"o1", "A1", kA1, "A2", kA2}));
  w.step();
  EXPECT_EQ(w.exec.state(), State::kWaiting);
  EXPECT_EQ(w.exec.phase(), OrderPhase::kToPick);
  const Pose2 before = w.truth;
  w.run_until([] { return false; }, 3.5);
  EXPECT_GE(w.plan_requests, 3) << "asks again every replan_interval";
  EXPECT_EQ(w.truth, before) << "stands still while waiting";
  w.answer_plans = true;
  ASSERT_TRUE(w.run_until([&] { return w.exec.state() == State::kTrackPath; }, 2.0));
  ASSERT_TRUE(w.run_until([&] { return w.exec.state() == State::kSearchPallet; }, 60.0));
}

TEST(TaskExecutor, APathEndingShortOfHomeIsPlannedAgainNotTakenForHome) {
  World w;
  w.pallets.add(kA1);
  ASSERT_TRUE(w.exec.submit({"o1", "A1", kA1, "A2", kA2}));
  w.run_until([] { return false; }, 1.0);
  ASSERT_TRUE(w.exec.cancel(nullptr));
  w.plans_short = 1;
  const int asked_before = w.plan_requests;
  ASSERT_TRUE(w.run_until([&] { return w.exec.state() == State::kIdle; }, 60.0)) << to_string(w.exec.state());
  EXPECT_LT(geometry::distance(w.truth.position(), kHome.position()), 0.05)
      << "took (" << w.truth.x << ", " << w.truth.y << ") for home";
  EXPECT_EQ(w.plan_requests - asked_before, 2) << "the short path, then one from where it ended";
}

TEST(TaskExecutor, PauseFreezesAndResumeContinues) {
  World w;
  w.pallets.add(kA1);
  ASSERT_TRUE(w.exec.submit({"o1", "A1", kA1, "A2", kA2}));
  w.run_until([] { return false; }, 0.5);
  ASSERT_TRUE(w.exec.pause());
  const Pose2 paused_at = w.truth;
  w.run_until([] { return false; }, 1.0);
  EXPECT_EQ(w.truth, paused_at);
  EXPECT_EQ(w.exec.state(), State::kPaused);
  EXPECT_EQ(w.exec.phase(), OrderPhase::kToPick);
  ASSERT_TRUE(w.exec.resume());
  EXPECT_EQ(w.exec.state(), State::kTrackPath);
  ASSERT_TRUE(w.run_until([&] { return w.exec.state() == State::kSearchPallet; }, 60.0));
}

TEST(TaskExecutor, ALongPauseDuringThePickDoesNotFailIt) {
  World w;
  w.pallets.add(kA1);
  ASSERT_TRUE(w.exec.submit({"o1", "A1", kA1, "A2", kA2}));
  ASSERT_TRUE(w.run_until([&] { return w.exec.state() == State::kPickPallet; }, 120.0));
  w.run_until([] { return false; }, 0.3);
  ASSERT_TRUE(w.exec.pause());
  w.run_until([] { return false; }, 5.0);  // longer than the pick's marker-lost timeout
  ASSERT_TRUE(w.exec.resume());
  // The first step after the pause falls between two camera frames.
  w.exec.step({w.t, w.truth, {}});
  w.t += kDt;
  ASSERT_TRUE(w.run_until([&] { return w.exec.phase() == OrderPhase::kToDrop; }, 60.0));
  for (const auto& r : w.reports) EXPECT_NE(r.kind, Kind::kFailed);
  for (const auto& tr : w.transitions) {
    EXPECT_FALSE(tr.from == State::kPickPallet && tr.to == State::kSearchPallet) << "the pick was not given up";
  }
  EXPECT_TRUE(w.exec.carrying());
}

TEST(TaskExecutor, APickThatKeepsFailingFailsTheOrderAndClearsTheWayHome) {
  // A pick that never finishes in time (too short a timeout stands in for a neighbour that keeps
  // the robot from backing to d_min): after max_pick_attempts the forks are still empty, so the
  // robot reports the order failed with the reason and leaves the area instead of standing in
  // ERROR in front of it, where it held the road for every other robot.
  ExecutorParams params;
  params.pick.timeout = 0.2;
  World w(params);
  w.pallets.add(kA1);
  ASSERT_TRUE(w.exec.submit({"o1", "A1", kA1, "A2", kA2}));
  ASSERT_TRUE(w.run_until([&] { return w.exec.state() == State::kGoHome; }, 200.0))
      << "in " << to_string(w.exec.state()) << " " << w.exec.error_reason();
  int picks = 0;
  for (const auto& tr : w.transitions) picks += tr.to == State::kPickPallet && tr.from != State::kPickPallet;
  EXPECT_EQ(picks, params.max_pick_attempts);
  ASSERT_FALSE(w.reports.empty());
  const TaskReport& failed = w.reports.back();
  EXPECT_EQ(failed.kind, Kind::kFailed);
  EXPECT_EQ(failed.order_id, "o1");
  EXPECT_EQ(failed.detail, "pick failed 3 times: pick timed out");
  EXPECT_FALSE(w.exec.carrying());
  ASSERT_TRUE(w.run_until([&] { return w.exec.state() == State::kIdle; }, 120.0));
  EXPECT_LT(geometry::distance(w.truth.position(), kHome.position()), 0.05);
}

TEST(TaskExecutor, FaultStopsAndReportsTheReason) {
  World w;
  ASSERT_TRUE(w.exec.submit({"o1", "A1", kA1, "A2", kA2}));
  w.run_until([] { return false; }, 0.5);
  w.exec.fault("localization lost");
  EXPECT_EQ(w.exec.state(), State::kError);
  EXPECT_EQ(w.exec.error_reason(), "localization lost");
  w.step();
  EXPECT_EQ(w.reports.back().kind, Kind::kFailed);
  EXPECT_EQ(w.reports.back().detail, "localization lost");
  EXPECT_EQ(w.reports.back().order_id, "o1");
  EXPECT_FALSE(w.exec.submit({"o2", "A1", kA1, "A2", kA2}));
  EXPECT_TRUE(w.exec.reset());
  EXPECT_EQ(w.exec.state(), State::kIdle);
}

}  // namespace
}  // namespace fleet::task

namespace fleet::task {
namespace {

using namespace test_world;

/// A loader's walk of three boxes at A1 and three at A2, its first `released` stops released.
TaskOrder loader_walk(std::size_t released) {
  TaskOrder walk;
  walk.order_id = "w1";
  walk.kind = orders::OrderKind::kPick;
  walk.loader = true;
  walk.released = released;
  walk.items = {{"A1", kA1, "I1", 3}, {"A2", kA2, "I2", 3}};
  return walk;
}

/// A2's stop of loader_walk released: the loader drives there, loads, and the walk ends.
void release_a2_and_end_the_walk(World& w, TaskOrder update) {
  update.released = 2;
  ASSERT_TRUE(w.exec.submit(update));
  ASSERT_TRUE(w.run_until([&] { return w.exec.state() == State::kPickItems; }, 60.0));
  EXPECT_LT(geometry::distance(w.truth.position(), w.exec.item_pose(kA2).position()), 0.1);
  w.exec.items_done(true);
  ASSERT_TRUE(w.run_until([&] { return w.exec.state() == State::kIdle; }, 60.0));
}

TEST(TaskExecutor, ALoaderDrivesOnlyToReleasedStopsAndWaitsForANewPalletAtHome) {
  World w;
  const TaskOrder walk = loader_walk(0);
  ASSERT_TRUE(w.exec.submit(walk));
  // Nothing released: it waits at home, where it is.
  w.run_until([] { return false; }, 5.0);
  EXPECT_EQ(w.exec.state(), State::kWaiting);
  EXPECT_LT(geometry::distance(w.truth.position(), kHome.position()), 0.05);

  // Its transporter stands behind A1's stop: the first stop is released.
  TaskOrder update = walk;
  update.released = 1;
  update.pallet = 7;
  ASSERT_TRUE(w.exec.submit(update));
  ASSERT_TRUE(w.run_until([&] { return w.exec.state() == State::kPickItems; }, 60.0));
  const geometry::Pose2 first_stop = w.exec.item_pose(kA1);
  EXPECT_LT(geometry::distance(w.truth.position(), first_stop.position()), 0.1);
  w.exec.items_done(true);
  // The same pallet moves up behind A2's stop: the loader stands where it is meanwhile.
  w.run_until([] { return false; }, 5.0);
  EXPECT_EQ(w.exec.state(), State::kWaiting);
  EXPECT_LT(geometry::distance(w.truth.position(), first_stop.position()), 0.1);

  // That pallet left full and a new one comes: the loader makes way, home.
  update.pallet = 8;
  ASSERT_TRUE(w.exec.submit(update));
  ASSERT_TRUE(w.run_until([&] { return geometry::distance(w.truth.position(), kHome.position()) < 0.05; }, 60.0));
  w.run_until([] { return false; }, 3.0);
  EXPECT_EQ(w.exec.state(), State::kWaiting) << "it waits at home, not done";

  // The new pallet stands behind A2's stop: on to it, and the walk ends there.
  release_a2_and_end_the_walk(w, update);
  EXPECT_EQ(w.kinds(), (std::vector<Kind>{Kind::kAccepted, Kind::kDropped, Kind::kHomeReached}));
  EXPECT_GT(w.t, 20.0) << "home, A1, home, A2, home at a walk's pace";
}

TEST(TaskExecutor, ALoaderFollowsItsPalletToAStopOpenToApproachAndWaitsThereForTheRelease) {
  World w;
  TaskOrder walk = loader_walk(1);
  walk.pallet = 7;
  ASSERT_TRUE(w.exec.submit(walk));
  ASSERT_TRUE(w.run_until([&] { return w.exec.state() == State::kPickItems; }, 60.0));
  w.exec.items_done(true);
  w.run_until([] { return false; }, 2.0);
  EXPECT_EQ(w.exec.state(), State::kWaiting) << "its pallet has not moved yet";

  // The pallet moves up ahead of it: it drives to A2's stop and stands there, its arm still.
  TaskOrder update = walk;
  update.approach = 2;
  ASSERT_TRUE(w.exec.submit(update));
  ASSERT_TRUE(w.run_until([&] { return w.exec.state() == State::kPickItems; }, 60.0));
  EXPECT_LT(geometry::distance(w.truth.position(), w.exec.item_pose(kA2).position()), 0.1);
  EXPECT_EQ(w.exec.item_line(), 1u);
  EXPECT_FALSE(w.exec.order()->released > w.exec.item_line()) << "the arm waits for the release";

  // The pallet was lost on its way and another comes in behind the stop: the loader makes way.
  update.approach = 0;
  update.pallet = 8;
  ASSERT_TRUE(w.exec.submit(update));
  ASSERT_TRUE(w.run_until([&] { return w.exec.state() == State::kWaiting; }, 60.0)) << "it waits at home, not done";
  EXPECT_LT(geometry::distance(w.truth.position(), kHome.position()), 0.05);

  // The new pallet stands behind A2's stop: back to it.
  release_a2_and_end_the_walk(w, update);
}

}  // namespace
}  // namespace fleet::task
