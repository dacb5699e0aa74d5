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

namespace {

/// How far along its road fl1 is granted while fl2 works in an area across that road 0.6 m ahead
/// of fl1's start, standing 1 m ahead: fl2 either renews its request as an agent does or, once
/// the area is clear, falls silent (lost in the middle of its manoeuvre).
struct AreaRun {
  std::vector<double> along;  ///< metres along fl1's route at each of its points
  std::size_t area_from = 0;  ///< the first point of fl1's route in fl2's area
  int furthest = -1;          ///< the furthest point fl1 was granted to
  std::string server_log;
};

AreaRun run_beside_a_work_area(int domain, bool worker_goes_silent) {
  AreaRun run;
  TableARoutes routes;
  const map::RoadGraph& graph = routes.graph();
  // fl1's way from home H1 to A4, and fl2 standing on it 1 m along, working beside it: the area
  // it sweeps reaches back along the road towards fl1 (a stacker's docking run from the lane).
  const std::vector<int> route = routes.shortest(routes.point_near(0.83, 0.82), routes.point_near(2.55, 2.025));
  EXPECT_GE(route.size(), 20u);
  if (route.size() < 20u) return run;
  std::vector<double>& along = run.along;
  along.push_back(0.0);
  for (std::size_t i = 1; i < route.size(); ++i) {
    const auto& a = graph.points[static_cast<std::size_t>(route[i - 1])];
    const auto& b = graph.points[static_cast<std::size_t>(route[i])];
    along.push_back(along.back() + std::hypot(b.x - a.x, b.y - a.y));
  }
  const auto index_at = [&](double metres) {
    return static_cast<std::size_t>(std::lower_bound(along.begin(), along.end(), metres) - along.begin());
  };
  const std::size_t stands = index_at(1.0), area_from = index_at(0.6);
  run.area_from = area_from;
  EXPECT_LT(stands, route.size());
  if (stands >= route.size()) return run;
  const auto& at = graph.points[static_cast<std::size_t>(route[stands])];
  const auto& from = graph.points[static_cast<std::size_t>(route[area_from])];

  ScriptedFleet s(domain);
  s.fleet.start_server();
  ScriptedRobot fl2(s.client, "fl2", {at.x, at.y, 0.0});
  const bool ready = s.client.find_server(5s) && s.robot.registers_with(s.fleet) && fl2.registers_with(s.fleet);
  EXPECT_TRUE(ready) << s.server_log();
  if (!ready) return run;
  dds::Writer<model::TrafficRequest> requests(s.client.participant(), dds::qos::live_state());
  dds::Reader<model::TrafficGrant> grants(s.client.participant(), dds::qos::live_state(),
                                          model::every_robot_partition());
  const geometry::Polygon area{{from.x - 0.05, from.y - 0.05},
                               {from.x + 0.05, from.y - 0.05},
                               {from.x + 0.05, from.y + 0.05},
                               {from.x - 0.05, from.y + 0.05}};
  constexpr std::uint64_t kRoute = 16, kWork = 8;
  bool area_clear = false;
  EXPECT_TRUE(eventually(
      [&] {
        s.robot.publish_state();
        fl2.publish_state();
        requests.write({"fl2", kWork, {}, 0.0, {}, 0.0, area, {}, {}, "table_a"});
        grants.take_data([&](model::TrafficGrant&& g) {
          area_clear = area_clear || (g.robot_id == "fl2" && g.status == "AREA_CLEAR");
        });
        return area_clear;
      },
      10s))
      << s.server_log();
  if (!area_clear) return run;
  // fl1 drives up to the end of every grant for 4 s (40 s sim), fl2 renewing its request as an
  // agent does (every 0.5 s wall here, slower than the server's cycle), or silent.
  int& furthest = run.furthest;
  double progress = 0.0;
  const auto until = std::chrono::steady_clock::now() + 4s;
  auto next_work = std::chrono::steady_clock::now();
  while (std::chrono::steady_clock::now() < until) {
    s.robot.publish_state();
    if (!worker_goes_silent) fl2.publish_state();
    if (!worker_goes_silent && std::chrono::steady_clock::now() >= next_work) {
      requests.write({"fl2", kWork, {}, 0.0, {}, 0.0, area, {}, {}, "table_a"});
      next_work += 500ms;
    }
    requests.write({"fl1", kRoute, route, progress, {}, 0.0, {}, {}, {}, "table_a"});
    grants.take_data([&](model::TrafficGrant&& g) {
      if (g.robot_id != "fl1" || g.version != kRoute || g.granted_index < 0) return;
      furthest = std::max(furthest, g.granted_index);
      progress = std::max(progress, g.granted_distance);
    });
    std::this_thread::sleep_for(20ms);
  }
  run.server_log = s.server_log();
  return run;
}

void expect_kept_out(const AreaRun& run) {
  ASSERT_GE(run.furthest, 0) << "fl1 was never let onto the road\n" << run.server_log;
  EXPECT_LT(static_cast<std::size_t>(run.furthest), run.area_from)
      << "fl1 granted to " << run.along[static_cast<std::size_t>(run.furthest)] << " m, into fl2's area from "
      << run.along[run.area_from] << " m\n"
      << run.server_log;
}

}  // namespace

TEST(WorkArea, ARobotComingAlongTheRoadIsNeverGrantedIntoAHeldArea) {
  expect_kept_out(run_beside_a_work_area(87, false));
}

TEST(WorkArea, ARobotLostInTheMiddleOfItsManoeuvreKeepsItsWholeArea) {
  // Heard from again, it goes on with its manoeuvre: nobody may have been let in meanwhile.
  expect_kept_out(run_beside_a_work_area(88, true));
}
