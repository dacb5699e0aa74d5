// libFuzzer target: any byte string given to the OpenDRIVE parser either yields a network that
// evaluates and builds a road graph, or a MapError. Anything else (a crash, a sanitizer report,
// another exception type) is a bug.

#include <cstddef>
#include <cstdint>
#include <string>

#include "map/opendrive.hpp"
#include "map/reference_samples.hpp"
#include "map/road_graph_builder.hpp"
#include "map/site.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const fleet::map::RoadNetwork net = fleet::map::parse_opendrive(text, "fuzz.xodr");
    double total = 0.0;
    for (const auto& road : net.roads) {
      total += road.length;
      for (std::size_t si = 0; si < road.sections.size(); ++si) {
        for (const auto* side : {&road.sections[si].left, &road.sections[si].right}) {
          for (const auto& lane : *side) (void)fleet::map::lane_center(road, si, lane.id, road.sections[si].s);
        }
      }
    }
    // A spacing that keeps the graph small whatever lengths the input claims.
    const double spacing = total > 1000.0 ? total / 1000.0 : 1.0;
    const auto graph = fleet::map::build_road_graph(net, {.spacing = spacing, .single_lane_roads_both_ways = true});
    std::vector<int> component;
    (void)fleet::map::strong_components(graph, component);
    (void)fleet::map::sample_reference_lines(net, spacing);
  } catch (const fleet::map::MapError&) {
    // Refused with a message: the expected outcome for malformed input.
  }
  return 0;
}
