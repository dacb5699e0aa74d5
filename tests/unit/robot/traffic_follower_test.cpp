// The traffic-following piece every robot type drives by, tested on a straight road without a
// robot: where the grant ends, what a manager's re-route replaces, when a siding is left.
#include "robot/traffic_follower.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace fleet::robot {
namespace {

using geometry::Vec2;

/// `count` points along y = 0, `spacing` apart from x = `first_x` (no edges: routes name points).
map::RoadGraph points_along_x(int count, double first_x, double spacing) {
  map::RoadGraph g;
  for (int i = 0; i < count; ++i) {
    map::GraphPoint p;
    p.id = i;
    p.x = first_x + spacing * i;
    g.points.push_back(p);
  }
  g.successors.resize(static_cast<std::size_t>(count));
  return g;
}

/// Road points 0..5 along y = 0 at x = 1..6 (1 m apart).
map::RoadGraph straight_road() {
  return points_along_x(6, 1.0, 1.0);
}

/// An own plan from (0, 0) onto the road at point 0, along it to point `last`, then 0.5 m off it
/// to the goal at (1 + last, 0.5).
planning::Route own_plan(const map::RoadGraph& g, int last) {
  planning::Route r;
  r.status = planning::PlanStatus::kFound;
  r.points.push_back({0.0, 0.0});
  for (int i = 0; i <= last; ++i) {
    r.road.point_ids.push_back(i);
    r.road.points.push_back({g.points[static_cast<std::size_t>(i)].x, 0.0});
    r.points.push_back(r.road.points.back());
  }
  r.points.push_back({1.0 + last, 0.5});
  return r;
}

/// Room as the robot drives along y = 0 from x = `from` to `to` in 1 cm steps (the follower finds
/// the robot near where it last was, as a robot moving at its control rate is).
double room_after_driving(TrafficFollower& f, double from, double to) {
  double room = 0.0;
  for (double x = from; x <= to + 1e-9; x += 0.01) room = f.room({x, 0.0});
  return room;
}

TEST(TrafficFollower, AGrantShorterThanThePathStopsTheRobotAtTheGrant) {
  const map::RoadGraph g = straight_road();
  TrafficFollower f({.traffic = true, .siding_timeout = 30.0}, 100);
  f.adopt_plan(own_plan(g, 4));
  const TrafficRoute route = f.route();
  EXPECT_EQ(route.version, 102u) << "an own route takes the next even version";
  EXPECT_EQ(route.points, (std::vector<int>{0, 1, 2, 3, 4}));
  // Not granted yet: it may not move at all.
  EXPECT_LT(f.room({0.0, 0.0}), 0.0);
  // Granted up to point 1 (1 m of road): the room ends at x = 2, one metre onto the road.
  EXPECT_FALSE(f.grant({route.version, 1, 1.0, {"fl2"}, {}, false}));
  EXPECT_NEAR(f.room({0.0, 0.0}), 2.0, 1e-9);
  EXPECT_NEAR(room_after_driving(f, 0.0, 1.5), 0.5, 1e-6);
  EXPECT_NEAR(room_after_driving(f, 1.5, 2.0), 0.0, 1e-6);
  EXPECT_NEAR(f.route().progress, 1.0, 1e-6);
  EXPECT_EQ(f.blocked_by(), std::vector<std::string>{"fl2"});
  // A grant of another route holds it again; the whole route granted frees it.
  f.grant({route.version - 2, 4, 4.0, {}, {}, false});
  EXPECT_LT(f.room({2.0, 0.0}), 0.0);
  f.grant({route.version, 4, 4.0, {}, {}, false});
  EXPECT_TRUE(std::isinf(f.room({2.0, 0.0})));
}

TEST(TrafficFollower, AGrantWithdrawnMidRouteHoldsTheRobotWhereItIsUntilTheNextGrant) {
  // What an agent does after its process stood still: it drops the grant it had (the road ahead
  // may have gone to another robot meanwhile) and waits for a fresh one.
  const map::RoadGraph g = straight_road();
  TrafficFollower f({.traffic = true, .siding_timeout = 30.0}, 100);
  f.adopt_plan(own_plan(g, 4));
  const std::uint64_t version = f.route().version;
  f.grant({version, 4, 4.0, {}, {}, false});
  EXPECT_TRUE(std::isinf(room_after_driving(f, 0.0, 2.5)));
  TrafficPermit none;
  none.version = version;
  none.granted_index = -1;
  EXPECT_FALSE(f.grant(none));
  EXPECT_LT(f.room({2.5, 0.0}), 0.0) << "no room at all, not even to turn";
  f.grant({version, 3, 3.0, {}, {}, false});
  EXPECT_NEAR(f.room({2.5, 0.0}), 1.5, 1e-6);
}

TEST(TrafficFollower, ARobotThatWaitsOffTheRoadForRoomStandsUntilGrantedPastTheEntry) {
  const map::RoadGraph g = straight_road();
  for (bool waits : {false, true}) {
    TrafficFollower f({.traffic = true, .siding_timeout = 30.0, .wait_off_road_for_room = waits}, 100);
    f.adopt_plan(own_plan(g, 4));
    const TrafficRoute route = f.route();
    // Granted the entry point only: a robot that waits stays where it is, one that does not
    // drives the metre onto the road.
    f.grant({route.version, 0, 0.0, {"fl2"}, {}, false});
    if (waits) {
      EXPECT_LE(f.room({0.0, 0.0}), 0.0);
    } else {
      EXPECT_NEAR(f.room({0.0, 0.0}), 1.0, 1e-9);
    }
    // On the road at the entry, or granted further, both drive as granted.
    f.grant({route.version, 2, 2.0, {}, {}, false});
    EXPECT_NEAR(f.room({0.0, 0.0}), 3.0, 1e-9) << (waits ? "waits" : "drives");
  }
}

TEST(TrafficFollower, WithTrafficOffGrantsAreIgnoredAndTheRoomIsUnlimited) {
  const map::RoadGraph g = straight_road();
  TrafficFollower f({.traffic = false, .siding_timeout = 30.0}, 100);
  f.adopt_plan(own_plan(g, 4));
  EXPECT_FALSE(f.grant({103, 1, 1.0, {}, {2, 3}, false}));
  EXPECT_FALSE(f.take_route());
  EXPECT_TRUE(std::isinf(f.room({0.0, 0.0})));
}

TEST(TrafficFollower, AManagerReRouteReplacesThePathAndTheVersion) {
  const map::RoadGraph g = straight_road();
  TrafficFollower f({.traffic = true, .siding_timeout = 30.0}, 100);
  f.adopt_plan(own_plan(g, 4));
  f.grant({102, 1, 1.0, {}, {}, false});
  room_after_driving(f, 0.0, 1.4);
  // The manager hands over a route back to the own plan's last road point, from point 0 behind
  // the robot: it waits for the next plan, and an older or second one is not taken meanwhile.
  EXPECT_TRUE(f.grant({103, 4, 4.0, {}, {0, 1, 2, 3, 4}, false}));
  EXPECT_FALSE(f.grant({105, 4, 4.0, {}, {0, 1, 2, 3, 4}, false})) << "one re-route pending at a time";
  EXPECT_EQ(f.route().version, 102u) << "still driving its own route until it plans";
  const auto permit = f.take_route();
  ASSERT_TRUE(permit);
  EXPECT_FALSE(f.take_route()) << "taken once";
  f.adopt_route(*permit, g, {1.4, 0.0});
  EXPECT_EQ(f.route().version, 103u);
  EXPECT_EQ(f.route().points, (std::vector<int>{0, 1, 2, 3, 4}));
  // The path starts where the robot stands and joins the route ahead (point 1 at x = 2), not at
  // point 0 behind it; the leg off the road to the goal is kept.
  const std::vector<Vec2> expected{{1.4, 0.0}, {2.0, 0.0}, {3.0, 0.0}, {4.0, 0.0}, {5.0, 0.0}, {5.0, 0.5}};
  ASSERT_EQ(f.path().size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_LT(geometry::distance(f.path()[i], expected[i]), 1e-9) << i;
  // Progress counts from the route's first point (x = 1) as before.
  f.grant({103, 4, 4.0, {}, {}, false});
  EXPECT_TRUE(std::isinf(f.room({1.5, 0.0})));
  EXPECT_NEAR(f.route().progress, 0.5, 1e-6);
  // A re-route no newer than the route driven is stale.
  EXPECT_FALSE(f.grant({103, 2, 2.0, {}, {1, 2}, false}));
}

TEST(TrafficFollower, ARouteThatBacksUpAPlaceCountsProgressAlongTheLegBehindFirst) {
  // Places 0.1 m apart, as on a table: the coordination core pushes a robot standing at point 2
  // back to point 1 and then sends it on over point 2 again. Standing where it stands, the robot
  // is on the route's first leg, not on the stretch after the cusp that passes under it too.
  const map::RoadGraph g = points_along_x(6, 0.0, 0.1);
  TrafficFollower f({.traffic = true, .siding_timeout = 30.0}, 100);
  ASSERT_TRUE(f.grant({101, 1, 0.1, {}, {2, 1, 2, 3, 4}, false}));
  const auto permit = f.take_route();
  ASSERT_TRUE(permit);
  f.adopt_route(*permit, g, {0.205, 0.0});
  f.grant({101, 1, 0.1, {}, {}, false});
  EXPECT_NEAR(f.room({0.205, 0.0}), 0.105, 1e-6) << "the point behind it is still ahead on the route";
  EXPECT_NEAR(f.route().progress, 0.0, 1e-6);
  double x = 0.205;
  for (; x >= 0.1; x -= 0.005) f.room({x, 0.0});
  EXPECT_NEAR(f.route().progress, 0.1, 0.006) << "backed up to point 1";
  f.grant({101, 4, 0.4, {}, {}, false});
  for (; x <= 0.3; x += 0.005) f.room({x, 0.0});
  EXPECT_NEAR(f.route().progress, 0.3, 0.006) << "on past point 2 to point 3 after the cusp";
}

TEST(TrafficFollower, NotCalledBackFromASidingItLeavesItAfterTheTimeout) {
  const map::RoadGraph g = straight_road();
  TrafficFollower f({.traffic = true, .siding_timeout = 30.0}, 100);
  f.adopt_plan(own_plan(g, 4));
  ASSERT_TRUE(f.grant({103, 2, 2.0, {}, {0, 1, 2}, true}));
  f.adopt_route(*f.take_route(), g, {0.0, 0.0});
  EXPECT_TRUE(f.in_siding());
  f.grant({103, 2, 2.0, {}, {}, false});
  // Granted the whole siding, it still stops 3 cm short of its end (x = 3).
  EXPECT_NEAR(room_after_driving(f, 0.0, 2.9), 0.07, 1e-6);
  EXPECT_FALSE(f.siding_timed_out(10.0, true));
  EXPECT_FALSE(f.siding_timed_out(25.0, false)) << "counted from the first hold, through a flicker";
  EXPECT_FALSE(f.siding_timed_out(40.0, true));
  EXPECT_TRUE(f.siding_timed_out(40.5, true));
  EXPECT_FALSE(f.in_siding());
  EXPECT_FALSE(f.siding_timed_out(80.0, true)) << "left once";
}

TEST(TrafficFollower, ArrivedBesideTheRoadItHoldsNoRoad) {
  const map::RoadGraph g = straight_road();
  TrafficFollower f({.traffic = true, .siding_timeout = 30.0}, 100);
  f.adopt_plan(own_plan(g, 4));
  EXPECT_TRUE(f.on_road());
  f.leave_road();
  EXPECT_FALSE(f.on_road());
  EXPECT_TRUE(f.path().empty());
  EXPECT_TRUE(f.route().points.empty());
  EXPECT_EQ(f.route().version, 102u);
  EXPECT_TRUE(std::isinf(f.room({5.0, 0.5})));
}

TEST(TrafficFollower, ARobotThatSkipsTheLegBackOfItsRouteIsFoundAgainAndHeldAtItsGrant) {
  // A route back one place and on again, the robot at the place it backs up from; its controller
  // skips the short leg back and drives on, and nobody says so. Its progress must follow it, or
  // the room left in its grant would never shrink.
  const map::RoadGraph g = points_along_x(10, 0.0, 0.1);
  TrafficFollower f({.traffic = true, .siding_timeout = 30.0}, 100);
  ASSERT_TRUE(f.grant({101, 4, 0.4, {}, {2, 1, 2, 3, 4, 5, 6, 7, 8, 9}, false}));
  const auto permit = f.take_route();
  ASSERT_TRUE(permit);
  f.adopt_route(*permit, g, {0.2, 0.0});
  f.grant({101, 4, 0.4, {}, {}, false});
  double x = 0.2;
  for (; x < 0.8 && f.room({x, 0.0}) > 0.0; x += 0.005) {
  }
  EXPECT_LT(x, 0.4 + 0.16) << "held within the search's reach past the grant's end (x = 0.4)";
}

}  // namespace
}  // namespace fleet::robot
