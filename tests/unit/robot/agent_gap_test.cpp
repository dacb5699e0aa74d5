// Traffic grants two robots places whose bodies stay `traffic.margin` apart. A robot's own look
// ahead must not then refuse to drive past one standing at that gap beside its lane, or the two
// wait for each other for good with the road granted to both.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <string>

#include "config/fleet_config.hpp"
#include "map/site_map.hpp"
#include "road_to_itself.hpp"
#include "robot/robot_factory.hpp"
#include "test_paths.hpp"
#include "traffic/traffic_settings.hpp"

using namespace fleet;

namespace {

struct Stretch {
  geometry::Vec2 start, end;  ///< a straight piece of the path, 8 m long
};

/// The first straight 8 m of `path` that starts at least 3 m from its first point.
std::optional<Stretch> straight_stretch(const std::vector<geometry::Vec2>& path) {
  std::vector<double> along{0.0};
  for (std::size_t i = 1; i < path.size(); ++i)
    along.push_back(along.back() + geometry::distance(path[i - 1], path[i]));
  for (std::size_t i = 0; i < path.size(); ++i) {
    if (along[i] < 3.0) continue;
    std::size_t j = i;
    while (j + 1 < path.size() && along[j] - along[i] < 8.0) ++j;
    if (along[j] - along[i] < 8.0) return std::nullopt;
    const geometry::Vec2 a = path[i], b = path[j];
    bool straight = true;
    for (std::size_t k = i; k <= j && straight; ++k) straight = geometry::point_segment_distance(path[k], a, b) < 0.005;
    if (straight) return Stretch{a, a + (8.0 / geometry::distance(a, b)) * (b - a)};
  }
  return std::nullopt;
}

/// Sends a robot of `fleet_id` (simulated with `seed`) from its first home to expedition place EX4
/// and stands a plant forklift beside the first straight stretch of its route, parallel to it,
/// `gap` metres from the robot's body as the route carries it. Whether the robot gets 3 m past the
/// standing one within a minute; `closest` is the least gap between their real bodies meanwhile.
bool drives_past_a_robot_beside_its_lane(const std::string& fleet_id, const std::string& core, double gap,
                                         std::uint64_t seed, double& closest, std::string* why) {
  const auto site =
      std::make_shared<const map::SiteMap>(map::load_site_map(fleet::test::source_path("/maps/plant.yaml")));
  config::FleetConfig config = config::load_fleet_config(fleet::test::source_path("/config/sites/plant.yaml"));
  config.settings.set("traffic.enabled", "true", "agent_gap_test");
  config.settings.set("traffic.core", core, "agent_gap_test");
  const auto& fleet =
      *std::find_if(config.fleets.begin(), config.fleets.end(), [&](const auto& f) { return f.id == fleet_id; });
  auto robot = robot::make_robot(fleet, config, site, site->site.find_home(fleet.robots.front().home)->pose, seed, 1);
  robot->set_site(site, robot::route_graph_for(config, fleet, *site));
  std::vector<robot::Neighbour> neighbours;
  std::vector<geometry::Polygon> bodies;
  const auto step = [&] {
    test::grant_everything(*robot);
    test::step_among(*robot, neighbours, bodies);
    robot->take_events();
  };
  while (robot->status().time < 1.0) step();
  task::TaskOrder order;
  order.order_id = "1";
  order.kind = orders::OrderKind::kMove;
  order.drop_area_id = "EX4";
  order.drop_area = site->site.find_area("EX4")->pose;
  if (!robot->submit(order, why)) return false;
  while (robot->status().time < 20.0 && robot->navigation().follower().path().size() < 2) step();
  const auto stretch = straight_stretch(robot->navigation().follower().path());
  if (!stretch) {
    *why = "no straight 8 m in the route";
    return false;
  }
  const geometry::Vec2 along = (1.0 / 8.0) * (stretch->end - stretch->start);
  const geometry::Vec2 left{-along.y, along.x};
  const geometry::Footprint other{1.2, 0.8};
  const geometry::Vec2 beside =
      stretch->start + 4.0 * along + (robot->status().footprint.width / 2.0 + gap + other.width / 2.0) * left;
  const geometry::Pose2 pose{beside.x, beside.y, std::atan2(along.y, along.x)};
  neighbours = {{"fk9", pose, other, 0.0, 0.1}};
  bodies = {geometry::footprint_polygon(pose, other)};
  const double start = robot->status().time;
  const auto past = [&] { return geometry::dot(robot->status().truth.position() - stretch->start, along) > 7.0; };
  while (robot->status().time < start + 60.0 && !past()) {
    step();
    closest = std::min(
        closest, geometry::convex_polygons_distance(
                     geometry::footprint_polygon(robot->status().truth, robot->status().footprint), bodies.front()));
  }
  if (!past()) *why = robot->status().task_state + " (" + robot->status().detail + ")";
  return past();
}

}  // namespace

TEST(AgentGap, EveryFleetDrivesPastARobotStandingTheTrafficMarginBesideItsLane) {
  const double margin =
      traffic::reservation_margin(config::load_fleet_config(fleet::test::source_path("/config/sites/plant.yaml")));
  for (const char* fleet : {"forklifts", "reach_trucks", "stackers", "pickers"}) {
    for (std::uint64_t seed : {1, 2, 3}) {
      std::string why;
      double closest = std::numeric_limits<double>::infinity();
      EXPECT_TRUE(drives_past_a_robot_beside_its_lane(fleet, "manager", margin, seed, closest, &why))
          << fleet << " (seed " << seed << ") stopped: " << why;
      EXPECT_GT(closest, 0.0) << fleet << " (seed " << seed << ") touched the robot it passed";
    }
  }
}

TEST(AgentGap, UnderTheCoordinationCoreEveryFleetDrivesPastARobotStandingItsMarginBesideItsLane) {
  config::FleetConfig config = config::load_fleet_config(fleet::test::source_path("/config/sites/plant.yaml"));
  config.settings.set("traffic.core", "places", "agent_gap_test");
  const double margin = traffic::reservation_margin(config);
  EXPECT_EQ(margin, config.settings.get_double("traffic.places_margin"));
  for (const char* fleet : {"forklifts", "reach_trucks", "stackers", "pickers"}) {
    for (std::uint64_t seed : {1, 2}) {
      std::string why;
      double closest = std::numeric_limits<double>::infinity();
      EXPECT_TRUE(drives_past_a_robot_beside_its_lane(fleet, "places", margin, seed, closest, &why))
          << fleet << " (seed " << seed << ") stopped: " << why;
      EXPECT_GT(closest, 0.0) << fleet << " (seed " << seed << ") touched the robot it passed";
    }
  }
}
