#include "monitor/progress_monitor.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

namespace fleet::monitor {
namespace {

TEST(ProgressMonitor, RobotStandingStillWithAnOrderForTheTimeoutIsOneDeadlock) {
  ProgressMonitor m(60.0, 0.02);
  const geometry::Pose2 here{1.0, 1.0, 0.0};
  EXPECT_FALSE(m.update("fl1", here, "7/TO_PICK", 0.0));
  EXPECT_FALSE(m.update("fl1", {1.01, 1.0, 0.5}, "7/TO_PICK", 59.9));  // a turn on the spot is not progress
  EXPECT_TRUE(m.update("fl1", here, "7/TO_PICK", 60.0));
  EXPECT_FALSE(m.update("fl1", here, "7/TO_PICK", 200.0));  // the same episode counts once
  ASSERT_EQ(m.deadlocks().size(), 1u);
  EXPECT_EQ(m.deadlocks()[0].robot_id, "fl1");
  EXPECT_EQ(m.deadlocks()[0].task, "7/TO_PICK");
  EXPECT_DOUBLE_EQ(m.deadlocks()[0].since, 0.0);
  // Moving on starts a new episode, which can be counted again.
  EXPECT_FALSE(m.update("fl1", {1.5, 1.0, 0.0}, "7/TO_PICK", 201.0));
  EXPECT_TRUE(m.update("fl1", {1.5, 1.0, 0.0}, "7/TO_PICK", 261.0));
  EXPECT_EQ(m.deadlocks().size(), 2u);
}

TEST(ProgressMonitor, MovingOrChangingPhaseOrHavingNoOrderIsNotADeadlock) {
  ProgressMonitor m(60.0, 0.02);
  m.update("fl1", {0, 0, 0}, "7/PICKING", 0.0);
  EXPECT_FALSE(m.update("fl1", {0, 0, 0}, "7/TO_DROP", 50.0));  // a phase change is progress
  EXPECT_FALSE(m.update("fl1", {0, 0, 0}, "7/TO_DROP", 100.0));
  m.update("fl2", {0, 0, 0}, "", 0.0);
  EXPECT_FALSE(m.update("fl2", {0, 0, 0}, "", 500.0));  // idle at home
  for (int i = 1; i <= 20; ++i) EXPECT_FALSE(m.update("fl3", {0.05 * i, 0, 0}, "9/TO_PICK", 10.0 * i));
  EXPECT_TRUE(m.deadlocks().empty());
}

TEST(ProgressMonitor, ARobotQueuedBehindRobotsThatMoveWaitsItsTurnUpToTheQueueBound) {
  ProgressMonitor m(60.0, 0.02, 180.0);
  // rt4 waits for rt3, which waits for rt1, which drives away: a queue leaving one at a time.
  m.note_waiting_for("rt4", {"rt3"});
  m.note_waiting_for("rt3", {"rt1"});
  for (int s = 0; s <= 100; ++s) {
    const double t = s;
    EXPECT_FALSE(m.update("rt1", {0.1 * s, 0.0, 0.0}, "1/TO_PICK", t));
    EXPECT_FALSE(m.update("rt3", {5.0, 0.0, 0.0}, "3/TO_PICK", t));
    EXPECT_FALSE(m.update("rt4", {6.0, 0.0, 0.0}, "4/TO_PICK", t)) << "at t = " << t;
  }
  // Its turn come, it is granted and waits for nobody: the time it spent queued does not count.
  m.note_waiting_for("rt4", {});
  EXPECT_FALSE(m.update("rt4", {6.0, 0.0, 0.0}, "4/TO_PICK", 100.5));
  m.note_waiting_for("rt4", {"rt3"});
  // The same queue whose head stands still is a deadlock after the timeout, for all behind it.
  m.note_waiting_for("rt1", {"rt4"});
  bool rt4_reported = false;
  for (int s = 101; s <= 170 && !rt4_reported; ++s) {
    m.update("rt1", {10.0, 0.0, 0.0}, "1/TO_PICK", s);
    m.update("rt3", {5.0, 0.0, 0.0}, "3/TO_PICK", s);
    rt4_reported = m.update("rt4", {6.0, 0.0, 0.0}, "4/TO_PICK", s);
  }
  EXPECT_TRUE(rt4_reported);
  // A robot queued behind one that moves for ever is reported at the queue bound.
  ProgressMonitor q(60.0, 0.02, 180.0);
  q.note_waiting_for("fl2", {"fl1"});
  double reported_at = -1.0;
  for (int s = 0; s <= 200 && reported_at < 0.0; ++s) {
    q.update("fl1", {0.1 * (s % 2), 0.0, 0.0}, "1/TO_PICK", s);
    if (q.update("fl2", {3.0, 0.0, 0.0}, "2/TO_PICK", s)) reported_at = s;
  }
  EXPECT_DOUBLE_EQ(reported_at, 180.0);
}

// An arm at work, a transporter holding its pallet behind its picker: standing by design is
// progress, but the phase stays bounded.
TEST(ProgressMonitor, StandingByDesignIsProgressUpToThePhaseBound) {
  ProgressMonitor m(60.0, 0.02, 180.0, 900.0);
  const geometry::Pose2 stop{41.2, 10.6, 3.14};
  bool counted = false;
  for (double t = 0.0; t < 899.0; t += 1.0) counted = m.update("pk1", stop, "8/PICKING", t, true) || counted;
  EXPECT_FALSE(counted);
  EXPECT_TRUE(m.update("pk1", stop, "8/PICKING", 900.0, true)) << "one phase for the phase bound";
  EXPECT_FALSE(m.update("st1", stop, "9/TO_DROP", 0.0, true));
  EXPECT_FALSE(m.update("st1", stop, "9/TO_DROP", 30.0, false));
  EXPECT_TRUE(m.update("st1", stop, "9/TO_DROP", 90.0, false)) << "standing without a reason counts again";
}

TEST(ProgressMonitor, ARobotMovingAboutInOnePhaseForThePhaseBoundIsOneDeadlock) {
  // Pushed back and forth, re-routed round and round: it moves, but its order gets nowhere.
  ProgressMonitor m(60.0, 0.02, 180.0, 900.0);
  for (double t = 0.0; t <= 2000.0; t += 5.0) {
    const double x = static_cast<int>(t / 5.0) % 2 == 0 ? 1.0 : 1.3;
    m.update("fl1", {x, 1.0, 0.0}, "7/TO_PICK", t);
    // Another robot moves just as much but gets on with its order: a phase every 300 s.
    m.update("fl2", {x, 2.0, 0.0}, "8/" + std::to_string(static_cast<int>(t / 300.0)), t);
  }
  ASSERT_EQ(m.deadlocks().size(), 1u) << "once per phase";
  EXPECT_EQ(m.deadlocks()[0].robot_id, "fl1");
  EXPECT_DOUBLE_EQ(m.deadlocks()[0].since, 0.0);
  EXPECT_DOUBLE_EQ(m.deadlocks()[0].detected, 900.0);
}

TEST(ProgressMonitor, ForgottenRobotRestartsItsWatch) {
  ProgressMonitor m(60.0, 0.02);
  m.update("fl1", {0, 0, 0}, "7/TO_PICK", 0.0);
  m.forget("fl1");
  EXPECT_FALSE(m.update("fl1", {0, 0, 0}, "7/TO_PICK", 70.0));
  EXPECT_TRUE(m.update("fl1", {0, 0, 0}, "7/TO_PICK", 130.0));
}

TEST(ProgressMonitor, LongestWaitIncludesOngoingWaits) {
  ProgressMonitor m;
  m.note_state("fl1", "WAITING", 10.0);
  m.note_state("fl1", "TRACK_PATH", 14.0);
  m.note_state("fl2", "WAITING", 20.0);
  EXPECT_DOUBLE_EQ(m.max_wait_s(22.0), 4.0);
  EXPECT_DOUBLE_EQ(m.max_wait_s(30.0), 10.0);
  m.note_state("fl2", "WAITING", 25.0);  // still the same wait
  EXPECT_DOUBLE_EQ(m.max_wait_s(30.0), 10.0);
}

}  // namespace
}  // namespace fleet::monitor

#include "common/errors.hpp"
#include "monitor/fault_plan.hpp"

namespace fleet::monitor {
namespace {

TEST(FaultPlan, ParsesListsAndNamesAnUnknownFault) {
  EXPECT_TRUE(parse_fault_list("none").empty());
  EXPECT_EQ(parse_fault_list("all").size(), 5u);
  const auto all = parse_fault_list("all");
  EXPECT_EQ(std::count(all.begin(), all.end(), FaultKind::kKillHost), 0) << "kill-host needs a standby: named only";
  EXPECT_EQ(parse_fault_list("kill-host"), std::vector<FaultKind>{FaultKind::kKillHost});
  const auto two = parse_fault_list("kill-agent,obstacles,kill-agent");
  ASSERT_EQ(two.size(), 2u);
  EXPECT_EQ(two[0], FaultKind::kKillAgent);
  EXPECT_EQ(two[1], FaultKind::kObstacles);
  try {
    parse_fault_list("kill-agent,explode");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'explode'"), std::string::npos);
  }
}

TEST(FaultPlan, ALossIsExplainedOnlyByAFaultOfThatRobotOrOfTheServerJustBefore) {
  const std::vector<InjectedFault> faults{{FaultKind::kKillAgent, "fl2", 100.0},
                                          {FaultKind::kStallAgent, "fl1", 200.0},
                                          {FaultKind::kMapSwitch, "", 300.0},
                                          {FaultKind::kKillServer, "", 400.0}};
  const std::vector<RobotLoss> losses{
      {"fl2", 101.0, 1010.0},  // its agent killed a second before
      {"fl1", 201.0, 2010.0},  // its agent stopped
      {"fl3", 101.5, 1015.0},  // another robot's agent was killed: not this one's
      {"fl1", 230.0, 2300.0},  // long after its stall ended
      {"fl4", 300.8, 3008.0},  // right after a map switch: nothing stops a robot there
      {"fl4", 401.0, 4010.0},  // the server restarted
      {"fl2", 99.0, 990.0},    // before its kill
  };
  const auto left = unexplained_losses(losses, faults, 10.0);
  std::vector<double> at;
  for (const auto& l : left) at.push_back(l.at_sim);
  EXPECT_EQ(at, (std::vector<double>{1015.0, 2300.0, 3008.0, 990.0}));
}

TEST(FaultPlan, IsReproducibleUsesEveryKindEachRoundAndKeepsTheTailQuiet) {
  const auto kinds = parse_fault_list("kill-agent,stall-agent,kill-server,obstacles");
  const auto a = plan_faults(kinds, 1800.0, 120.0, 200.0, 4, 4, 7);
  const auto b = plan_faults(kinds, 1800.0, 120.0, 200.0, 4, 4, 7);
  ASSERT_EQ(a.size(), b.size());
  ASSERT_GE(a.size(), 12u);
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].at_sim, b[i].at_sim);
    EXPECT_EQ(a[i].kind, b[i].kind);
    EXPECT_EQ(a[i].target, b[i].target);
    EXPECT_LE(a[i].at_sim, 1600.0);
    EXPECT_GE(a[i].target, 0);
    EXPECT_LT(a[i].target, 4);
  }
  for (std::size_t round = 0; round + 4 <= a.size(); round += 4) {
    std::vector<int> seen(5, 0);
    for (std::size_t i = round; i < round + 4; ++i) ++seen[static_cast<int>(a[i].kind)];
    for (FaultKind k : kinds) EXPECT_EQ(seen[static_cast<int>(k)], 1) << to_string(k);
  }
  const auto other = plan_faults(kinds, 1800.0, 120.0, 200.0, 4, 4, 8);
  bool differs = false;
  for (std::size_t i = 0; i < std::min(a.size(), other.size()); ++i) {
    differs = differs || a[i].kind != other[i].kind || a[i].target != other[i].target;
  }
  EXPECT_TRUE(differs);
}

}  // namespace
}  // namespace fleet::monitor
