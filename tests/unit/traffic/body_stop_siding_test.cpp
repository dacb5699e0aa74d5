// Two robots meet head-on in a lane driven both ways; their agents' safety checks stop each for
// the other's body before either reaches the end of its grant. The lane has a spur on either side
// of them: one between them, one behind the robot going south. A siding through the spur between
// them leads towards the body that stops the robot sent there, which its safety check does not let
// it drive: the manager must send it the other way.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <map>
#include <vector>

#include "test_grants.hpp"
#include "test_graphs.hpp"
#include "traffic/traffic_manager.hpp"

namespace fleet::traffic {
namespace {

using testing::grant_of;
using testing::has_event;
using testing::point_at;

struct Point {
  double x = 0.0, y = 0.0;
};

// An agent reduced to what the manager sees of it: it drives its route up to its grant, and a
// stand-in for its safety check, longer ahead than the places' 0.25 x 0.16 m bodies (as a turning
// body reaches past its places), stops it where a step would bring another robot's centre within
// kBodyGap ahead and kBodyWidth beside it, and nearer than it is; such a stop is reported after
// 3 s, as agents do.
struct EmulatedRobot {
  static constexpr double kBodyGap = 2.0;      // metres between centres, ahead
  static constexpr double kBodyWidth = 0.3;    // metres between centres, beside
  static constexpr double kReportAfter = 3.0;  // sim seconds

  int id = 0;
  std::vector<int> route;
  std::uint64_t version = 1;
  double driven = 0.0;
  double stopped_since = -1.0;
  int stopped_for = -1;

  Point at(const map::RoadGraph& g, double distance) const {
    double left = distance;
    for (std::size_t k = 1; k < route.size(); ++k) {
      const auto& a = g.points[static_cast<std::size_t>(route[k - 1])];
      const auto& b = g.points[static_cast<std::size_t>(route[k])];
      const double length = std::hypot(b.x - a.x, b.y - a.y);
      if (left <= length) return {a.x + (b.x - a.x) * left / length, a.y + (b.y - a.y) * left / length};
      left -= length;
    }
    const auto& last = g.points[static_cast<std::size_t>(route.back())];
    return {last.x, last.y};
  }
};

double gap(Point a, Point b) {
  return std::hypot(a.x - b.x, a.y - b.y);
}

/// Whether a robot stepping from `from` to `to` stops for a body centred at `body`.
bool stops_for(Point from, Point to, Point body) {
  const double dx = to.x - from.x, dy = to.y - from.y;
  const double step = std::hypot(dx, dy);
  if (step < 1e-9 || gap(to, body) >= gap(from, body)) return false;
  const double ahead = ((body.x - to.x) * dx + (body.y - to.y) * dy) / step;
  const double beside = std::abs((body.y - to.y) * dx - (body.x - to.x) * dy) / step;
  return ahead > -EmulatedRobot::kBodyGap && ahead < EmulatedRobot::kBodyGap && beside < EmulatedRobot::kBodyWidth;
}

// The lane with its two spurs, robot 1 going south from y = 6 and robot 2 north from y = 2.
struct HeadOn {
  testing::GraphBuilder b;
  std::map<int, EmulatedRobot> robots;
  HeadOn() {
    b.road(0.0, 0.0, 0.0, 12.0);
    b.road(0.0, 4.5, 3.0, 4.5);     // the spur between them
    b.road(0.0, 9.0, -3.0, 9.0);    // the spur behind the southbound robot
    b.road(0.0, 10.5, -3.0, 10.5);  // a second spur behind it
    b.road(10.0, 0.0, 10.0, 12.0);  // a lane apart, where a docked robot's body stands
    const auto& g = b.graph();
    robots[1].id = 1;
    for (int k = 60; k >= 0; --k) robots[1].route.push_back(point_at(g, 0.0, 0.1 * k));
    robots[2].id = 2;
    for (int k = 20; k <= 120; ++k) robots[2].route.push_back(point_at(g, 0.0, 0.1 * k));
  }

  /// Drives both robots until both arrive (or 300 s); `siding` sees every siding sent. The number
  /// of sidings sent, and whether both arrived.
  std::pair<int, bool> drive(TrafficManager& m, const std::function<void(int id, const Grant&)>& siding) {
    const auto& g = b.graph();
    for (auto& [id, robot] : robots) EXPECT_EQ(m.submit_route({id, 1, robot.route}, 0.0), SubmitStatus::kAccepted);
    double t = 0.0;
    int sidings = 0;
    bool both_arrived = false;
    constexpr double kStep = 0.05, kSpeed = 0.4;
    for (int i = 0; i < 20 * 300 && !both_arrived; ++i, t += kStep) {
      const UpdateResult r = m.update(t);
      EXPECT_EQ(m.check_invariant(), "");
      both_arrived = true;
      for (auto& [id, robot] : robots) {
        sidings += has_event(r, TrafficEvent::Kind::kSidingSent, id) ? 1 : 0;
        const Grant* grant = grant_of(r, id);
        if (grant == nullptr) return {sidings, false};
        if (grant->instruction == Instruction::kSiding && grant->version != robot.version) siding(id, *grant);
        if (grant->instruction != Instruction::kNone && grant->version != robot.version) {
          robot.version = grant->version;
          robot.route = grant->route;
          robot.driven = 0.0;
          robot.stopped_since = -1.0;
        }
        both_arrived = both_arrived && grant->status == GrantStatus::kArrived;
        const EmulatedRobot& other = robots[3 - id];
        const Point here = robot.at(g, robot.driven);
        const Point there = other.at(g, other.driven);
        const double next = std::min(robot.driven + kSpeed * kStep, grant->granted_distance);
        const Point ahead = robot.at(g, next);
        if (stops_for(here, ahead, there)) {
          if (robot.stopped_since < 0.0) robot.stopped_since = t;
        } else {
          robot.driven = std::max(robot.driven, next);
          robot.stopped_since = -1.0;
        }
        const bool report = robot.stopped_since >= 0.0 && t - robot.stopped_since >= EmulatedRobot::kReportAfter;
        m.report_progress({id, robot.version, robot.driven, report ? std::vector<int>{3 - id} : std::vector<int>{}}, t);
      }
    }
    return {sidings, both_arrived};
  }
};

TrafficConfiguration both_ways() {
  TrafficConfiguration c;
  c.one_way = false;
  return c;
}

TEST(BodyStopSiding, ARobotStoppedForABodyIsSentToASidingAwayFromItNotPastIt) {
  HeadOn lane;
  const auto& g = lane.b.graph();
  TrafficManager m(g, both_ways());
  const auto [sidings, both_arrived] = lane.drive(m, [&](int id, const Grant& grant) {
    // The way to the siding never leads nearer the other robot than this one stands.
    const EmulatedRobot& robot = lane.robots[id];
    const EmulatedRobot& other = lane.robots[3 - id];
    const Point there = other.at(g, other.driven);
    const double now_apart = gap(robot.at(g, robot.driven), there);
    for (int p : grant.route) {
      const Point q{g.points[static_cast<std::size_t>(p)].x, g.points[static_cast<std::size_t>(p)].y};
      EXPECT_GE(gap(q, there), now_apart - 0.15)
          << "robot " << id << " sent past robot " << 3 - id << " through (" << q.x << ", " << q.y << ")";
    }
  });
  EXPECT_TRUE(both_arrived) << "with " << sidings << " sidings sent";
  EXPECT_LE(sidings, 3);
}

// A robot docked beside the first spur behind the southbound robot will turn out across it: the
// siding is the second spur.
TEST(BodyStopSiding, NoSidingEndsInTheWayOutOfADockedRobot) {
  HeadOn lane;
  const auto& g = lane.b.graph();
  TrafficManager m(g, both_ways());
  ASSERT_TRUE(m.hold_body(3, {{9.8, 5.8}, {10.2, 5.8}, {10.2, 6.2}, {9.8, 6.2}}, 0.0));
  m.keep_clear(3, {{-3.5, 8.5}, {-0.3, 8.5}, {-0.3, 9.5}, {-3.5, 9.5}});
  int sent = 0;
  const auto [sidings, both_arrived] = lane.drive(m, [&](int id, const Grant& grant) {
    ++sent;
    const auto& end = g.points[static_cast<std::size_t>(grant.route.back())];
    EXPECT_FALSE(end.x < -0.3 && end.y > 8.5 && end.y < 9.5)
        << "robot " << id << " sent to stand in the way out, at (" << end.x << ", " << end.y << ")";
  });
  EXPECT_GT(sent, 0) << "no siding sent";
  EXPECT_TRUE(both_arrived) << "with " << sidings << " sidings sent";
}

// A robot comes to stand at the end of the first siding sent (a stacker docking there): the robot
// sent to it, stopped short of it, is sent to another siding rather than waiting for good.
TEST(BodyStopSiding, ARobotHeldUpOnItsWayToASidingIsSentToAnother) {
  HeadOn lane;
  const auto& g = lane.b.graph();
  TrafficConfiguration configuration = both_ways();
  configuration.reroute_wait = 10.0;
  TrafficManager m(g, configuration);
  int sent_to = -1;
  int second = 0;
  Point first_end{};
  const auto [sidings, both_arrived] = lane.drive(m, [&](int id, const Grant& grant) {
    const auto& end = g.points[static_cast<std::size_t>(grant.route.back())];
    if (sent_to < 0) {
      sent_to = id;
      first_end = {end.x, end.y};
      EXPECT_TRUE(m.hold_body(3,
                              {{end.x - 0.05, end.y - 0.05},
                               {end.x + 0.05, end.y - 0.05},
                               {end.x + 0.05, end.y + 0.05},
                               {end.x - 0.05, end.y + 0.05}},
                              0.0));
      return;
    }
    if (id != sent_to) return;
    ++second;
    EXPECT_GT(std::hypot(end.x - first_end.x, end.y - first_end.y), 0.3)
        << "robot " << id << " sent again to where robot 3 stands";
  });
  ASSERT_GE(sent_to, 0) << "no siding sent";
  EXPECT_GT(second, 0) << "robot " << sent_to << " was not sent to another siding";
  EXPECT_TRUE(both_arrived) << "with " << sidings << " sidings sent";
}

}  // namespace
}  // namespace fleet::traffic
