// The plant (maps/plant.*): a real-scale site for several fleets. Its roads have the lanes and
// widths the design gives them, and the places each fleet can reach follow from those widths.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <functional>
#include <numbers>
#include <set>
#include <string>

#include "geometry/polygon.hpp"
#include "map/site_map.hpp"
#include "test_paths.hpp"

using namespace fleet::map;
using fleet::geometry::Footprint;
using fleet::geometry::footprint_polygon;
using fleet::geometry::Polygon;
using fleet::geometry::segment_polygon_distance;

namespace {

constexpr double kFitMargin = 0.10;  // the plant's margin: a vehicle fits when width + margin <= lane width
constexpr double kForkliftWidth = 0.8;
constexpr double kPickerWidth = 0.5;
constexpr double kReachTruckWidth = 0.9;
const Footprint kPallet{1.2, 0.8};      // EPAL, forks along the length
const Footprint kReachTruck{1.6, 0.9};  // the largest vehicle that parks at a home stall
const Footprint kStacker{1.7, 0.748};   // parks in its own bay

const SiteMap& plant() {
  static const SiteMap map = load_site_map(fleet::test::source_path("/maps/plant.yaml"));
  return map;
}

const Road& road_of(const SiteMap& map, const GraphPoint& p) {
  const Road* road = map.network.find_road(p.road_id);
  if (road == nullptr) throw std::runtime_error("no road " + p.road_id);
  return *road;
}

/// Width of the lane each graph point lies on, from the OpenDRIVE lanes.
std::vector<double> lane_widths(const SiteMap& map) {
  std::vector<double> widths;
  for (const GraphPoint& p : map.graph.graph.points) {
    const Road& road = road_of(map, p);
    widths.push_back(lane_width_at(road, section_index_at(road, p.s), p.lane_id, p.s));
  }
  return widths;
}

/// Points reachable from `start` over points a vehicle of `width` fits on.
std::vector<bool> reachable(const SiteMap& map, int start, double width) {
  const RoadGraph& g = map.graph.graph;
  const std::vector<double> widths = lane_widths(map);
  const auto fits = [&](int i) { return width + kFitMargin <= widths[static_cast<std::size_t>(i)] + 1e-9; };
  std::vector<bool> seen(g.points.size(), false);
  if (!fits(start)) return seen;
  std::deque<int> open{start};
  seen[static_cast<std::size_t>(start)] = true;
  while (!open.empty()) {
    const int v = open.front();
    open.pop_front();
    for (const int w : g.successors[static_cast<std::size_t>(v)]) {
      if (!seen[static_cast<std::size_t>(w)] && fits(w)) {
        seen[static_cast<std::size_t>(w)] = true;
        open.push_back(w);
      }
    }
  }
  return seen;
}

bool starts_with(const std::string& s, const std::string& prefix) {
  return s.rfind(prefix, 0) == 0;
}

/// Distance from `polygon` to the nearest lane area among the edges `counted` accepts: the lane
/// centre segment less half the narrower lane width of its two ends; negative when they overlap.
double clearance_to_lanes(const SiteMap& map, const Polygon& polygon,
                          const std::function<bool(const GraphPoint&)>& counted) {
  const RoadGraph& g = map.graph.graph;
  const std::vector<double> widths = lane_widths(map);
  double best = 1e9;
  for (std::size_t i = 0; i < g.points.size(); ++i) {
    const GraphPoint& a = g.points[i];
    for (const int j : g.successors[i]) {
      const GraphPoint& b = g.points[static_cast<std::size_t>(j)];
      if (!counted(a) || !counted(b)) continue;
      const double half = 0.5 * std::min(widths[i], widths[static_cast<std::size_t>(j)]);
      best = std::min(best, segment_polygon_distance({a.x, a.y}, {b.x, b.y}, polygon) - half);
    }
  }
  return best;
}

}  // namespace

TEST(Plant, FinishedGoodsCorridorHasTwoLanesOf149mDrivenOppositeWays) {
  const SiteMap& map = plant();
  const Road* corridor = nullptr;
  for (const Road& r : map.network.roads) {
    if (r.name == "finished-goods corridor") corridor = &r;
  }
  ASSERT_NE(corridor, nullptr);
  ASSERT_EQ(corridor->sections.size(), 1u);
  EXPECT_NEAR(lane_width_at(*corridor, 0, -1, 0.0), 1.49, 1e-9);
  EXPECT_NEAR(lane_width_at(*corridor, 0, 1, corridor->length), 1.49, 1e-9);
  EXPECT_NEAR(lane_center_t(*corridor, 0, -1, 0.0), -0.745, 1e-9);  // keep right: lane -1 right of the line

  const RoadGraph& g = map.graph.graph;
  int along = 0, against = 0;
  for (std::size_t i = 0; i < g.points.size(); ++i) {
    const GraphPoint& a = g.points[i];
    if (a.road_id != corridor->id) continue;
    EXPECT_TRUE(a.lane_id == -1 || a.lane_id == 1) << a.lane_id;
    for (const int j : g.successors[i]) {
      const GraphPoint& b = g.points[static_cast<std::size_t>(j)];
      if (b.road_id != corridor->id) continue;
      ASSERT_EQ(a.lane_id, b.lane_id) << "no edge crosses from one lane to the other";
      // The corridor runs west to east: right-hand traffic drives lane -1 east, lane +1 west.
      if (a.lane_id == -1) {
        EXPECT_GT(b.s, a.s);
        EXPECT_GT(b.x, a.x);
        ++along;
      } else {
        EXPECT_LT(b.s, a.s);
        EXPECT_LT(b.x, a.x);
        ++against;
      }
    }
  }
  EXPECT_GT(along, 40);  // 24 m at 0.5 m
  EXPECT_EQ(along, against);
}

TEST(Plant, CrossAndRackAislesAreTwoWayAndWideEnough) {
  const SiteMap& map = plant();
  int cross = 0, rack = 0;
  for (const Road& r : map.network.roads) {
    if (r.in_junction()) continue;
    const bool is_cross = r.name.find("aisle") != std::string::npos && !starts_with(r.name, "rack aisle");
    if (!is_cross && !starts_with(r.name, "rack aisle")) continue;
    SCOPED_TRACE(r.name);
    ASSERT_NE(r.sections[0].find(-1), nullptr);
    ASSERT_NE(r.sections[0].find(1), nullptr);
    const double road = lane_width_at(r, 0, -1, 0.0) + lane_width_at(r, 0, 1, 0.0);
    if (is_cross) {
      EXPECT_GE(road, 3.5 - 1e-9);
      ++cross;
    } else {
      EXPECT_NEAR(road, 3.0, 1e-9);  // between the rack faces
      ++rack;
    }
  }
  EXPECT_GE(cross, 10);
  EXPECT_EQ(rack, 2);
}

TEST(Plant, NarrowLanesTakeAForkliftButNotAReachTruck) {
  const SiteMap& map = plant();
  const std::vector<double> widths = lane_widths(map);
  std::size_t narrow = 0;
  for (std::size_t i = 0; i < widths.size(); ++i) {
    const double w = widths[i];
    const GraphPoint& at = map.graph.graph.points[i];
    // Every lane takes a forklift but the stacker bays, which no vehicle drives along, and the
    // pickers' access, street and stalls south of the south cross aisle, which only a picker fits.
    if (std::abs(w - 0.8) < 1e-3) continue;
    if (at.x > 19.0 && at.x < 27.0 && at.y < 6.0 && w < kForkliftWidth + kFitMargin) {
      EXPECT_GE(w, kPickerWidth + kFitMargin - 1e-9) << "a picker fits its street";
      continue;
    }
    EXPECT_GE(w, kForkliftWidth + kFitMargin - 1e-9)
        << "every lane takes a forklift: " << at.road_id << " at (" << at.x << ", " << at.y << ")";
    if (w < kReachTruckWidth + kFitMargin) ++narrow;
  }
  EXPECT_GT(narrow, 20u);
}

TEST(Plant, EveryPlaceIsReachableFromEveryHome) {
  const SiteMap& map = plant();
  const SiteReport report = check_site_map(map);
  ASSERT_TRUE(report.usable()) << format_report(report);
  for (const PlaceReach& home : report.homes) {
    const std::vector<bool> seen = reachable(map, home.nearest_point, 0.0);
    for (const PlaceReach& place : report.areas) {
      EXPECT_TRUE(seen[static_cast<std::size_t>(place.nearest_point)]) << home.id << " -> " << place.id;
    }
  }
}

TEST(Plant, ForkliftsReachEveryPlaceReachTrucksEveryHighPlaceButNotTheNarrowOnes) {
  const SiteMap& map = plant();
  const SiteReport report = check_site_map(map);
  int forklift_homes = 0, reach_truck_homes = 0, narrow_only = 0, high = 0;
  for (const PlaceReach& home : report.homes) {
    if (starts_with(home.id, "PT")) continue;  // a stacker's bay (stacker_test.cpp drives them)
    if (starts_with(home.id, "PP")) {
      // A picker's stall: from there it reaches every place it takes boxes from or drops them at.
      const std::vector<bool> seen = reachable(map, home.nearest_point, kPickerWidth);
      for (std::size_t i = 0; i < report.areas.size(); ++i) {
        const LoadingArea& area = map.site.loading_areas[i];
        if (!area.offers("pickItem") && !area.offers("dropItem")) continue;
        EXPECT_TRUE(seen[static_cast<std::size_t>(report.areas[i].nearest_point)]) << home.id << " -> " << area.id;
      }
      continue;
    }
    const bool forklift = starts_with(home.id, "PF");
    ASSERT_TRUE(forklift || starts_with(home.id, "PR")) << home.id;
    (forklift ? forklift_homes : reach_truck_homes)++;
    const std::vector<bool> seen = reachable(map, home.nearest_point, forklift ? kForkliftWidth : kReachTruckWidth);
    for (std::size_t i = 0; i < report.areas.size(); ++i) {
      const LoadingArea& area = map.site.loading_areas[i];
      const bool reached = seen[static_cast<std::size_t>(report.areas[i].nearest_point)];
      // Handled from a single-lane spur: expedition's EN places and the packing stations off the
      // spurs; those along the south cross aisle are handled from its 1.75 m lane.
      const double lane = map.graph.graph.points[static_cast<std::size_t>(report.areas[i].nearest_point)].lane_width;
      const bool on_narrow_road = starts_with(area.id, "EN") || (starts_with(area.id, "PS") && lane < 1.0);
      if (starts_with(area.id, "EN")) {
        EXPECT_LT(lane, 1.0) << area.id;
      }
      if (forklift) {
        EXPECT_TRUE(reached) << home.id << " -> " << area.id;
      } else if (on_narrow_road) {
        EXPECT_FALSE(reached) << home.id << " -> " << area.id << ": a reach truck does not fit the narrow spur";
        narrow_only += home.id == "PR1" ? 1 : 0;
      } else {
        EXPECT_TRUE(reached) << home.id << " -> " << area.id;
        high += home.id == "PR1" && area.height > 0.5 ? 1 : 0;
      }
    }
  }
  EXPECT_EQ(forklift_homes, 8);
  EXPECT_EQ(reach_truck_homes, 8);
  EXPECT_EQ(narrow_only, 14);  // 6 on the expedition spur, 8 at the packing stations
  EXPECT_EQ(high, 36);
}

TEST(Plant, PlacesSayWhatTheyOfferAndHowHighTheirLoadStands) {
  const Site& site = plant().site;
  int high = 0, bays = 0, packing = 0, finished = 0;
  for (const LoadingArea& a : site.loading_areas) {
    SCOPED_TRACE(a.id);
    EXPECT_TRUE(a.offers("pick") || a.offers("drop"));
    if (starts_with(a.id, "RH")) {
      ++high;
      EXPECT_GE(a.height, 2.0);
      EXPECT_LE(a.height, 4.5);
      EXPECT_TRUE(a.offers("pick") && a.offers("drop"));
    } else if (starts_with(a.id, "FG")) {
      ++finished;
      EXPECT_NEAR(a.height, 0.30, 1e-9);  // on the limiter [Stacker thesis, section 4.1.3]
      EXPECT_EQ(a.actions, std::vector<std::string>{"pick"});
    } else {
      EXPECT_EQ(a.height, 0.0);
    }
    if (starts_with(a.id, "RB")) bays += a.offers("pickItem") ? 1 : 0;
    if (starts_with(a.id, "PS")) packing += a.offers("dropItem") ? 1 : 0;
  }
  EXPECT_EQ(high, 36);
  EXPECT_EQ(bays, 24);
  EXPECT_EQ(packing, 12);
  EXPECT_EQ(finished, 16);
}

TEST(Plant, PalletsStandBesideTheLanesAndHomesInTheirOwnStalls) {
  const SiteMap& map = plant();
  for (const LoadingArea& a : map.site.loading_areas) {
    const Polygon pallet = footprint_polygon(a.pose, kPallet);
    // Racked pallets stand flush with the rack face, which is the aisle lane's edge; yaws written
    // to six decimals tilt them by a fraction of a millimetre.
    EXPECT_GE(clearance_to_lanes(map, pallet, [](const GraphPoint&) { return true; }), -1e-3) << a.id;
  }
  const RoadGraph& g = map.graph.graph;
  std::set<std::string> junction_roads;
  for (const Road& r : map.network.roads) {
    if (r.in_junction()) junction_roads.insert(r.id);
  }
  for (const Home& h : map.site.homes) {
    // A home is at the end of its stall, a dead-end lane of its own: clear of every other lane. A
    // stacker's bay is as deep as the stacker: its front meets the aisle's edge.
    const std::string stall = g.points[static_cast<std::size_t>(nearest_point(g, h.pose.x, h.pose.y))].road_id;
    const bool bay = starts_with(h.id, "PT");
    const Polygon body = footprint_polygon(h.pose, bay ? kStacker : kReachTruck);
    const double clearance = clearance_to_lanes(map, body, [&](const GraphPoint& p) {
      return p.road_id != stall && !(bay && junction_roads.contains(p.road_id));
    });
    EXPECT_GT(clearance, bay ? -1e-6 : 0.0) << h.id;
    EXPECT_TRUE(map.site.bounds.contains(body[0]) && map.site.bounds.contains(body[2])) << h.id;
    for (const Home& other : map.site.homes) {
      if (other.id == h.id) continue;
      EXPECT_FALSE(fleet::geometry::polygons_overlap(body, footprint_polygon(other.pose, kReachTruck)))
          << h.id << " / " << other.id;
    }
  }
}

TEST(Plant, FinishedGoodsStandBehindTheLimiterAcrossFromTheCorridor) {
  const SiteMap& map = plant();
  const Rack* limiter = nullptr;
  for (const Rack& r : map.site.racks) {
    if (r.id == "L1") limiter = &r;
  }
  ASSERT_NE(limiter, nullptr);
  for (const LoadingArea& a : map.site.loading_areas) {
    if (!starts_with(a.id, "FG")) continue;
    const double ax = a.pose.x + map.site.approach_distance * std::cos(a.pose.yaw);
    const double ay = a.pose.y + map.site.approach_distance * std::sin(a.pose.yaw);
    EXPECT_TRUE(fleet::geometry::segment_intersects_polygon({a.pose.x, a.pose.y}, {ax, ay}, limiter->polygon))
        << a.id << ": the stacker reaches over the limiter";
  }
}

TEST(Plant, MarkersOnEveryPillarAndWithinCameraRangeEverywhere) {
  const SiteMap& map = plant();
  const auto& markers = map.site.markers;
  // Pillar markers 3.5 m apart along each rack face [Picker thesis, section 4.2.9.3].
  int pillar = 0;
  for (std::size_t i = 0; i + 1 < markers.size(); ++i) {
    if (markers[i].id < 100 || markers[i + 1].id != markers[i].id + 1) continue;
    EXPECT_NEAR(markers[i + 1].pose.x - markers[i].pose.x, 3.5, 1e-9);
    EXPECT_NEAR(markers[i + 1].pose.y, markers[i].pose.y, 1e-9);
    ++pillar;
  }
  EXPECT_EQ(pillar, 5 * 6);
  // From every lane a marker is in sight of the Axis camera, which detects them up to 10 m
  // [Picker thesis, section 4.2.9.2].
  for (const GraphPoint& p : map.graph.graph.points) {
    double nearest = 1e9;
    for (const Marker& m : markers) nearest = std::min(nearest, std::hypot(m.pose.x - p.x, m.pose.y - p.y));
    EXPECT_LE(nearest, 10.0) << p.road_id << " at (" << p.x << ", " << p.y << ")";
  }
  // UWB anchors about every 20 m: three or more within 25 m of every lane point.
  for (const GraphPoint& p : map.graph.graph.points) {
    int near = 0;
    for (const UwbAnchor& u : map.site.uwb_anchors) near += std::hypot(u.x - p.x, u.y - p.y) <= 25.0 ? 1 : 0;
    EXPECT_GE(near, 3) << p.road_id << " at (" << p.x << ", " << p.y << ")";
  }
}
