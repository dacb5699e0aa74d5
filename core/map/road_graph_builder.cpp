// Road graph from OpenDRIVE [Forklift thesis, section 5.1, Fig. 5.3-5.5]: points sampled on lane
// centres, connected along lanes, across lane sections, road links and junction connections.

#include "map/road_graph_builder.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "map/site.hpp"

namespace fleet::map {

namespace {

/// Bounds the work a single lane may ask for, so that a hostile or mistaken file (a road of
/// 1e300 m) is refused instead of exhausting memory.
constexpr double kMaxSamplesPerLane = 1e6;

struct LaneEnd {
  std::size_t lane = 0;  ///< index into lanes
  bool at_end = false;   ///< the end at the section's largest s
};

class Builder {
 public:
  Builder(const RoadNetwork& net, const GraphOptions& options) : net_(net), options_(options) {}

  RoadGraphBuild build() {
    for (std::size_t r = 0; r < net_.roads.size(); ++r) sample_road(r);
    for (std::size_t r = 0; r < net_.roads.size(); ++r) link_sections(r);
    for (std::size_t r = 0; r < net_.roads.size(); ++r) link_roads(r);
    for (const Junction& j : net_.junctions) link_junction(j);
    return std::move(out_);
  }

 private:
  bool single_lane(const Road& road) const {
    for (const LaneSection& sec : road.sections) {
      int n = 0;
      for (const auto* side : {&sec.left, &sec.right}) {
        for (const Lane& l : *side) n += l.drivable() ? 1 : 0;
      }
      if (n != 1) return false;
    }
    return true;
  }

  LaneDirection direction(const Road& road, const Lane& lane, bool single) const {
    if (lane.type == "bidirectional" || (single && options_.single_lane_roads_both_ways)) return LaneDirection::kBoth;
    // RHT: right lanes (negative ids) run along the reference line; LHT mirrors that.
    const bool forward = (lane.id < 0) != road.left_hand_traffic;
    return forward ? LaneDirection::kForward : LaneDirection::kBackward;
  }

  void sample_road(std::size_t r) {
    const Road& road = net_.roads[r];
    const bool single = single_lane(road);
    for (std::size_t si = 0; si < road.sections.size(); ++si) {
      const LaneSection& sec = road.sections[si];
      const double s0 = sec.s;
      const double s1 = std::max(s0, road.section_end(si));
      // The thesis takes M = 10 points a road [Forklift thesis, section 5.1]; here the count follows the length so that
      // long and short roads get the same density, with both section ends always sampled.
      const double wanted = std::ceil((s1 - s0) / options_.spacing - 1e-9);
      if (!(wanted <= kMaxSamplesPerLane)) {
        throw MapError(net_.file + ":" + std::to_string(sec.line) + ": <laneSection> of road '" + road.id +
                       "': " + std::to_string(s1 - s0) + " m at " + std::to_string(options_.spacing) +
                       " m spacing needs more than " + std::to_string(static_cast<long>(kMaxSamplesPerLane)) +
                       " graph points a lane");
      }
      const int n = std::max(1, static_cast<int>(wanted));
      for (const auto* side : {&sec.left, &sec.right}) {
        for (const Lane& lane : *side) {
          if (!lane.drivable()) continue;
          GraphLane gl{r, si, lane.id, direction(road, lane, single), {}};
          gl.points.reserve(static_cast<std::size_t>(n) + 1);
          for (int i = 0; i <= n; ++i) {
            const double s = i == n ? s1 : s0 + (s1 - s0) * i / n;
            const RefPoint p = lane_center(road, si, lane.id, s);
            const int id = static_cast<int>(out_.graph.points.size());
            const double width = lane_width_at(road, si, lane.id, s);
            out_.graph.points.push_back(
                {id, p.x, p.y, road.id, lane.id, s, width > 0.0 ? width : options_.default_lane_width});
            out_.graph.successors.emplace_back();
            gl.points.push_back(id);
          }
          // Inner points connect to the previous and next point [Forklift thesis, section 5.1].
          for (std::size_t i = 0; i + 1 < gl.points.size(); ++i) {
            if (gl.direction != LaneDirection::kBackward) add_edge(gl.points[i], gl.points[i + 1]);
            if (gl.direction != LaneDirection::kForward) add_edge(gl.points[i + 1], gl.points[i]);
          }
          index_[{r, si, lane.id}] = out_.lanes.size();
          out_.lanes.push_back(std::move(gl));
        }
      }
    }
  }

  const GraphLane* lane_of(std::size_t road, std::size_t section, int lane_id, std::size_t* index) const {
    const auto it = index_.find({road, section, lane_id});
    if (it == index_.end()) return nullptr;
    *index = it->second;
    return &out_.lanes[it->second];
  }

  void add_edge(int from, int to) {
    auto& succ = out_.graph.successors[static_cast<std::size_t>(from)];
    if (from != to && std::find(succ.begin(), succ.end(), to) == succ.end()) succ.push_back(to);
  }

  static bool leaves_through(const GraphLane& l, bool at_end) {
    return at_end ? l.direction != LaneDirection::kBackward : l.direction != LaneDirection::kForward;
  }

  int end_point(const LaneEnd& e) const {
    const GraphLane& l = out_.lanes[e.lane];
    return e.at_end ? l.points.back() : l.points.front();
  }

  /// Joins two lane ends that touch: traffic passes from one to the other when the first lane
  /// can be left through that end and the second entered through its end.
  void join(const LaneEnd& a, const LaneEnd& b) {
    const GraphLane& la = out_.lanes[a.lane];
    const GraphLane& lb = out_.lanes[b.lane];
    // Entering a lane through an end is leaving it through the same end in reverse.
    const auto enters_through = [](const GraphLane& l, bool at_end) { return leaves_through(l, !at_end); };
    if (leaves_through(la, a.at_end) && enters_through(lb, b.at_end)) add_edge(end_point(a), end_point(b));
    if (leaves_through(lb, b.at_end) && enters_through(la, a.at_end)) add_edge(end_point(b), end_point(a));
  }

  static int drivable_count(const LaneSection& sec, int* only) {
    int n = 0;
    for (const auto* side : {&sec.left, &sec.right}) {
      for (const Lane& l : *side) {
        if (l.drivable()) {
          ++n;
          *only = l.id;
        }
      }
    }
    return n;
  }

  /// Lane of `to_sec` that lane `from` continues into when no lane link says so: the only
  /// drivable lane when both sides have one, else the same id when the roads run the same way
  /// (end meets start) or the mirrored id when they meet head to head.
  static int default_lane(const LaneSection& from_sec, int from, const LaneSection& to_sec, bool same_orientation) {
    int only_from = 0, only_to = 0;
    if (drivable_count(from_sec, &only_from) == 1 && drivable_count(to_sec, &only_to) == 1) return only_to;
    return same_orientation ? from : -from;
  }

  void link_sections(std::size_t r) {
    const Road& road = net_.roads[r];
    for (std::size_t si = 0; si + 1 < road.sections.size(); ++si) {
      const LaneSection& sec = road.sections[si];
      for (const auto* side : {&sec.left, &sec.right}) {
        for (const Lane& lane : *side) {
          std::size_t a = 0, b = 0;
          if (lane_of(r, si, lane.id, &a) == nullptr) continue;
          const int next = lane.successor ? *lane.successor : default_lane(sec, lane.id, road.sections[si + 1], true);
          if (lane_of(r, si + 1, next, &b) == nullptr) continue;
          join({a, true}, {b, false});
        }
      }
    }
  }

  RefPoint road_end(const Road& road, bool at_end) const {
    return evaluate_reference(road, at_end ? road.length : 0.0);
  }

  /// Which end of `other` touches the `at_end` end of `road`, by distance.
  bool nearer_end(const Road& road, bool at_end, const Road& other) const {
    const RefPoint p = road_end(road, at_end);
    const RefPoint s = road_end(other, false);
    const RefPoint e = road_end(other, true);
    return std::hypot(e.x - p.x, e.y - p.y) < std::hypot(s.x - p.x, s.y - p.y);
  }

  /// Connects the lanes of `road` at one end to those of `other` at one end. `lane_target`
  /// gives an explicit lane mapping (lane link) or nothing.
  template <typename Target>
  void join_roads(std::size_t r, bool r_at_end, std::size_t o, bool o_at_end, Target lane_target) {
    const Road& road = net_.roads[r];
    const Road& other = net_.roads[o];
    const std::size_t rs = r_at_end ? road.sections.size() - 1 : 0;
    const std::size_t os = o_at_end ? other.sections.size() - 1 : 0;
    const LaneSection& rsec = road.sections[rs];
    for (const auto* side : {&rsec.left, &rsec.right}) {
      for (const Lane& lane : *side) {
        std::size_t a = 0, b = 0;
        if (lane_of(r, rs, lane.id, &a) == nullptr) continue;
        const std::optional<int> explicit_target = lane_target(lane);
        const int target =
            explicit_target ? *explicit_target : default_lane(rsec, lane.id, other.sections[os], r_at_end != o_at_end);
        if (lane_of(o, os, target, &b) == nullptr) continue;
        join({a, r_at_end}, {b, o_at_end});
      }
    }
  }

  void link_roads(std::size_t r) {
    const Road& road = net_.roads[r];
    for (const bool at_end : {false, true}) {
      const std::optional<RoadLink>& link = at_end ? road.successor : road.predecessor;
      if (!link || link->target != LinkTarget::kRoad) continue;
      const std::size_t o = net_.road_index(link->element_id);
      if (o >= net_.roads.size()) continue;
      const bool o_at_end = link->contact == ContactPoint::kNone ? nearer_end(road, at_end, net_.roads[o])
                                                                 : link->contact == ContactPoint::kEnd;
      join_roads(r, at_end, o, o_at_end, [at_end](const Lane& l) { return at_end ? l.successor : l.predecessor; });
    }
  }

  void link_junction(const Junction& j) {
    for (const Connection& c : j.connections) {
      const std::size_t in = net_.road_index(c.incoming_road);
      const std::size_t con = net_.road_index(c.connecting_road);
      if (in >= net_.roads.size() || con >= net_.roads.size()) continue;
      const Road& incoming = net_.roads[in];
      const bool con_at_end = c.contact == ContactPoint::kEnd;
      const bool pred = incoming.predecessor && incoming.predecessor->target == LinkTarget::kJunction &&
                        incoming.predecessor->element_id == j.id;
      const bool succ = incoming.successor && incoming.successor->target == LinkTarget::kJunction &&
                        incoming.successor->element_id == j.id;
      bool in_at_end = succ;
      if (pred == succ) {
        // Both ends (a loop through the junction) or neither: the geometry decides.
        in_at_end = nearer_end(net_.roads[con], con_at_end, incoming);
      }
      const auto& links = c.lane_links;
      join_roads(in, in_at_end, con, con_at_end, [&links](const Lane& l) -> std::optional<int> {
        if (links.empty()) return std::nullopt;
        for (const LaneLink& ll : links) {
          if (ll.from == l.id) return ll.to;
        }
        return 0;  // lane 0 is never a graph lane: this lane does not enter the connection
      });
    }
  }

  struct Key {
    std::size_t road, section;
    int lane;
    bool operator<(const Key& o) const { return std::tie(road, section, lane) < std::tie(o.road, o.section, o.lane); }
  };

  const RoadNetwork& net_;
  GraphOptions options_;
  RoadGraphBuild out_;
  std::map<Key, std::size_t> index_;
};

}  // namespace

RoadGraphBuild build_road_graph_detailed(const RoadNetwork& network, const GraphOptions& options) {
  if (!(options.spacing > 0.0) || !std::isfinite(options.spacing)) {
    throw MapError(network.file + ": graph spacing " + std::to_string(options.spacing) + " must be positive");
  }
  return Builder(network, options).build();
}

RoadGraph build_road_graph(const RoadNetwork& network, const GraphOptions& options) {
  return build_road_graph_detailed(network, options).graph;
}

std::size_t weak_components(const RoadGraph& graph, std::vector<int>& component) {
  const std::size_t n = graph.points.size();
  std::vector<std::vector<int>> adjacent(n);
  for (std::size_t i = 0; i < n; ++i) {
    for (const int j : graph.successors[i]) {
      adjacent[i].push_back(j);
      adjacent[static_cast<std::size_t>(j)].push_back(static_cast<int>(i));
    }
  }
  component.assign(n, -1);
  int count = 0;
  std::vector<int> stack;
  for (std::size_t start = 0; start < n; ++start) {
    if (component[start] >= 0) continue;
    component[start] = count;
    stack.push_back(static_cast<int>(start));
    while (!stack.empty()) {
      const int v = stack.back();
      stack.pop_back();
      for (const int w : adjacent[static_cast<std::size_t>(v)]) {
        if (component[static_cast<std::size_t>(w)] < 0) {
          component[static_cast<std::size_t>(w)] = count;
          stack.push_back(w);
        }
      }
    }
    ++count;
  }
  return static_cast<std::size_t>(count);
}

std::size_t strong_components(const RoadGraph& graph, std::vector<int>& component) {
  // Tarjan's algorithm with an explicit stack: road graphs of big sites are deep enough to
  // overflow the call stack with the recursive form.
  const std::size_t n = graph.points.size();
  std::vector<int> index(n, -1), low(n, 0);
  std::vector<bool> on_stack(n, false);
  std::vector<int> stack;
  component.assign(n, -1);
  int next_index = 0, count = 0;
  struct Frame {
    int v;
    std::size_t edge;
  };
  std::vector<Frame> call;
  for (std::size_t root = 0; root < n; ++root) {
    if (index[root] >= 0) continue;
    call.push_back({static_cast<int>(root), 0});
    index[root] = low[root] = next_index++;
    stack.push_back(static_cast<int>(root));
    on_stack[root] = true;
    while (!call.empty()) {
      Frame& f = call.back();
      const auto v = static_cast<std::size_t>(f.v);
      if (f.edge < graph.successors[v].size()) {
        const auto w = static_cast<std::size_t>(graph.successors[v][f.edge++]);
        if (index[w] < 0) {
          index[w] = low[w] = next_index++;
          stack.push_back(static_cast<int>(w));
          on_stack[w] = true;
          call.push_back({static_cast<int>(w), 0});
        } else if (on_stack[w]) {
          low[v] = std::min(low[v], index[w]);
        }
        continue;
      }
      if (low[v] == index[v]) {
        int w = -1;
        do {
          w = stack.back();
          stack.pop_back();
          on_stack[static_cast<std::size_t>(w)] = false;
          component[static_cast<std::size_t>(w)] = count;
        } while (w != f.v);
        ++count;
      }
      call.pop_back();
      if (!call.empty()) {
        const auto parent = static_cast<std::size_t>(call.back().v);
        low[parent] = std::min(low[parent], low[v]);
      }
    }
  }
  return static_cast<std::size_t>(count);
}

int nearest_point(const RoadGraph& graph, double x, double y, double* distance) {
  int best = -1;
  double best_d = std::numeric_limits<double>::infinity();
  for (const GraphPoint& p : graph.points) {
    const double d = std::hypot(p.x - x, p.y - y);
    if (d < best_d) {
      best_d = d;
      best = p.id;
    }
  }
  if (distance != nullptr) *distance = best_d;
  return best;
}

double distance_to_graph(const RoadGraph& graph, double x, double y) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < graph.points.size(); ++i) {
    const GraphPoint& a = graph.points[i];
    best = std::min(best, std::hypot(a.x - x, a.y - y));
    for (const int j : graph.successors[i]) {
      const GraphPoint& b = graph.points[static_cast<std::size_t>(j)];
      const double dx = b.x - a.x, dy = b.y - a.y;
      const double len2 = dx * dx + dy * dy;
      if (len2 <= 0.0) continue;
      const double t = std::clamp(((x - a.x) * dx + (y - a.y) * dy) / len2, 0.0, 1.0);
      best = std::min(best, std::hypot(a.x + t * dx - x, a.y + t * dy - y));
    }
  }
  return best;
}

}  // namespace fleet::map
