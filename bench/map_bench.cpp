// Parse + evaluate + road graph of a large generated OpenDRIVE network (target: a 1.6 MB network
// with hundreds of roads in under 200 ms). The network is written in memory so the benchmark
// needs no data file: a grid of two-way roads, each chaining line, spiral, arc, spiral and
// paramPoly3 records, four driving lanes plus sidewalks, two lane sections, joined through
// four-way junctions.

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <utility>

#include "map/opendrive.hpp"
#include "map/road_graph_builder.hpp"

namespace {

using fleet::map::Geometry;
using fleet::map::GeometryKind;

std::string num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.15g", v);
  return buf;
}

std::string lanes_xml(double length) {
  std::string out = "<lanes><laneOffset s=\"0\" a=\"0\" b=\"0\" c=\"0\" d=\"0\"/>";
  for (const double s : {0.0, 0.5 * length}) {
    out += "<laneSection s=\"" + num(s) + "\"><left>";
    for (int id = 1; id <= 3; ++id) {
      out += "<lane id=\"" + std::to_string(id) + "\" type=\"" + (id == 3 ? "sidewalk" : "driving") +
             "\" level=\"false\"><link><predecessor id=\"" + std::to_string(id) + "\"/><successor id=\"" +
             std::to_string(id) +
             "\"/></link><width sOffset=\"0\" a=\"3.5\" b=\"0\" c=\"0\" d=\"0\"/>"
             "<roadMark sOffset=\"0\" type=\"solid\" weight=\"standard\" color=\"standard\" width=\"0.12\"/></lane>";
    }
    out += "</left><center><lane id=\"0\" type=\"none\" level=\"false\"/></center><right>";
    for (int id = 1; id <= 3; ++id) {
      out += "<lane id=\"-" + std::to_string(id) + "\" type=\"" + (id == 3 ? "sidewalk" : "driving") +
             "\" level=\"false\"><link><predecessor id=\"-" + std::to_string(id) + "\"/><successor id=\"-" +
             std::to_string(id) +
             "\"/></link><width sOffset=\"0\" a=\"3.5\" b=\"0\" c=\"0\" d=\"0\"/>"
             "<roadMark sOffset=\"0\" type=\"solid\" weight=\"standard\" color=\"standard\" width=\"0.12\"/></lane>";
    }
    out += "</right></laneSection>";
  }
  return out + "</lanes>";
}

/// Plan view of a road leaving (x, y) along hdg: a gentle S made of every geometry kind, whose
/// records join exactly because each starts where the previous one ends.
std::string plan_view_xml(double x, double y, double hdg, double& length) {
  Geometry g;
  g.x = x;
  g.y = y;
  g.hdg = hdg;
  std::string out = "<planView>";
  const auto emit = [&](const std::string& shape) {
    out += "<geometry s=\"" + num(g.s) + "\" x=\"" + num(g.x) + "\" y=\"" + num(g.y) + "\" hdg=\"" + num(g.hdg) +
           "\" length=\"" + num(g.length) + "\">" + shape + "</geometry>";
    const fleet::map::RefPoint end = fleet::map::evaluate_geometry(g, g.length);
    g.s += g.length;
    g.x = end.x;
    g.y = end.y;
    g.hdg = end.hdg;
  };
  g.kind = GeometryKind::kLine;
  g.length = 20.0;
  emit("<line/>");
  g.kind = GeometryKind::kSpiral;
  g.length = 15.0;
  g.curv_start = 0.0;
  g.curv_end = 0.01;
  emit("<spiral curvStart=\"0\" curvEnd=\"0.01\"/>");
  g.kind = GeometryKind::kArc;
  g.length = 10.0;
  g.curvature = 0.01;
  emit("<arc curvature=\"0.01\"/>");
  g.kind = GeometryKind::kSpiral;
  g.length = 15.0;
  g.curv_start = 0.01;
  g.curv_end = 0.0;
  emit("<spiral curvStart=\"0.01\" curvEnd=\"0\"/>");
  g.kind = GeometryKind::kParamPoly3;
  g.length = 20.0;
  g.normalized = false;
  g.au = 0.0;
  g.bu = 1.0;
  g.cu = 0.0;
  g.du = 0.0;
  g.av = 0.0;
  g.bv = 0.0;
  g.cv = -0.004;
  g.dv = 0.0001;
  emit(
      "<paramPoly3 aU=\"0\" bU=\"1\" cU=\"0\" dU=\"0\" aV=\"0\" bV=\"0\" cV=\"-0.004\" dV=\"0.0001\" "
      "pRange=\"arcLength\"/>");
  length = g.s;
  return out + "</planView>";
}

/// `rows` x `cols` junctions on a torus; a road leaves each junction east and north.
std::string make_network(int rows, int cols) {
  std::string xml = "<?xml version=\"1.0\"?>\n<OpenDRIVE><header revMajor=\"1\" revMinor=\"6\" name=\"bench\"/>";
  std::string junctions;
  int road_id = 0;
  for (int i = 0; i < rows; ++i) {
    for (int j = 0; j < cols; ++j) {
      const int junction = i * cols + j;
      for (int dir = 0; dir < 2; ++dir) {
        const int next = dir == 0 ? (i * cols + (j + 1) % cols) : (((i + 1) % rows) * cols + j);
        double length = 0.0;
        const std::string plan = plan_view_xml(100.0 * j, 100.0 * i, dir == 0 ? 0.0 : M_PI / 2, length);
        xml += "<road name=\"r" + std::to_string(road_id) + "\" id=\"" + std::to_string(road_id) + "\" length=\"" +
               num(length) + "\" junction=\"-1\"><link><predecessor elementType=\"junction\" elementId=\"" +
               std::to_string(junction) + "\"/><successor elementType=\"junction\" elementId=\"" +
               std::to_string(next) + "\"/></link>" + plan +
               "<elevationProfile><elevation s=\"0\" a=\"0\" b=\"0\" c=\"0\" d=\"0\"/></elevationProfile>" +
               lanes_xml(length) + "</road>\n";
        ++road_id;
      }
    }
  }
  // Each junction lets traffic go straight on between the road arriving from the west (or
  // south) and the one leaving east (or north). Those roads link to each other directly here,
  // i.e. the junction's connecting roads are the roads themselves (a direct junction).
  for (int i = 0; i < rows; ++i) {
    for (int j = 0; j < cols; ++j) {
      const int here = i * cols + j;
      const int east = 2 * here, north = 2 * here + 1;
      const int from_west = 2 * (i * cols + (j + cols - 1) % cols);
      const int from_south = 2 * (((i + rows - 1) % rows) * cols + j) + 1;
      junctions += "<junction id=\"" + std::to_string(here) + "\" type=\"direct\">";
      int c = 0;
      for (const auto& [in, out] : {std::pair{from_west, east}, std::pair{from_south, north},
                                    std::pair{from_west, north}, std::pair{from_south, east}}) {
        junctions += "<connection id=\"" + std::to_string(c++) + "\" incomingRoad=\"" + std::to_string(in) +
                     "\" linkedRoad=\"" + std::to_string(out) +
                     "\" contactPoint=\"start\"><laneLink from=\"-1\" to=\"-1\"/><laneLink from=\"-2\" to=\"-2\"/>"
                     "<laneLink from=\"1\" to=\"1\"/><laneLink from=\"2\" to=\"2\"/></connection>";
      }
      junctions += "</junction>\n";
    }
  }
  return xml + junctions + "</OpenDRIVE>\n";
}

const std::string& network_text() {
  static const std::string text = make_network(13, 14);  // 364 roads, about 1.6 MB
  return text;
}

void BM_ParseOpenDrive(benchmark::State& state) {
  const std::string& text = network_text();
  for (auto _ : state) {
    auto net = fleet::map::parse_opendrive(text, "bench.xodr");
    benchmark::DoNotOptimize(net);
  }
  state.counters["bytes"] = static_cast<double>(text.size());
}
BENCHMARK(BM_ParseOpenDrive)->Unit(benchmark::kMillisecond);

void BM_BuildRoadGraph(benchmark::State& state) {
  const auto net = fleet::map::parse_opendrive(network_text(), "bench.xodr");
  std::size_t points = 0;
  for (auto _ : state) {
    auto graph = fleet::map::build_road_graph(net, {.spacing = 1.0, .single_lane_roads_both_ways = true});
    points = graph.points.size();
    benchmark::DoNotOptimize(graph);
  }
  state.counters["points"] = static_cast<double>(points);
}
BENCHMARK(BM_BuildRoadGraph)->Unit(benchmark::kMillisecond);

void BM_ParseEvaluateBuild(benchmark::State& state) {
  const std::string& text = network_text();
  std::size_t roads = 0, points = 0, edges = 0;
  for (auto _ : state) {
    const auto net = fleet::map::parse_opendrive(text, "bench.xodr");
    const auto graph = fleet::map::build_road_graph(net, {.spacing = 1.0, .single_lane_roads_both_ways = true});
    roads = net.roads.size();
    points = graph.points.size();
    edges = graph.edge_count();
    benchmark::DoNotOptimize(graph);
  }
  state.counters["bytes"] = static_cast<double>(text.size());
  state.counters["roads"] = static_cast<double>(roads);
  state.counters["points"] = static_cast<double>(points);
  state.counters["edges"] = static_cast<double>(edges);
}
BENCHMARK(BM_ParseEvaluateBuild)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
