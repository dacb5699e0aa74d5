#include "control/path_follower.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

namespace fleet::control {
namespace {

using geometry::Pose2;

constexpr double kDt = 1.0 / 70.0;  // pose and control at 70 Hz [Forklift thesis, Table 3.1]

std::vector<Pose2> line_path(double length, double spacing) {
  std::vector<Pose2> path;
  const int n = static_cast<int>(std::round(length / spacing));
  for (int i = 0; i <= n; ++i) path.push_back({i * spacing, 0.0, 0.0});
  return path;
}

std::vector<Pose2> arc_path(double radius, double sweep, double spacing) {
  // Counter-clockwise arc centred on (0, radius), starting at the origin heading +x.
  std::vector<Pose2> path;
  const int n = static_cast<int>(std::ceil(radius * sweep / spacing));
  for (int i = 0; i <= n; ++i) {
    const double a = sweep * i / n;
    path.push_back({radius * std::sin(a), radius - radius * std::cos(a), a});
  }
  return path;
}

struct RunResult {
  Pose2 final_pose;
  double max_late_cross = 0.0;  ///< |cross-track| over the second half of the run
  double max_domega = 0.0;      ///< largest omega change between steps while tracking
  bool arrived = false;
  int steps = 0;
};

RunResult run(PathFollower& f, Pose2 pose, double max_time, double late_from_s) {
  RunResult r;
  BodyTwist prev;
  double travelled = 0.0;
  for (int i = 0; i < static_cast<int>(max_time / kDt); ++i) {
    const BodyTwist cmd = f.step({pose, i == 0 ? 0.0 : kDt});
    EXPECT_DOUBLE_EQ(cmd.vy, 0.0) << "the follower drives in differential mode";
    if (f.status() == FollowerStatus::kTracking && i > 0) {
      r.max_domega = std::max(r.max_domega, std::abs(cmd.omega - prev.omega));
    }
    if (travelled > late_from_s && f.status() == FollowerStatus::kTracking) {
      r.max_late_cross = std::max(r.max_late_cross, std::abs(f.debug().cross_track));
    }
    prev = cmd;
    travelled += std::abs(cmd.vx) * kDt;
    pose = integrate_twist(pose, cmd, kDt);
    r.steps = i;
    if (f.arrived()) break;
  }
  r.final_pose = pose;
  r.arrived = f.arrived();
  return r;
}

TEST(SpeedLaw, Eq62EndPoints) {
  // v_max at omega = 0, zero at omega_max, linear in between [Forklift thesis, eq. 6.2].
  EXPECT_DOUBLE_EQ(speed_law(0.0, 0.2, 2.0), 0.2);
  EXPECT_DOUBLE_EQ(speed_law(2.0, 0.2, 2.0), 0.0);
  EXPECT_DOUBLE_EQ(speed_law(-2.0, 0.2, 2.0), 0.0);
  EXPECT_DOUBLE_EQ(speed_law(1.0, 0.2, 2.0), 0.1);
  EXPECT_DOUBLE_EQ(speed_law(-0.5, 0.2, 2.0), 0.15);
  // Beyond the limit the robot turns in place, it never backs up.
  EXPECT_DOUBLE_EQ(speed_law(5.0, 0.2, 2.0), 0.0);
}

TEST(PathFollower, CommandsRespectOmegaMaxAndSpeedLaw) {
  FollowerParams p;
  PathFollower f(p);
  f.set_path(line_path(1.0, 0.1));
  // Facing backwards: beta is about pi, omega saturates and the robot turns in place.
  const BodyTwist cmd = f.step({{0.0, 0.0, 3.0}, 0.0});
  EXPECT_NEAR(std::abs(cmd.omega), p.omega_max, 1e-12);
  EXPECT_NEAR(cmd.vx, 0.0, 1e-12);
  const BodyTwist cmd2 = f.step({{0.0, 0.0, 3.0}, kDt});
  EXPECT_NEAR(cmd2.vx, speed_law(cmd2.omega, p.v_max, p.omega_max), 1e-12);
}

TEST(PathFollower, ConvergesOntoStraightLineFromOffset) {
  for (bool smooth : {false, true}) {
    FollowerParams p = smooth ? FollowerParams::regulated() : FollowerParams{};
    PathFollower f(p);
    f.set_path(line_path(2.0, 0.1));
    const RunResult r = run(f, {0.0, 0.06, 0.3}, 30.0, 0.8);
    EXPECT_TRUE(r.arrived) << "smooth=" << smooth;
    EXPECT_LT(r.max_late_cross, 0.005) << "smooth=" << smooth;
    EXPECT_NEAR(r.final_pose.x, 2.0, 0.02) << "smooth=" << smooth;
    EXPECT_NEAR(r.final_pose.y, 0.0, 0.005) << "smooth=" << smooth;
    EXPECT_NEAR(geometry::angle_diff(r.final_pose.yaw, 0.0), 0.0, p.heading_tolerance + 1e-9);
  }
}

TEST(PathFollower, ConvergesOntoArcFromOffset) {
  for (bool smooth : {false, true}) {
    FollowerParams p = smooth ? FollowerParams::regulated() : FollowerParams{};
    PathFollower f(p);
    const double radius = 0.6;
    f.set_path(arc_path(radius, std::numbers::pi, 0.1));
    const RunResult r = run(f, {0.0, -0.05, -0.2}, 40.0, 0.8);
    EXPECT_TRUE(r.arrived) << "smooth=" << smooth;
    // Polyline chords of a 0.6 m arc sampled every 10 cm sag by about 2 mm; a lookahead
    // controller cuts inside a little more.
    EXPECT_LT(r.max_late_cross, 0.012) << "smooth=" << smooth;
    EXPECT_NEAR(std::hypot(r.final_pose.x, r.final_pose.y - 2 * radius), 0.0, 0.03);
  }
}

TEST(PathFollower, SmoothLookaheadRemovesCommandJumps) {
  // The seed notes jerky commands when the target switches between path points (Fig. 6.4b).
  // A coarse path makes the switches large; the interpolated target makes them vanish.
  const auto path = arc_path(0.5, std::numbers::pi / 2, 0.15);
  FollowerParams seed;
  FollowerParams smooth;
  smooth.smooth_lookahead = true;
  PathFollower a(seed);
  PathFollower b(smooth);
  a.set_path(path);
  b.set_path(path);
  const RunResult ra = run(a, {0.0, 0.0, 0.0}, 20.0, 0.0);
  const RunResult rb = run(b, {0.0, 0.0, 0.0}, 20.0, 0.0);
  EXPECT_TRUE(ra.arrived);
  EXPECT_TRUE(rb.arrived);
  EXPECT_LT(rb.max_domega, 0.5 * ra.max_domega);
}

TEST(PathFollower, PoseTargetReachesPointThenHeading) {
  PathFollower f;
  const Pose2 target{0.3, 0.2, std::numbers::pi / 2};
  f.set_pose_target(target);
  const RunResult r = run(f, {0.0, 0.0, 0.0}, 20.0, 0.0);
  ASSERT_TRUE(r.arrived);
  EXPECT_LT(geometry::distance(r.final_pose.position(), target.position()), 0.012);
  EXPECT_LT(std::abs(geometry::angle_diff(r.final_pose.yaw, target.yaw)), 0.021);
}

TEST(PathFollower, StopsAtTheEndOnlyOnceHeadingIsAligned) {
  PathFollower f;
  // A path whose last pose asks for a heading 90 degrees off the last leg: the follower drives
  // to the end, then turns in place.
  auto path = line_path(0.5, 0.1);
  path.back().yaw = std::numbers::pi / 2;
  f.set_path(path);
  Pose2 pose{0.0, 0.0, 0.0};
  bool saw_aligning = false;
  for (int i = 0; i < 2000 && !f.arrived(); ++i) {
    const BodyTwist cmd = f.step({pose, i == 0 ? 0.0 : kDt});
    if (f.status() == FollowerStatus::kAligning) {
      saw_aligning = true;
      EXPECT_DOUBLE_EQ(cmd.vx, 0.0);
    }
    pose = integrate_twist(pose, cmd, kDt);
  }
  EXPECT_TRUE(saw_aligning);
  ASSERT_TRUE(f.arrived());
  EXPECT_NEAR(pose.x, 0.5, 0.02);
  EXPECT_NEAR(geometry::angle_diff(pose.yaw, std::numbers::pi / 2), 0.0, 0.021);
  EXPECT_EQ(f.step({pose, kDt}), BodyTwist{});
}

TEST(PathFollower, TurnsAroundAtACusp) {
  // A route that runs up a single-lane road and comes back down it, as road-graph routes do
  // between two areas on the same road.
  std::vector<Pose2> path;
  for (int i = 0; i <= 8; ++i) path.push_back({0.1 * i, 0.0, 0.0});
  for (int i = 7; i >= 2; --i) path.push_back({0.1 * i, 0.0, std::numbers::pi});
  path.back().yaw = std::numbers::pi;
  for (bool smooth : {false, true}) {
    FollowerParams p = smooth ? FollowerParams::regulated() : FollowerParams{};
    PathFollower f(p);
    f.set_path(path);
    Pose2 pose{0.0, 0.0, 0.0};
    double max_x = 0.0;
    double max_cross = 0.0;
    for (int i = 0; i < 70 * 40 && !f.arrived(); ++i) {
      const BodyTwist cmd = f.step({pose, i == 0 ? 0.0 : kDt});
      pose = integrate_twist(pose, cmd, kDt);
      max_x = std::max(max_x, pose.x);
      max_cross = std::max(max_cross, std::abs(pose.y));
    }
    ASSERT_TRUE(f.arrived()) << "smooth=" << smooth;
    EXPECT_GT(max_x, 0.78) << "reached the cusp before turning, smooth=" << smooth;
    EXPECT_LT(max_cross, 0.03) << "smooth=" << smooth;
    EXPECT_NEAR(pose.x, 0.2, 0.02) << "smooth=" << smooth;
    EXPECT_NEAR(std::abs(pose.yaw), std::numbers::pi, 0.03) << "smooth=" << smooth;
  }
}

TEST(PathFollower, DoesNotTurnRoundToTouchARoadPointJustBehindIt) {
  // A forklift parked 5 cm short of its stall's road point: its route out starts with that point,
  // behind it, and turns back on itself there. Turning round in a stall beside a parked neighbour
  // sweeps its corners into the neighbour.
  std::vector<Pose2> path{{0.0, 0.0, std::numbers::pi}, {0.05, 0.0, 0.0}};
  for (int i = 1; i <= 10; ++i) path.push_back({0.05 - 0.1 * i, 0.0, std::numbers::pi});
  for (const double shortest : {0.0, 0.25}) {
    FollowerParams p = FollowerParams::regulated();
    p.shortest_first_leg = shortest;
    p.reverse_legs_up_to = 0.0;
    PathFollower f(p);
    f.set_path(path);
    Pose2 pose{0.0, 0.0, std::numbers::pi};
    double max_turn = 0.0;
    for (int i = 0; i < 70 * 40 && !f.arrived(); ++i) {
      const BodyTwist cmd = f.step({pose, i == 0 ? 0.0 : kDt});
      pose = integrate_twist(pose, cmd, kDt);
      max_turn = std::max(max_turn, std::abs(geometry::angle_diff(pose.yaw, std::numbers::pi)));
    }
    ASSERT_TRUE(f.arrived()) << "shortest_first_leg=" << shortest;
    EXPECT_NEAR(pose.x, -0.95, 0.03) << "shortest_first_leg=" << shortest;
    if (shortest > 0.0) {
      EXPECT_LT(max_turn, 0.1);
    } else {
      EXPECT_GT(max_turn, 3.0) << "the thesis's follower drives every leg";
    }
  }
}

TEST(PathFollower, BacksIntoAStallWhoseHeadingPointsOutOfIt) {
  // Along a lane, then up a 0.4 m stall to a home that faces back out of it, as parking stalls
  // side by side do. Turning round at the stall's end sweeps the body into the stalls beside it.
  std::vector<Pose2> path;
  for (int i = 0; i <= 10; ++i) path.push_back({0.1 * i, 0.0, 0.0});
  for (int i = 1; i <= 4; ++i) path.push_back({1.0, 0.1 * i, std::numbers::pi / 2});
  path.back().yaw = -std::numbers::pi / 2;
  for (const bool back_in : {false, true}) {
    PathFollower f(FollowerParams::regulated());
    f.set_path(path, back_in);
    Pose2 pose{0.0, 0.0, 0.0};
    double most_turned_in_stall = 0.0;
    bool reversed = false;
    for (int i = 0; i < 70 * 40 && !f.arrived(); ++i) {
      const BodyTwist cmd = f.step({pose, i == 0 ? 0.0 : kDt});
      reversed = reversed || cmd.vx < -1e-3;
      pose = integrate_twist(pose, cmd, kDt);
      if (pose.y > 0.1) {
        most_turned_in_stall =
            std::max(most_turned_in_stall, std::abs(geometry::angle_diff(pose.yaw, -std::numbers::pi / 2)));
      }
    }
    ASSERT_TRUE(f.arrived()) << "back_in=" << back_in;
    EXPECT_NEAR(pose.x, 1.0, 0.03) << "back_in=" << back_in;
    EXPECT_NEAR(pose.y, 0.4, 0.03) << "back_in=" << back_in;
    EXPECT_NEAR(geometry::angle_diff(pose.yaw, -std::numbers::pi / 2), 0.0, 0.03) << "back_in=" << back_in;
    EXPECT_EQ(reversed, back_in);
    if (back_in) {
      EXPECT_LT(most_turned_in_stall, 0.2);
    } else {
      EXPECT_GT(most_turned_in_stall, 3.0) << "without backing in it turns round at the end";
    }
  }
}

TEST(PathFollower, BacksUpAShortLegBehindItInsteadOfTurningRoundTwice) {
  // Pushed back two places along a lane by a robot coming the other way, then sent on the way it
  // faces: turning round at both ends of the short leg sweeps its corners into the robots in
  // front of it and behind it.
  std::vector<Pose2> path{{0.0, 0.0, 0.0}, {-0.09, 0.0, 0.0}, {-0.18, 0.0, 0.0}};
  for (int i = -1; i <= 10; ++i) path.push_back({0.09 * i, 0.0, 0.0});
  for (const double reverse_up_to : {0.0, 0.4}) {
    FollowerParams p = FollowerParams::regulated();
    p.reverse_legs_up_to = reverse_up_to;
    p.shortest_first_leg = 0.0;
    PathFollower f(p);
    f.set_path(path);
    Pose2 pose{0.0, 0.0, 0.0};
    double most_turned = 0.0;
    double min_x = 0.0;
    for (int i = 0; i < 70 * 40 && !f.arrived(); ++i) {
      const BodyTwist cmd = f.step({pose, i == 0 ? 0.0 : kDt});
      pose = integrate_twist(pose, cmd, kDt);
      most_turned = std::max(most_turned, std::abs(geometry::angle_diff(pose.yaw, 0.0)));
      min_x = std::min(min_x, pose.x);
    }
    ASSERT_TRUE(f.arrived()) << "reverse_legs_up_to=" << reverse_up_to;
    EXPECT_LT(min_x, -0.16) << "it drives the leg behind it to its end";
    EXPECT_NEAR(pose.x, 0.9, 0.03);
    if (reverse_up_to > 0.0) {
      EXPECT_LT(most_turned, 0.1);
    } else {
      EXPECT_GT(most_turned, 3.0) << "without reversing it turns round at both ends of the leg";
    }
  }
}

TEST(PathFollower, BacksUpToARoadPointJustBehindItRatherThanSkipIt) {
  // The same route start as above with the regulated follower's defaults: the point behind is
  // reached backwards, neither skipped nor turned round for.
  std::vector<Pose2> path{{0.0, 0.0, std::numbers::pi}, {0.05, 0.0, 0.0}};
  for (int i = 1; i <= 10; ++i) path.push_back({0.05 - 0.1 * i, 0.0, std::numbers::pi});
  PathFollower f(FollowerParams::regulated());
  f.set_path(path);
  Pose2 pose{0.0, 0.0, std::numbers::pi};
  double max_x = 0.0;
  double max_turn = 0.0;
  for (int i = 0; i < 70 * 40 && !f.arrived(); ++i) {
    const BodyTwist cmd = f.step({pose, i == 0 ? 0.0 : kDt});
    pose = integrate_twist(pose, cmd, kDt);
    max_x = std::max(max_x, pose.x);
    max_turn = std::max(max_turn, std::abs(geometry::angle_diff(pose.yaw, std::numbers::pi)));
  }
  ASSERT_TRUE(f.arrived());
  EXPECT_GT(max_x, 0.035);
  EXPECT_LT(max_turn, 0.1);
  EXPECT_NEAR(pose.x, -0.95, 0.03);
}

TEST(PathFollower, TurnsRoundForALegBehindItLongerThanItReverses) {
  std::vector<Pose2> path{{0.0, 0.0, 0.0}};
  for (int i = 1; i <= 10; ++i) path.push_back({-0.09 * i, 0.0, std::numbers::pi});
  PathFollower f(FollowerParams::regulated());
  f.set_path(path);
  Pose2 pose{0.0, 0.0, 0.0};
  bool reversed = false;
  for (int i = 0; i < 70 * 40 && !f.arrived(); ++i) {
    const BodyTwist cmd = f.step({pose, i == 0 ? 0.0 : kDt});
    reversed = reversed || cmd.vx < -1e-3;
    pose = integrate_twist(pose, cmd, kDt);
  }
  ASSERT_TRUE(f.arrived());
  EXPECT_FALSE(reversed);
  EXPECT_NEAR(pose.x, -0.9, 0.03);
}

TEST(PathFollower, BacksOnlyTheLastStretchOfALongStraightOne) {
  // A 2 m straight run to a pose facing back along it: the turn comes back_in_up_to (0.5 m)
  // short of the end, and the rest is driven backwards.
  std::vector<Pose2> path = line_path(2.0, 0.1);
  path.back().yaw = std::numbers::pi;
  PathFollower f(FollowerParams::regulated());
  f.set_path(path, true);
  Pose2 pose{0.0, 0.0, 0.0};
  double first_reversed_at = -1.0;
  double furthest = 0.0;
  for (int i = 0; i < 70 * 40 && !f.arrived(); ++i) {
    const BodyTwist cmd = f.step({pose, i == 0 ? 0.0 : kDt});
    if (cmd.vx < -1e-3 && first_reversed_at < 0.0) first_reversed_at = pose.x;
    pose = integrate_twist(pose, cmd, kDt);
    furthest = std::max(furthest, pose.x);
  }
  ASSERT_TRUE(f.arrived());
  EXPECT_NEAR(first_reversed_at, 1.5, 0.05);
  EXPECT_LT(furthest, 2.03);
  EXPECT_NEAR(pose.x, 2.0, 0.03);
  EXPECT_NEAR(std::abs(pose.yaw), std::numbers::pi, 0.03);
}

TEST(PathFollower, ALongFirstSegmentBeforeACuspIsFollowedToTheCuspAndOn) {
  // A route handed by traffic, joined from where the robot stands: one long segment to the route's
  // first point, a short move on, then back along the lane. The projection must reach past the
  // long segment's end, or the robot circles a target it stands on for ever.
  const std::vector<Pose2> path{{0.0, 0.0, 0.0},  {2.8, 0.0, 0.0},  {3.3, 0.0, 0.0},  {2.8, 0.0, 3.14},
                                {2.3, 0.0, 3.14}, {1.8, 0.0, 3.14}, {1.3, 0.0, 3.14}, {0.8, 0.0, 3.14159}};
  PathFollower f(FollowerParams::regulated());
  f.set_path(path);
  Pose2 pose{0.0, 0.0, 0.0};
  double max_x = 0.0;
  for (int i = 0; i < 70 * 60 && !f.arrived(); ++i) {
    const BodyTwist cmd = f.step({pose, i == 0 ? 0.0 : kDt});
    pose = integrate_twist(pose, cmd, kDt);
    max_x = std::max(max_x, pose.x);
  }
  ASSERT_TRUE(f.arrived());
  EXPECT_GT(max_x, 3.2) << "it drives to the cusp";
  EXPECT_NEAR(pose.x, 0.8, 0.05);
}

TEST(PathFollower, HeldShortOfABendItKeepsItsHeading) {
  // Traffic grants the path up to 4 cm short of a right-angle bend: the robot drives there and
  // stands facing along its lane, its body not turned over the crossing lane it was not granted.
  const std::vector<Pose2> path{
      {0.0, 0.0, 0.0}, {0.5, 0.0, 0.0}, {1.0, 0.0, 0.0}, {1.0, 0.5, 1.5708}, {1.0, 1.0, 1.5708}};
  const auto drive = [&](bool granted) {
    PathFollower f(FollowerParams::regulated());
    f.set_path(path);
    Pose2 pose{0.0, 0.0, 0.0};
    for (int i = 0; i < 70 * 30; ++i) {
      const double room = 0.96 - pose.x;
      if (room <= 0.0) break;  // held: the robot stands, as the task executor waits
      const BodyTwist cmd =
          f.step({pose, i == 0 ? 0.0 : kDt, room + 0.08, granted ? room : std::numeric_limits<double>::infinity()});
      pose = integrate_twist(pose, cmd, kDt);
    }
    return pose;
  };
  const Pose2 held = drive(true);
  EXPECT_GT(held.x, 0.9);
  EXPECT_LT(std::abs(held.yaw), 0.1) << "it faces along its lane";
  EXPECT_GT(drive(false).yaw, 0.3) << "steering for the path beyond the grant turns it towards the bend";
}

TEST(PathFollower, ObstacleRegulationSlowsAndStops) {
  FollowerParams p = FollowerParams::regulated();
  p.limit_acceleration = false;
  PathFollower f(p);
  f.set_path(line_path(2.0, 0.1));
  const Pose2 pose{0.0, 0.0, 0.0};
  const BodyTwist free = f.step({pose, kDt, 10.0});
  const BodyTwist near = f.step({pose, kDt, 0.5 * (p.obstacle_slow_distance + p.obstacle_stop_distance)});
  const BodyTwist stop = f.step({pose, kDt, p.obstacle_stop_distance * 0.9});
  EXPECT_NEAR(free.vx, p.v_max, 1e-6);
  EXPECT_LT(near.vx, 0.6 * p.v_max);
  EXPECT_GE(near.vx, p.regulated_min_speed);
  EXPECT_DOUBLE_EQ(stop.vx, 0.0);
}

TEST(PathFollower, AccelerationLimitBoundsCommandSteps) {
  FollowerParams p = FollowerParams::regulated();
  PathFollower f(p);
  f.set_path(line_path(1.0, 0.1));
  Pose2 pose{0.0, 0.03, 0.5};
  BodyTwist prev;
  for (int i = 0; i < 1500 && !f.arrived(); ++i) {
    const BodyTwist cmd = f.step({pose, kDt});
    if (f.arrived()) break;  // the final stop is one step, as the thesis's "stopped" is
    EXPECT_LE(std::abs(cmd.vx - prev.vx), p.max_linear_accel * kDt + 1e-9);
    EXPECT_LE(std::abs(cmd.omega - prev.omega), p.max_angular_accel * kDt + 1e-9);
    prev = cmd;
    pose = integrate_twist(pose, cmd, kDt);
  }
  EXPECT_TRUE(f.arrived());
}

TEST(PathFollower, CurvatureRegulationSlowsInTightTurns) {
  FollowerParams p;
  p.regulate_curvature = true;
  p.smooth_lookahead = true;
  PathFollower f(p);
  f.set_path(arc_path(0.15, std::numbers::pi / 2, 0.02));
  const BodyTwist cmd = f.step({{0.0, 0.0, 0.0}, kDt});
  FollowerParams q = p;
  q.regulate_curvature = false;
  PathFollower g(q);
  g.set_path(arc_path(0.15, std::numbers::pi / 2, 0.02));
  const BodyTwist plain = g.step({{0.0, 0.0, 0.0}, kDt});
  EXPECT_LT(cmd.vx, plain.vx);
}

TEST(PathFollower, IdleAndClearGiveZero) {
  PathFollower f;
  EXPECT_EQ(f.step({{0, 0, 0}, kDt}), BodyTwist{});
  f.set_path(line_path(1.0, 0.1));
  EXPECT_NE(f.step({{0, 0, 0}, kDt}), BodyTwist{});
  f.clear();
  EXPECT_EQ(f.status(), FollowerStatus::kIdle);
  EXPECT_EQ(f.step({{0, 0, 0}, kDt}), BodyTwist{});
  EXPECT_THROW(f.set_path({}), std::invalid_argument);
}

}  // namespace
}  // namespace fleet::control
