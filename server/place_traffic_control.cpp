#include "server/place_traffic_control.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "model/names.hpp"
#include "robot/robot_factory.hpp"
#include "traffic/traffic_settings.hpp"

namespace fleet::server {

namespace {

coordination::PlaceTrafficParams params_for(const config::FleetConfig& config) {
  // Plan steps about as long as a move at the slowest fleet's top speed.
  double speed = std::numeric_limits<double>::infinity();
  for (const auto& fleet : config.fleets) speed = std::min(speed, config.top_speed(fleet));
  coordination::PlaceTrafficParams params;
  if (std::isfinite(speed) && speed > 0.0) params.speed = speed;
  params.plan_ahead = static_cast<int>(config.settings.get_int("traffic.plan_ahead"));
  params.plan_period_s = config.settings.get_double("traffic.plan_period_s");
  return params;
}

}  // namespace

PlaceTrafficSite::PlaceTrafficSite(std::shared_ptr<const map::SiteMap> map, const config::FleetConfig& config)
    : PlaceTrafficSite(std::move(map), robot::traffic_configuration_with_drives(config), params_for(config)) {}

PlaceTrafficSite::PlaceTrafficSite(std::shared_ptr<const map::SiteMap> map,
                                   const traffic::TrafficConfiguration& configuration,
                                   const coordination::PlaceTrafficParams& params)
    : site_map(std::move(map)),
      zones(site_map->graph.graph, configuration.resources),
      lanes(traffic::driving_graph(site_map->graph.graph, configuration)),
      traffic(lanes, zones, params),
      robot_types(configuration.robot_vehicle_types) {}

PlaceTrafficControl::PlaceTrafficControl(std::unique_ptr<PlaceTrafficSite> site, std::string map_id,
                                         dds::Participant& participant, SenderGate& gate, Logger log)
    : site_(std::move(site)),
      traffic_(site_->traffic),
      map_id_(std::move(map_id)),
      gate_(gate),
      log_(std::move(log)),
      grants_(participant, log_),
      requests_(participant, gate) {
  log_->info("traffic control on (coordination core): {} places, plan step {:.2f} s", site_->zones.place_count(),
             traffic_.plan_period_s());
}

int PlaceTrafficControl::number_of(const std::string& robot_id) {
  if (const auto it = numbers_.find(robot_id); it != numbers_.end()) return it->second;
  const auto type = site_->robot_types.find(robot_id);
  const int number = traffic_.add_robot(type != site_->robot_types.end() ? type->second : 0);
  numbers_[robot_id] = number;
  names_.push_back(robot_id);
  return number;
}

std::vector<std::string> PlaceTrafficControl::names_of(const std::vector<int>& robots) const {
  std::vector<std::string> names;
  for (const int robot : robots) names.push_back(names_[static_cast<std::size_t>(robot)]);
  return names;
}

bool PlaceTrafficControl::usable(const model::TrafficRequest& request, const dds::SampleInfo& info) {
  if (request.robot_id.empty() || !std::isfinite(request.progress)) {
    gate_.warn(info, "progress",
               fmt::format("traffic request from '{}' ignored: progress {} is not a number", request.robot_id,
                           request.progress));
    return false;
  }
  if (request.map_id != map_id_) {
    // Sent before the robot heard of a map switch: its points number another graph. Until it
    // replans on this map it stands with its body.
    if (other_map_.insert(request.robot_id).second) {
      log_->info("traffic: {} still drives on map '{}'; its requests wait until it replans on '{}'", request.robot_id,
                 request.map_id, map_id_);
    }
    return false;
  }
  other_map_.erase(request.robot_id);
  for (const int point : request.points) {
    if (point < 0 || static_cast<std::size_t>(point) >= site_->zones.point_count()) {
      gate_.warn(info, "point",
                 fmt::format("traffic request from '{}' ignored: graph point {} does not exist ({} points)",
                             request.robot_id, point, site_->zones.point_count()));
      return false;
    }
  }
  return true;
}

void PlaceTrafficControl::handle_requests(double /*now_sim*/, double now_wall) {
  // A new core (start-up, map switch) first learns where every robot stands from their states,
  // so that nobody is let onto the roads into another's body.
  constexpr double kSettleWall = 0.5;
  if (settle_until_wall_ < 0.0) settle_until_wall_ = now_wall + kSettleWall;
  if (now_wall < settle_until_wall_) return;
  requests_.take([&](model::TrafficRequest&& request, const dds::SampleInfo& info) {
    if (!usable(request, info)) return;
    const int id = number_of(request.robot_id);
    waiting_for_area_.erase(request.robot_id);
    if (request.points.empty()) {
      routed_.erase(request.robot_id);
      status_.erase(request.robot_id);
      if (!request.work_area.empty()) {
        work_beside_roads(request, id, now_wall);
        return;
      }
      working_.erase(request.robot_id);
      const auto body = bodies_.find(request.robot_id);
      traffic_.stand(id, body != bodies_.end() ? body->second : geometry::Polygon{});
      return;
    }
    working_.erase(request.robot_id);
    routed_.insert(request.robot_id);
    std::vector<int> stopped_for;
    for (const std::string& other : request.stopped_for) {
      if (const auto known = numbers_.find(other); known != numbers_.end()) stopped_for.push_back(known->second);
    }
    traffic_.stopped_for(id, std::move(stopped_for));
    // A route with a work area starts beside the roads: the area is its way out onto them.
    const geometry::Polygon way_out =
        request.work_area.empty() ? geometry::Polygon{} : traffic::convex_hull(request.work_area);
    traffic_.drive(id, request.version, request.points, request.progress, way_out);
    if (!traffic_.on_roads(id)) {
      const auto body = bodies_.find(request.robot_id);
      if (body != bodies_.end()) traffic_.waiting_body(id, body->second);
    }
  });
}

void PlaceTrafficControl::work_beside_roads(const model::TrafficRequest& request, int id, double now_wall) {
  // The manoeuvre sweeps the area and the body it starts from: it begins once no other robot's
  // visit, begun or planned, nor standing body is in the area it sweeps, and the robot stands with
  // all of it until it drives again, so no plan leads into it meanwhile.
  const geometry::Polygon swept = traffic::convex_hull(request.work_area);
  std::vector<geometry::Vec2> corners = request.work_area;
  const auto body = bodies_.find(request.robot_id);
  if (body != bodies_.end()) corners.insert(corners.end(), body->second.begin(), body->second.end());
  model::TrafficGrant answer;
  answer.robot_id = request.robot_id;
  answer.version = request.version;
  answer.sim_time = request.sim_time;
  if (!working_.contains(request.robot_id)) {
    std::vector<int> blockers = traffic_.robots_in_area(id, swept);
    std::erase_if(blockers, [&](int b) { return partners(names_[static_cast<std::size_t>(b)], request.robot_id); });
    if (!blockers.empty()) {
      traffic_.stand(id, body != bodies_.end() ? body->second : geometry::Polygon{}, swept);
      waiting_for_area_[request.robot_id] = swept;
      answer.status = "AREA_WAITING";
      answer.blocked_by = names_of(blockers);
      status_[request.robot_id] = {"AREA_WAITING", 0.0, answer.blocked_by, {}};
      grants_.publish(std::move(answer), now_wall);
      return;
    }
    working_.insert(request.robot_id);
    log_->debug("traffic: {} manoeuvres beside the roads", request.robot_id);
  }
  traffic_.stand(id, traffic::convex_hull(std::move(corners)));
  answer.status = "AREA_CLEAR";
  grants_.publish(std::move(answer), now_wall);
}

void PlaceTrafficControl::set_body(const std::string& robot_id, const geometry::Polygon& body) {
  const auto [known, first] = bodies_.try_emplace(robot_id);
  if (first) grants_.open(robot_id);
  known->second = body;
  // Standing without a route (parked, not let on yet, working beside the roads without an area,
  // waiting to begin a manoeuvre): its body holds what it reaches, with the area it waits for.
  if (!routed_.contains(robot_id) && !working_.contains(robot_id)) {
    const auto area = waiting_for_area_.find(robot_id);
    traffic_.stand(number_of(robot_id), body, area != waiting_for_area_.end() ? area->second : geometry::Polygon{});
  }
  // Routed but not let onto the roads yet: it waits beside them where its body is.
  if (routed_.contains(robot_id)) traffic_.waiting_body(number_of(robot_id), body);
}

void PlaceTrafficControl::robot_lost(const std::string& robot_id, const geometry::Polygon& body, double /*now_sim*/) {
  // Lost, it is still in the way: it stands with its body (with its manoeuvre's area, when it was
  // working, as it may go on with it the moment it is heard from again).
  routed_.erase(robot_id);
  status_.erase(robot_id);
  waiting_for_area_.erase(robot_id);
  grants_.forget(robot_id);
  if (working_.contains(robot_id)) return;
  traffic_.stand(number_of(robot_id), body);
  log_->warn("traffic: {} lost; it stands where its body was last seen", robot_id);
}

void PlaceTrafficControl::report_wait_cycle(double now_sim) {
  // The order of visits promises there is none: one found is a fault worth a warning, once.
  const std::vector<int> cycle = traffic_.wait_cycle();
  const std::string members = model::join(names_of(cycle));
  if (!cycle.empty() && members != reported_cycle_) {
    log_->warn("traffic: robots wait for one another in a cycle [{}] at {:.1f} s", members, now_sim);
  }
  reported_cycle_ = members;
}

void PlaceTrafficControl::update(double now_sim, double now_wall) {
  traffic_.update(now_sim);
  report_wait_cycle(now_sim);
  for (const std::string& robot : routed_) {
    const int id = numbers_.at(robot);
    const coordination::PlaceGrant& g = traffic_.grant(id);
    model::TrafficGrant grant;
    grant.robot_id = robot;
    grant.version = g.version;
    grant.granted_index = g.granted_index;
    grant.granted_distance = g.granted_distance;
    grant.blocked_by = names_of(g.waits_for);
    const bool waiting = g.granted_index < 0 || !g.waits_for.empty();
    grant.status = g.arrived ? "ARRIVED" : waiting ? "WAITING" : "MOVING";
    if (!waiting) waiting_since_.erase(robot);
    const double since = waiting ? waiting_since_.try_emplace(robot, now_sim).first->second : now_sim;
    grant.waited_s = now_sim - since;
    if (!g.route.empty()) {
      grant.instruction = "REROUTE";
      grant.route = g.route;
      if (g.version != rerouted_[robot]) {
        rerouted_[robot] = g.version;
        const auto from = site_->zones.position(site_->zones.place_of(g.route.front()));
        const auto to = site_->zones.position(site_->zones.place_of(g.route.back()));
        log_->debug("traffic: {} handed route v{} of {} points from ({:.2f}, {:.2f}) to ({:.2f}, {:.2f})", robot,
                    g.version, g.route.size(), from.x, from.y, to.x, to.y);
      }
    }
    grant.sim_time = now_sim;
    TrafficStatus& status = status_[robot];
    status = {grant.status, grant.waited_s, grant.blocked_by, {}};
    for (const int place : traffic_.places_ahead(id)) status.held.push_back(site_->zones.position(place));
    grants_.publish(std::move(grant), now_wall);
  }
}

}  // namespace fleet::server
