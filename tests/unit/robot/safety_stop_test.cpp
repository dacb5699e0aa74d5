// The safety stop every robot type drives under, tested without a robot: a 0.25 m x 0.16 m body
// at the origin facing +x, neighbours and lidar returns placed around it.
#include "robot/safety_stop.hpp"

#include <gtest/gtest.h>

#include <limits>

namespace fleet::robot {
namespace {

const geometry::Footprint kBody{0.25, 0.16};
const geometry::Pose2 kHere{0.0, 0.0, 0.0};

SafetyStop make_stop() {
  return SafetyStop({.safety_gap = 0.03, .stale_after = 0.5, .neighbour_max_speed = 0.3}, kBody);
}

/// A neighbour standing `gap` metres ahead of this body, footprint to footprint, its pose fresh.
Neighbour ahead_by(double gap, const std::string& id = "fl2") {
  return {id, {kBody.length + gap, 0.0, 0.0}, kBody, 0.0, 0.0};
}

TEST(SafetyStop, HoldsACommandThatWouldBringTheFootprintWithinTheGapOfANeighbour) {
  const SafetyStop stop = make_stop();
  const std::vector<Neighbour> others{ahead_by(0.05)};
  // 0.1 m/s forward closes 4 cm of the 5 cm within the 0.4 s horizon: 1 cm left, under the gap.
  const control::BodyTwist forward{0.1, 0.0, 0.0};
  EXPECT_TRUE(stop.moves_too_close(forward, kHere, others));
  EXPECT_EQ(stop.safe(forward, kHere, others), control::BodyTwist{});
  // Slow enough to keep the gap over the horizon, it drives on.
  const control::BodyTwist creep{0.04, 0.0, 0.0};
  EXPECT_EQ(stop.safe(creep, kHere, others), creep);
}

TEST(SafetyStop, LetsACommandThatMovesAwayPassEvenWithinTheGap) {
  const SafetyStop stop = make_stop();
  const std::vector<Neighbour> others{ahead_by(0.01)};
  const control::BodyTwist back{-0.1, 0.0, 0.0};
  EXPECT_FALSE(stop.moves_too_close(back, kHere, others));
  EXPECT_EQ(stop.safe(back, kHere, others), back);
  const control::BodyTwist sideways_away{0.0, 0.1, 0.0};
  EXPECT_EQ(stop.safe(sideways_away, {0.0, 0.0, 0.0}, {{"fl3", {0.0, -0.17, 0.0}, kBody, 0.0, 0.0}}), sideways_away);
}

TEST(SafetyStop, ANeighboursPoseCountsAsEverywhereItCouldHaveReachedSince) {
  const SafetyStop stop = make_stop();
  // 25 cm ahead: far enough for a pose just measured. 4 cm closer over the horizon.
  const control::BodyTwist forward{0.1, 0.0, 0.0};
  const Neighbour fresh = ahead_by(0.25);
  EXPECT_FALSE(stop.moves_too_close(forward, kHere, {fresh}));
  // A standing robot's pose 0.4 s old (younger than stale_after) has not moved.
  Neighbour standing = fresh;
  standing.age = 0.4;
  EXPECT_FALSE(stop.moves_too_close(forward, kHere, {standing}));
  // At 0.5 m/s it may have come 20 cm closer.
  Neighbour moving = standing;
  moving.speed = 0.5;
  EXPECT_TRUE(stop.moves_too_close(forward, kHere, {moving}));
  // Beyond stale_after it grows by the top speed whatever the reported one: a little late, a
  // little (0.2 s x 0.3 m/s); longer silent, more (0.7 s x 0.3 m/s).
  Neighbour late = fresh;
  late.age = 0.7;
  EXPECT_FALSE(stop.moves_too_close(forward, kHere, {late}));
  Neighbour stale = fresh;
  stale.age = 1.2;
  EXPECT_TRUE(stop.moves_too_close(forward, kHere, {stale}));
  EXPECT_FALSE(stop.moves_too_close({-0.1, 0.0, 0.0}, kHere, {stale})) << "moving away stays allowed";
}

TEST(SafetyStop, ALidarReturnStopsItAndCloseBesideItStepsAwaySlowly) {
  SafetyStop stop = make_stop();
  // A return 2 cm in front of the body and nobody in FleetView: the lidar alone stops it, and
  // within 10 cm the body steps straight away from the return at 3 cm/s.
  stop.set_returns({{kBody.length / 2 + 0.02, 0.0}});
  const control::BodyTwist forward{0.1, 0.0, 0.0};
  EXPECT_TRUE(stop.moves_too_close(forward, kHere, {}));
  const control::BodyTwist escape = stop.safe(forward, kHere, {});
  EXPECT_NEAR(escape.vx, -0.03, 1e-9);
  EXPECT_NEAR(escape.vy, 0.0, 1e-9);
  EXPECT_NEAR(escape.omega, 0.0, 1e-9);
  // Further off (11 cm), a stop without a step.
  stop.set_returns({{kBody.length / 2 + 0.11, 0.0}});
  EXPECT_EQ(stop.safe({0.3, 0.0, 0.0}, kHere, {}), control::BodyTwist{});
}

TEST(SafetyStop, AScanKeepsOnlyTheReturnsNearTheRobot) {
  SafetyStop stop = make_stop();
  planning::LidarScan scan;
  scan.pose = kHere;
  scan.angle_min = 0.0;
  scan.angle_increment = 0.5;
  scan.ranges = {0.145, 2.0, std::numeric_limits<double>::infinity()};  // straight ahead 2 cm off the body
  stop.take_scan(scan);
  EXPECT_TRUE(stop.moves_too_close({0.1, 0.0, 0.0}, kHere, {}));
  scan.ranges = {2.0};
  stop.take_scan(scan);
  EXPECT_FALSE(stop.moves_too_close({0.1, 0.0, 0.0}, kHere, {}));
}

TEST(SafetyStop, ALastingStopIsReportedForTheRobotItStandsFor) {
  SafetyStop stop = make_stop();
  const std::vector<Neighbour> others{ahead_by(0.3, "fl9"), ahead_by(0.02, "fl4")};
  EXPECT_EQ(stop.robot_within(kHere, others, 0.5), "fl4");
  EXPECT_EQ(stop.robot_within(kHere, {ahead_by(0.6)}, 0.5), "");
  const geometry::Vec2 here = kHere.position();
  // Stopped for fl4 from t = 10, the check flickering (a step without a stop now and then).
  for (double t = 10.0; t < 13.5; t += 0.5) stop.note(t, here, "fl4");
  EXPECT_TRUE(stop.stopped_for(12.5, here).empty()) << "a short stop is its own business";
  EXPECT_EQ(stop.stopped_for(13.2, here), std::vector<std::string>{"fl4"});
  // Moved away from where it stopped, or not stopped for a while, it waits for no one.
  EXPECT_TRUE(stop.stopped_for(13.2, {0.1, 0.0}).empty());
  EXPECT_TRUE(stop.stopped_for(15.0, here).empty());
  // Stopped for another robot, the count starts again; a new route clears it.
  stop.note(13.5, here, "fl9");
  EXPECT_TRUE(stop.stopped_for(13.5, here).empty());
  for (double t = 14.0; t <= 17.0; t += 0.5) stop.note(t, here, "fl9");
  EXPECT_EQ(stop.stopped_for(17.0, here), std::vector<std::string>{"fl9"});
  stop.clear();
  EXPECT_TRUE(stop.stopped_for(17.0, here).empty());
}

}  // namespace
}  // namespace fleet::robot
