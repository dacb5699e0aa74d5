// Road graph construction on small fixtures whose answer is known [Forklift thesis, section 5.1].

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "map/opendrive.hpp"
#include "map/road_graph_builder.hpp"
#include "map/site.hpp"

using namespace fleet::map;

namespace {

/// A straight two-lane road (lane 1 left, lane -1 right, 3 m each) along +x or -x.
std::string two_lane_road(const std::string& id, double x, const std::string& hdg, const std::string& link) {
  return "<road id=\"" + id + "\" length=\"10\" junction=\"-1\"><link>" + link +
         "</link><planView><geometry s=\"0\" x=\"" + std::to_string(x) + "\" y=\"0\" hdg=\"" + hdg +
         "\" length=\"10\"><line/></geometry></planView><lanes><laneSection s=\"0\">"
         "<left><lane id=\"1\" type=\"driving\"><width sOffset=\"0\" a=\"3\" b=\"0\" c=\"0\" d=\"0\"/></lane></left>"
         "<center><lane id=\"0\" type=\"none\"/></center>"
         "<right><lane id=\"-1\" type=\"driving\"><width sOffset=\"0\" a=\"3\" b=\"0\" c=\"0\" d=\"0\"/></lane></right>"
         "</laneSection></lanes></road>";
}

bool edge_between(const RoadGraph& g, const std::string& road_a, int lane_a, const std::string& road_b, int lane_b) {
  for (std::size_t i = 0; i < g.points.size(); ++i) {
    for (const int j : g.successors[i]) {
      const auto& a = g.points[i];
      const auto& b = g.points[static_cast<std::size_t>(j)];
      if (a.road_id == road_a && a.lane_id == lane_a && b.road_id == road_b && b.lane_id == lane_b) return true;
    }
  }
  return false;
}

}  // namespace

TEST(RoadGraph, HeadToHeadRoadsSwapLaneSides) {
  // Road A runs +x from 0 to 10; road B runs -x from 20 to 10, so their ends meet (contactPoint
  // end). A's right lane (driving +x) continues into B's left lane (driving against B's s, +x).
  const std::string xml =
      "<OpenDRIVE><header/>" +
      two_lane_road("A", 0.0, "0", R"(<successor elementType="road" elementId="B" contactPoint="end"/>)") +
      two_lane_road("B", 20.0, "3.141592653589793",
                    R"(<successor elementType="road" elementId="A" contactPoint="end"/>)") +
      "</OpenDRIVE>";
  const RoadNetwork net = parse_opendrive(xml, "head_to_head.xodr");
  const RoadGraph g = build_road_graph(net, {.spacing = 1.0, .single_lane_roads_both_ways = true});
  EXPECT_TRUE(edge_between(g, "A", -1, "B", 1));
  EXPECT_TRUE(edge_between(g, "B", -1, "A", 1));
  EXPECT_FALSE(edge_between(g, "A", -1, "B", -1));  // would jump across the road
  EXPECT_FALSE(edge_between(g, "B", 1, "A", -1));   // against the traffic
  // Where the lanes meet their points coincide: A's lane -1 at y = -1.5 going +x is B's lane 1.
  for (const auto& p : g.points) {
    if (p.road_id == "B" && p.lane_id == 1) {
      EXPECT_NEAR(p.y, -1.5, 1e-9);
    }
  }
  std::vector<int> weak;
  EXPECT_EQ(weak_components(g, weak), 2u);  // one path per direction of travel
}

TEST(RoadGraph, SingleLaneRoadIsDrivenBothWaysOnlyWhenAsked) {
  const std::string xml =
      "<OpenDRIVE><header/><road id=\"1\" length=\"1\" junction=\"-1\"><planView><geometry s=\"0\" x=\"0\" y=\"0\" "
      "hdg=\"0\" length=\"1\"><line/></geometry></planView><lanes><laneOffset s=\"0\" a=\"0.15\" b=\"0\" c=\"0\" "
      "d=\"0\"/>"
      "<laneSection s=\"0\"><center><lane id=\"0\" type=\"none\"/></center><right><lane id=\"-1\" type=\"driving\">"
      "<width sOffset=\"0\" a=\"0.3\" b=\"0\" c=\"0\" "
      "d=\"0\"/></lane></right></laneSection></lanes></road></OpenDRIVE>";
  const RoadNetwork net = parse_opendrive(xml, "single.xodr");
  const RoadGraph both = build_road_graph(net, {.spacing = 0.1, .single_lane_roads_both_ways = true});
  ASSERT_EQ(both.points.size(), 11u);  // s = 0, 0.1, ..., 1 inclusive
  EXPECT_EQ(both.edge_count(), 20u);
  for (const auto& p : both.points) EXPECT_NEAR(p.y, 0.0, 1e-12);  // laneOffset puts the lane on the line
  const RoadGraph one = build_road_graph(net, {.spacing = 0.1, .single_lane_roads_both_ways = false});
  EXPECT_EQ(one.edge_count(), 10u);
  for (std::size_t i = 0; i < one.points.size(); ++i) {
    for (const int j : one.successors[i]) EXPECT_GT(one.points[static_cast<std::size_t>(j)].s, one.points[i].s);
  }
  EXPECT_THROW(build_road_graph(net, {.spacing = 0.0, .single_lane_roads_both_ways = true}), MapError);
}

TEST(RoadGraph, LaneSectionsJoinThroughLaneLinks) {
  // Two sections; lane -1 of the first continues as lane -2 of the second (a lane opens on the
  // inside), stated by its successor link.
  const std::string xml =
      "<OpenDRIVE><header/><road id=\"1\" length=\"20\" junction=\"-1\"><planView><geometry s=\"0\" x=\"0\" y=\"0\" "
      "hdg=\"0\" length=\"20\"><line/></geometry></planView><lanes>"
      "<laneSection s=\"0\"><right><lane id=\"-1\" type=\"driving\"><link><successor id=\"-2\"/></link>"
      "<width sOffset=\"0\" a=\"3\" b=\"0\" c=\"0\" d=\"0\"/></lane></right></laneSection>"
      "<laneSection s=\"10\"><right><lane id=\"-1\" type=\"driving\"><width sOffset=\"0\" a=\"3\" b=\"0\" c=\"0\" "
      "d=\"0\"/></lane>"
      "<lane id=\"-2\" type=\"driving\"><link><predecessor id=\"-1\"/></link><width sOffset=\"0\" a=\"3\" b=\"0\" "
      "c=\"0\" d=\"0\"/>"
      "</lane></right></laneSection></lanes></road></OpenDRIVE>";
  const RoadNetwork net = parse_opendrive(xml, "sections.xodr");
  const RoadGraphBuild b = build_road_graph_detailed(net, {.spacing = 1.0, .single_lane_roads_both_ways = true});
  ASSERT_EQ(b.lanes.size(), 3u);
  const auto end_of_first = b.lanes[0].points.back();
  const auto& succ = b.graph.successors[static_cast<std::size_t>(end_of_first)];
  ASSERT_EQ(succ.size(), 1u);
  EXPECT_EQ(b.graph.points[static_cast<std::size_t>(succ[0])].lane_id, -2);
  EXPECT_NEAR(b.graph.points[static_cast<std::size_t>(succ[0])].s, 10.0, 1e-12);
}
