#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>

#include "map/road_graph.hpp"
#include "map/site.hpp"
#include "planning/occupancy_grid.hpp"

namespace fleet::planning {

/// Fixed per StaticGrid instance: the grid caches its layers on these values.
struct StaticGridConfiguration {
  double resolution = 0.02;         ///< metres per cell
  double road_width = 0.0;          ///< side of the square around each graph point; <= 0: the site's
  double obstacle_inflation = 0.0;  ///< obstacles grow by this (robot radius + margin), metres
  double loading_area_width = 0.0;  ///< width of the free corridor to a loading area; <= 0: road width
};

/// The static occupancy grid [Forklift thesis, section 5.3, Fig. 5.9]: the road squares around every
/// graph point are free (5.9a), loading areas and the corridor from each to its nearest graph
/// point are free, enabled static obstacles and temporary obstacles are occupied (5.9b).
///
/// The map layer is built once; the grid is rebuilt lazily, only after an obstacle changed, so
/// planners that cache on `revision()` replan only when something moved.
class StaticGrid {
 public:
  StaticGrid(const StaticGridConfiguration& configuration, const map::Site& site, const map::RoadGraph& graph);

  /// Switches a site obstacle on or off. False when the site has no obstacle of that id.
  bool set_obstacle_enabled(const std::string& id, bool enabled);
  /// An obstacle outside the site file (from the server or the operator), by id.
  void add_obstacle(const std::string& id, const geometry::Polygon& polygon);
  bool remove_obstacle(const std::string& id);
  /// Temporary obstacles from local planning [Forklift thesis, Fig. 5.13].
  void add_temporary(const std::string& id, const geometry::Polygon& polygon);
  bool remove_temporary(const std::string& id);
  const std::map<std::string, geometry::Polygon>& temporaries() const { return temporaries_; }

  /// Map layer + obstacles + temporaries: what the global planner reads Obs(x') from.
  const OccupancyGrid& grid();
  /// Map layer + obstacles without the temporaries: what local planning checks against, so a
  /// temporary obstacle never keeps itself alive.
  const OccupancyGrid& permanent_grid();
  /// The road and loading-area layer alone (Forklift thesis, Fig. 5.9a).
  const OccupancyGrid& map_layer() const { return map_layer_; }

  /// Grows by one on every change of the obstacles.
  std::uint64_t revision() const { return revision_; }
  /// How often the grid was rebuilt; lets tests check that nothing is rebuilt without a change.
  std::size_t build_count() const { return build_count_; }
  const StaticGridConfiguration& configuration() const { return configuration_; }
  double road_width() const { return road_width_; }

 private:
  void rebuild();
  void stamp(OccupancyGrid& grid, const geometry::Polygon& polygon) const;

  StaticGridConfiguration configuration_;
  double road_width_;
  OccupancyGrid map_layer_;
  std::map<std::string, geometry::Polygon> site_obstacles_;
  std::set<std::string> enabled_;
  std::map<std::string, geometry::Polygon> extra_obstacles_;
  std::map<std::string, geometry::Polygon> temporaries_;
  OccupancyGrid permanent_;
  OccupancyGrid grid_;
  std::uint64_t revision_ = 1;
  std::uint64_t built_revision_ = 0;
  std::size_t build_count_ = 0;
};

}  // namespace fleet::planning
