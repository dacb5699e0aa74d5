// The area a robot works in beside the roads (a stacker docking) is held for it over the wire
// for as long as it works there: a robot coming along the road is never granted into it.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>

#include "dds/qos.hpp"
#include "scripted_fleet.hpp"

using namespace fleet;
using namespace fleet::testing;
using namespace std::chrono_literals;

TEST(WorkArea, ARobotComingAlongTheRoadIsNeverGrantedIntoAHeldArea) {
  TableARoutes routes;
  const map::RoadGraph& graph = routes.graph();
  // fl1's way from home H1 to A4, and fl2 standing on it 1 m along, working beside it: the area
  // it sweeps reaches back along the road towards fl1 (a stacker's docking run from the lane).
  const std::vector<int> route = routes.shortest(routes.point_near(0.83, 0.82), routes.point_near(2.55, 2.025));
  ASSERT_GE(route.size(), 20u);
  std::vector<double> along{0.0};
  for (std::size_t i = 1; i < route.size(); ++i) {
    const auto& a = graph.points[static_cast<std::size_t>(route[i - 1])];
    const auto& b = graph.points[static_cast<std::size_t>(route[i])];
    along.push_back(along.back() + std::hypot(b.x - a.x, b.y - a.y));
  }
  const auto index_at = [&](double metres) {
    return static_cast<std::size_t>(std::lower_bound(along.begin(), along.end(), metres) - along.begin());
  };
  const std::size_t stands = index_at(1.0), area_from = index_at(0.6);
  ASSERT_LT(stands, route.size());
  const auto& at = graph.points[static_cast<std::size_t>(route[stands])];
  const auto& from = graph.points[static_cast<std::size_t>(route[area_from])];

  ScriptedFleet s(87);
  s.fleet.start_server();
  ASSERT_TRUE(s.client.find_server(5s));
  ScriptedRobot fl2(s.client, "fl2", {at.x, at.y, 0.0});
  ASSERT_TRUE(s.robot.registers_with(s.fleet)) << s.server_log();
  ASSERT_TRUE(fl2.registers_with(s.fleet)) << s.server_log();
  dds::Writer<model::TrafficRequest> requests(s.client.participant(), dds::qos::live_state());
  dds::Reader<model::TrafficGrant> grants(s.client.participant(), dds::qos::live_state());
  const geometry::Polygon area{{from.x - 0.05, from.y - 0.05},
                               {from.x + 0.05, from.y - 0.05},
                               {from.x + 0.05, from.y + 0.05},
                               {from.x - 0.05, from.y + 0.05}};
  constexpr std::uint64_t kRoute = 16, kWork = 8;
  bool area_clear = false;
  ASSERT_TRUE(eventually(
      [&] {
        s.robot.publish_state();
        fl2.publish_state();
        requests.write({"fl2", kWork, {}, 0.0, {}, 0.0, area, {}});
        grants.take_data([&](model::TrafficGrant&& g) {
          area_clear = area_clear || (g.robot_id == "fl2" && g.status == "AREA_CLEAR");
        });
        return area_clear;
      },
      10s))
      << s.server_log();
  // fl1 drives up to the end of every grant for 4 s (40 s sim), fl2 renewing its request as an
  // agent does (every 0.5 s wall here, slower than the server's cycle).
  int furthest = -1;
  double progress = 0.0;
  const auto until = std::chrono::steady_clock::now() + 4s;
  auto next_work = std::chrono::steady_clock::now();
  while (std::chrono::steady_clock::now() < until) {
    s.robot.publish_state();
    fl2.publish_state();
    if (std::chrono::steady_clock::now() >= next_work) {
      requests.write({"fl2", kWork, {}, 0.0, {}, 0.0, area, {}});
      next_work += 500ms;
    }
    requests.write({"fl1", kRoute, route, progress, {}, 0.0, {}, {}});
    grants.take_data([&](model::TrafficGrant&& g) {
      if (g.robot_id != "fl1" || g.version != kRoute || g.granted_index < 0) return;
      furthest = std::max(furthest, g.granted_index);
      progress = std::max(progress, g.granted_distance);
    });
    std::this_thread::sleep_for(20ms);
  }
  ASSERT_GE(furthest, 0) << "fl1 was never let onto the road\n" << s.server_log();
  EXPECT_LT(static_cast<std::size_t>(furthest), area_from)
      << "fl1 granted to " << along[static_cast<std::size_t>(furthest)] << " m, into fl2's area from "
      << along[area_from] << " m";
}
