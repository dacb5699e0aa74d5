#include "vda5050/vehicle_drive.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>

namespace fleet::vda5050 {

namespace {

constexpr double kDefaultDeviation = 0.05;  // metres, a node without allowedDeviationXy
constexpr double kPassedSlack = 0.02;       // metres short of a node that count as passing it

geometry::Vec2 position_of(const map::RoadGraph& graph, int point) {
  const map::GraphPoint& p = graph.points[static_cast<std::size_t>(point)];
  return {p.x, p.y};
}

std::optional<int> point_id(const std::string& node_id, const map::RoadGraph& graph) {
  if (node_id.size() < 2 || node_id[0] != 'p') return std::nullopt;
  if (!std::all_of(node_id.begin() + 1, node_id.end(), [](char c) { return c >= '0' && c <= '9'; })) {
    return std::nullopt;
  }
  if (node_id.size() > 10) return std::nullopt;
  const long id = std::stol(node_id.substr(1));
  if (id >= static_cast<long>(graph.points.size())) return std::nullopt;
  return static_cast<int>(id);
}

std::string metres(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f", value);
  return text;
}

}  // namespace

std::optional<NodeOnSite> locate_node(const ReceivedNode& node, const map::Site& site, const map::RoadGraph& graph,
                                      std::string* why) {
  NodeOnSite out{node.sequence, node.released, -1, "", {}};
  const double tolerance = node.allowed_deviation > 0.0 ? node.allowed_deviation : kDefaultDeviation;
  const geometry::Vec2 given{node.x, node.y};
  if (const auto point = point_id(node.id, graph)) {
    const geometry::Vec2 at = position_of(graph, *point);
    if (node.has_position && geometry::distance(at, given) > tolerance) {
      *why = "node '" + node.id + "' at (" + metres(node.x) + ", " + metres(node.y) + ") lies " +
             metres(geometry::distance(at, given)) + " m from graph point " + std::to_string(*point);
      return std::nullopt;
    }
    out.point = *point;
    out.pose = {at.x, at.y, node.theta.value_or(0.0)};
    return out;
  }
  if (const map::LoadingArea* area = site.find_area(node.id)) {
    out.place = area->id;
    out.pose = area->pose;
    return out;
  }
  if (const map::Home* home = site.find_home(node.id)) {
    out.place = home->id;
    out.pose = home->pose;
    return out;
  }
  if (!node.has_position) {
    *why = "node '" + node.id + "' has no position and names no graph point (p<id>), loading area or home of site '" +
           site.name + "'";
    return std::nullopt;
  }
  double best = tolerance;
  for (const map::GraphPoint& p : graph.points) {
    const double d = geometry::distance({p.x, p.y}, given);
    if (d <= best) {
      best = d;
      out.point = p.id;
      out.pose = {p.x, p.y, node.theta.value_or(0.0)};
    }
  }
  if (out.point >= 0) return out;
  const auto consider_place = [&](const std::string& id, const geometry::Pose2& pose) {
    const double d = geometry::distance(pose.position(), given);
    if (d <= best) {
      best = d;
      out.place = id;
      out.pose = pose;
    }
  };
  for (const map::LoadingArea& a : site.loading_areas) consider_place(a.id, a.pose);
  for (const map::Home& h : site.homes) consider_place(h.id, h.pose);
  if (!out.place.empty()) return out;
  if (site.bounds.contains(given)) {
    // A point of the master's own path off the roads (onto a road, into a place): the robot
    // passes it on its own way there.
    out.pose = {node.x, node.y, node.theta.value_or(0.0)};
    return out;
  }
  *why = "node '" + node.id + "' at (" + metres(node.x) + ", " + metres(node.y) + ") lies outside site '" + site.name +
         "'";
  return std::nullopt;
}

std::variant<VehicleJob, VehicleError> job_of(const std::string& order_id, const std::vector<ReceivedNode>& nodes,
                                              const std::vector<ReceivedEdge>& edges, const map::Site& site,
                                              const map::RoadGraph& graph, bool transports, bool carrying,
                                              const nlohmann::json& message) {
  VehicleJob job;
  job.order.order_id = order_id;
  job.order.kind = orders::OrderKind::kMove;
  for (const ReceivedEdge& e : edges) {
    if (!e.actions.empty()) {
      const ReceivedAction& a = e.actions.front();
      return order_error("orderError", "edge '" + e.id + "': Fleet's robots perform actions only at nodes", message,
                         {{"actionId", a.id}, {"actionType", a.type}});
    }
  }
  const ReceivedAction* pick = nullptr;
  const ReceivedAction* drop = nullptr;
  for (const ReceivedNode& node : nodes) {
    std::string why;
    const auto on_site = locate_node(node, site, graph, &why);
    if (!on_site) return order_error("noRouteError", why, message, {{"nodeId", node.id}});
    job.nodes.push_back(*on_site);
    for (const ReceivedAction& a : node.actions) {
      const std::vector<std::pair<std::string, std::string>> refs{{"actionId", a.id}, {"actionType", a.type}};
      if (a.type != "pick" && a.type != "drop") {
        return order_error("orderError", "action type '" + a.type + "' is not one Fleet's robots perform (pick, drop)",
                           message, refs);
      }
      if (!transports) return order_error("orderError", "this vehicle does not carry loads", message, refs);
      const map::LoadingArea* area = site.find_area(on_site->place);
      if (area == nullptr) {
        return order_error("orderError", a.type + " at node '" + node.id + "', which is no loading area", message,
                           refs);
      }
      if (a.type == "pick") {
        if (pick != nullptr) return order_error("orderError", "a second pick in one order", message, refs);
        pick = &a;
        job.pick_action = a.id;
        job.pick_node = node.sequence;
        job.order.pick_area_id = area->id;
        job.order.pick_area = area->pose;
      } else {
        if ((pick == nullptr && !carrying) || drop != nullptr) {
          return order_error("orderError", "a drop without a pick before it", message, refs);
        }
        drop = &a;
        job.drop_action = a.id;
        job.goal_node = node.sequence;
        job.order.drop_area_id = area->id;
        job.order.drop_area = area->pose;
        job.order.kind = orders::OrderKind::kTransport;
      }
    }
    const bool after_drop = drop != nullptr && job.goal_node != node.sequence;
    const bool after_lone_pick = pick != nullptr && drop == nullptr && job.pick_node != node.sequence;
    if (after_drop || after_lone_pick) {
      return order_error("orderError",
                         "node '" + node.id + "' after the " + (after_drop ? "drop" : "pick") +
                             ": a transport ends at its drop, a pick without a drop at the pick",
                         message, {{"nodeId", node.id}});
    }
  }
  if (pick != nullptr && drop == nullptr) {
    // The pick alone: the robot stands with the load until an order with the drop comes.
    job.order.kind = orders::OrderKind::kTransport;
    job.goal_node = job.pick_node;
  }
  if (job.order.kind == orders::OrderKind::kMove && !job.nodes.empty()) {
    const NodeOnSite& goal = job.nodes.back();
    job.goal_node = goal.sequence;
    job.order.drop_area_id = goal.place.empty() ? nodes.back().id : goal.place;
    job.order.drop_area = goal.pose;
    if (goal.place.empty() && !nodes.back().theta && job.nodes.size() >= 2) {
      const geometry::Vec2 along = goal.pose.position() - job.nodes[job.nodes.size() - 2].pose.position();
      job.order.drop_area.yaw = std::atan2(along.y, along.x);
    }
  }
  return job;
}

std::vector<int> shortest_road(const map::RoadGraph& graph, int from, int to) {
  const std::size_t n = graph.points.size();
  std::vector<double> cost(n, std::numeric_limits<double>::infinity());
  std::vector<int> previous(n, -1);
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
  cost[static_cast<std::size_t>(from)] = 0.0;
  open.push({0.0, from});
  while (!open.empty()) {
    const auto [c, p] = open.top();
    open.pop();
    if (p == to) break;
    if (c > cost[static_cast<std::size_t>(p)]) continue;
    for (int q : graph.successors[static_cast<std::size_t>(p)]) {
      const double next = c + geometry::distance(position_of(graph, p), position_of(graph, q));
      if (next < cost[static_cast<std::size_t>(q)]) {
        cost[static_cast<std::size_t>(q)] = next;
        previous[static_cast<std::size_t>(q)] = p;
        open.push({next, q});
      }
    }
  }
  if (std::isinf(cost[static_cast<std::size_t>(to)])) return {};
  std::vector<int> way{to};
  while (way.back() != from) way.push_back(previous[static_cast<std::size_t>(way.back())]);
  std::reverse(way.begin(), way.end());
  return way;
}

VehicleDrive::Led VehicleDrive::lead(const robot::TrafficRoute& route, const map::RoadGraph& graph) const {
  Led led;
  led.own_version = route.version;
  led.route = {route.points.front()};
  const auto extend = [&](int to) {
    const std::vector<int> way = shortest_road(graph, led.route.back(), to);
    if (way.empty()) return false;
    led.route.insert(led.route.end(), way.begin() + 1, way.end());
    return true;
  };
  std::vector<std::pair<std::uint32_t, std::size_t>> node_index;
  for (const NodeOnSite& node : leg_) {
    if (node.point < 0) continue;
    if (!extend(node.point)) break;
    node_index.emplace_back(node.sequence, led.route.size() - 1);
  }
  if (!extend(route.points.back())) {
    // No way on to where the robot's plan leaves the road: it drives its own plan.
    led.route = route.points;
    node_index.clear();
  }
  led.along.assign(led.route.size(), 0.0);
  for (std::size_t i = 1; i < led.route.size(); ++i) {
    led.along[i] =
        led.along[i - 1] + geometry::distance(position_of(graph, led.route[i - 1]), position_of(graph, led.route[i]));
  }
  for (const auto& [sequence, index] : node_index) led.node_at.emplace_back(sequence, led.along[index]);
  return led;
}

std::optional<robot::TrafficPermit> VehicleDrive::permit(const robot::TrafficRoute& route,
                                                         const map::RoadGraph& graph) {
  if (route.points.empty() || leg_.empty()) return std::nullopt;
  const auto handed_version = [](std::uint64_t own) { return own + (own % 2 == 0 ? 1 : 2); };
  const bool ours = led_ && (route.version == led_->own_version || route.version == handed_version(led_->own_version));
  const bool all_known = led_ && std::all_of(leg_.begin(), leg_.end(), [&](const NodeOnSite& n) {
                           return n.point < 0 || std::any_of(led_->node_at.begin(), led_->node_at.end(),
                                                             [&](const auto& at) { return at.first == n.sequence; });
                         });
  if (!ours || !all_known) led_ = lead(route, graph);
  robot::TrafficPermit permit;
  permit.version = route.version;
  if (route.points != led_->route) {
    permit.version = handed_version(route.version);
    permit.route = led_->route;
  }
  // How far the base reaches: its last node in the leg; the whole route once the leg's end is
  // released (the robot then leaves the road for the place, as it would under traffic).
  std::optional<double> granted;
  bool whole = true;
  for (const NodeOnSite& node : leg_) {
    if (!node.released) {
      whole = false;
      break;
    }
    for (const auto& [sequence, at] : led_->node_at) {
      if (sequence == node.sequence) granted = at;
    }
  }
  if (whole) {
    permit.granted_index = static_cast<int>(led_->route.size()) - 1;
    permit.granted_distance = led_->along.back();
    return permit;
  }
  if (!granted) return std::nullopt;
  permit.granted_distance = *granted;
  permit.granted_index = 0;
  for (std::size_t i = 1; i < led_->along.size() && led_->along[i] <= *granted + 1e-9; ++i) {
    permit.granted_index = static_cast<int>(i);
  }
  return permit;
}

std::vector<std::uint32_t> VehicleDrive::passed(const robot::TrafficRoute& route) const {
  std::vector<std::uint32_t> out;
  if (!led_ || route.points != led_->route) return out;
  for (const auto& [sequence, at] : led_->node_at) {
    if (at <= route.progress + kPassedSlack) out.push_back(sequence);
  }
  return out;
}

}  // namespace fleet::vda5050
