// Pausing and resuming a robot changes when it finishes, never where it ends up: for a pause at
// any moment of an order (so in every state the order passes through), of any length, while
// traffic blocks and frees the road, the robot ends idle at home with the pallet on the drop
// area and the same reports as without the pause.

#include <gtest/gtest.h>

#include <optional>
#include <set>
#include <sstream>

#include "executor_world.hpp"

namespace fleet::task {
namespace {

using namespace test_world;

// The traffic manager holds the robot back for a while on its way to the pick.
constexpr double kBlockedFrom = 0.5;
constexpr double kBlockedUntil = 4.0;
constexpr double kGiveUpAfter = 240.0;

struct Outcome {
  std::vector<Kind> reports;
  State end = State::kError;
  double finished_at = 0.0;
  Pose2 pose;
  Pose2 pallet;
  std::optional<State> paused_in;
};

Outcome run_order(std::optional<double> pause_at, double pause_for) {
  World w;
  const int pallet = w.pallets.add(kA1);
  Outcome out;
  if (!w.exec.submit({"o1", "A1", kA1, "A2", kA2})) return out;
  bool blocked = false;
  bool paused = false;
  bool resumed = false;
  while (w.t < kGiveUpAfter) {
    const bool want_blocked = w.t >= kBlockedFrom && w.t < kBlockedUntil;
    if (want_blocked != blocked) {
      w.exec.set_blocked(want_blocked);
      blocked = want_blocked;
    }
    if (pause_at && !paused && w.t >= *pause_at) {
      out.paused_in = w.exec.state();
      if (!w.exec.pause()) return out;
      paused = true;
    }
    if (paused && !resumed && w.t >= *pause_at + pause_for) {
      if (!w.exec.resume()) return out;
      resumed = true;
    }
    if (w.exec.state() == State::kIdle && (!pause_at || resumed)) break;
    w.step();
  }
  out.reports = w.kinds();
  out.end = w.exec.state();
  out.finished_at = w.t;
  out.pose = w.truth;
  out.pallet = w.pallets.find(pallet)->pose;
  return out;
}

std::string describe(const Outcome& o) {
  std::ostringstream s;
  s << "ended " << to_string(o.end) << " at t = " << o.finished_at << " s, at (" << o.pose.x << ", " << o.pose.y
    << "), pallet at (" << o.pallet.x << ", " << o.pallet.y << "), " << o.reports.size() << " reports";
  return s.str();
}

TEST(TaskPauseProperty, APauseInAnyStateOfAnyLengthOnlyDelaysTheOrder) {
  const Outcome plain = run_order(std::nullopt, 0.0);
  ASSERT_EQ(plain.end, State::kIdle) << describe(plain);
  ASSERT_EQ(plain.reports, (std::vector<Kind>{Kind::kAccepted, Kind::kPicked, Kind::kDropped, Kind::kHomeReached}));

  std::set<State> paused_in;
  for (double pause_at = 0.2; pause_at < plain.finished_at; pause_at += 0.35) {
    // Shorter than the wait, longer than what is left of it, and longer than a manoeuvre's timers.
    for (const double pause_for : {0.4, 3.0, 7.0}) {
      const Outcome o = run_order(pause_at, pause_for);
      SCOPED_TRACE("paused at t = " + std::to_string(pause_at) + " s in " +
                   (o.paused_in ? to_string(*o.paused_in) : std::string("?")) + " for " + std::to_string(pause_for) +
                   " s: " + describe(o));
      ASSERT_TRUE(o.paused_in.has_value());
      paused_in.insert(*o.paused_in);
      EXPECT_EQ(o.end, State::kIdle);
      EXPECT_EQ(o.reports, plain.reports);
      EXPECT_LT(geometry::distance(o.pose.position(), kHome.position()), 0.03);
      EXPECT_LT(geometry::distance(o.pallet.position(), kA2.position()), 0.02);
      // The pause itself, plus a manoeuvre started again from where the robot stands.
      EXPECT_LT(o.finished_at, plain.finished_at + pause_for + 15.0);
    }
  }
  // The pauses fell in every state the order passes through, waiting for traffic among them.
  const std::set<State> every{State::kTrackPath,  State::kWaiting,    State::kSearchPallet,
                              State::kPickPallet, State::kDropPallet, State::kGoHome};
  EXPECT_EQ(paused_in, every);
}

// Regression: paused while WAITING for traffic, the road freed during the pause, resumed: the
// robot stood in WAITING for good while the manager held the road granted to it.
TEST(TaskPauseProperty, PausedWhileWaitingAndFreedDuringThePauseItDrivesOnAfterTheResume) {
  const Outcome o = run_order(kBlockedFrom + 0.5, kBlockedUntil - kBlockedFrom);
  ASSERT_EQ(o.paused_in, State::kWaiting);
  EXPECT_EQ(o.end, State::kIdle) << describe(o);
}

}  // namespace
}  // namespace fleet::task
