#pragma once

#include <cstdint>
#include <vector>

#include "geometry/pose.hpp"
#include "map/road_graph.hpp"
#include "planning/occupancy_grid.hpp"
#include "planning/plan_status.hpp"

namespace fleet::planning {

/// Weights of [Forklift thesis, eq. 5.5] and the obstacle cost of [Forklift thesis, section 5.3]. Fixed per planner.
struct RoadPlannerConfiguration {
  double w_d = 1.0;              ///< per metre
  double w_h = 0.2;              ///< per radian of heading change
  double obstacle_cost = 100.0;  ///< Obs(x') of a point inside an obstacle (the thesis's value)
};

struct RoadPlan {
  PlanStatus status = PlanStatus::kNoPath;
  std::vector<int> point_ids;          ///< graph points from the start state on
  std::vector<geometry::Vec2> points;  ///< their positions
  double cost = 0.0;                   ///< C(x_G) of the search, obstacle costs included
  double length = 0.0;                 ///< metres along `points`
  int blocked_point = -1;              ///< kBlockedPartial: first blocked point the route met
  std::size_t expanded = 0;            ///< states moved to the closed list
};

/// A* on the road graph [Forklift thesis, section 5.2, Fig. 5.7].
///
/// The graph is turned into flat arrays once at construction and the search buffers are reused
/// between queries, so a query allocates nothing but its result. One query at a time per instance.
class RoadPlanner {
 public:
  RoadPlanner(const map::RoadGraph& graph, const RoadPlannerConfiguration& configuration = {});

  /// Reads Obs(x') for every graph point from the static grid [Forklift thesis, section 5.3]. Call again
  /// when the grid's revision changes.
  void set_obstacles(const OccupancyGrid& static_grid);
  void clear_obstacles();
  bool blocked(int point) const { return blocked_[static_cast<std::size_t>(point)] != 0; }

  /// kRoute: only points of the graph's main strongly connected component, from which every
  /// other can be reached (what is left of a lane the vehicle does not fit, cut out of its
  /// graph, is no place to start or end a route).
  enum class PointUse { kAny, kRoute };
  /// Graph point nearest `p` by Euclidean distance (Forklift thesis, Fig. 5.6); -1 when there is none.
  int nearest_point(geometry::Vec2 p, PointUse use = PointUse::kAny) const;
  /// The nearest route point (kRoute) with an edge leaving it within `tolerance` of `heading` or
  /// of its opposite: a point on a lane along that axis, not on a junction's connecting road
  /// across it; -1 when there is none.
  int nearest_point_along(geometry::Vec2 p, double heading, double tolerance) const;

  /// Start and goal states are the graph points nearest the poses; the start's cost-to-come is
  /// its distance from the start pose. When the cheapest route crosses a blocked point, the plan
  /// ends at the last free point before it and the status is kBlockedPartial (Forklift thesis, Fig. 5.11).
  RoadPlan plan(const geometry::Pose2& start, const geometry::Pose2& goal, const PlanOptions& options = {});
  /// The same between graph points, with C(x_S) = `start_cost`.
  RoadPlan plan_between(int start_point, int goal_point, double start_cost, const PlanOptions& options = {});
  /// The same from the cheapest of several start states, each with its own C(x_S).
  RoadPlan plan_from(const std::vector<std::pair<int, double>>& starts, int goal_point,
                     const PlanOptions& options = {});
  /// The start states for a robot at `p`: the nearest route point and the points it leads to
  /// that are almost as near (within `slack` times its distance), each with its distance as
  /// C(x_S). A robot standing between two points of a lane starts on whichever leads on, not on
  /// the one behind it.
  std::vector<std::pair<int, double>> start_states(geometry::Vec2 p, double slack) const;

  std::size_t point_count() const { return xs_.size(); }
  /// Whether point `i` is in the main strongly connected component (see PointUse::kRoute).
  bool in_main_component(int i) const { return main_component_[static_cast<std::size_t>(i)] != 0; }
  geometry::Vec2 point(int i) const { return {xs_[static_cast<std::size_t>(i)], ys_[static_cast<std::size_t>(i)]}; }
  const RoadPlannerConfiguration& configuration() const { return configuration_; }

 private:
  void mark_main_component();
  struct HeapItem {
    double f;
    double g;
    int node;
  };

  RoadPlannerConfiguration configuration_;
  std::vector<double> xs_, ys_;
  std::vector<std::uint32_t> offsets_;  ///< CSR adjacency: edges of i are [offsets_[i], offsets_[i+1])
  std::vector<int> targets_;
  std::vector<double> edge_length_;
  std::vector<double> edge_angle_;  ///< atan2(dy, dx) of each edge, the heading it assigns
  std::vector<std::uint8_t> blocked_;
  std::vector<std::uint8_t> main_component_;  ///< 1 for points of the largest strong component

  // The points by square cells of kIndexCell metres, for nearest_point: a site of tens of
  // thousands of points is asked for the nearest one many times a second.
  static constexpr double kIndexCell = 2.0;
  void build_index();
  int nearest_point_scan(geometry::Vec2 p, PointUse use) const;
  double index_min_x_ = 0.0, index_min_y_ = 0.0;
  int index_nx_ = 0, index_ny_ = 0;
  std::vector<std::uint32_t> cell_start_;  ///< points of cell c: cell_points_[cell_start_[c] .. cell_start_[c+1])
  std::vector<int> cell_points_;

  // Search state, reused; `stamp_` tells which entries belong to the current query.
  std::vector<std::uint32_t> stamp_;
  std::vector<std::uint8_t> closed_;
  std::vector<double> g_;
  std::vector<double> heading_;
  std::vector<int> parent_;
  std::vector<HeapItem> heap_;
  std::uint32_t query_ = 0;
};

}  // namespace fleet::planning
