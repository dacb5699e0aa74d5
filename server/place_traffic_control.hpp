#pragma once

#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "common/logging.hpp"
#include "config/fleet_config.hpp"
#include "coordination/place_traffic.hpp"
#include "dds/topics.hpp"
#include "map/site_map.hpp"
#include "server/grant_publisher.hpp"
#include "server/sender_gate.hpp"
#include "server/traffic_intake.hpp"
#include "server/traffic_service.hpp"
#include "traffic/conflict_zones.hpp"
#include "traffic/traffic_manager.hpp"

namespace fleet::server {

/// What the coordination core needs of a site, derived once per map (off the server loop on a
/// map switch, like the traffic manager): the conflict zones of the fleets' vehicle types and the
/// core on them.
struct PlaceTrafficSite {
  PlaceTrafficSite(std::shared_ptr<const map::SiteMap> site_map, const config::FleetConfig& config);
  PlaceTrafficSite(std::shared_ptr<const map::SiteMap> site_map, const traffic::TrafficConfiguration& configuration,
                   const coordination::PlaceTrafficParams& params);

  std::shared_ptr<const map::SiteMap> site_map;  ///< keeps the road graph the zones refer to
  traffic::ConflictZones zones;
  map::RoadGraph lanes;  ///< the graph the robots drive: one way along corridors on cycles with traffic.one_way
  coordination::PlaceTraffic traffic;
  std::map<std::string, int> robot_types;  ///< robot id -> vehicle type (the zones' numbering)
};

/// The server side of `traffic.core: places`: the agents' TrafficRequests into
/// coordination::PlaceTraffic, its grants out as TrafficGrant (REROUTE with the route when the
/// plan moves a robot off its own). Robots without a route stand with their bodies; a robot
/// manoeuvring beside the roads (a work area) is answered AREA_CLEAR once no other robot's visit
/// or body is in the area, and stands with the area until it drives again.
class PlaceTrafficControl : public TrafficService {
 public:
  PlaceTrafficControl(std::unique_ptr<PlaceTrafficSite> site, std::string map_id, dds::Participant& participant,
                      SenderGate& gate, Logger log);

  void handle_requests(double now_sim, double now_wall) override;
  void update(double now_sim, double now_wall) override;
  void robot_lost(const std::string& robot_id, const geometry::Polygon& body, double now_sim) override;
  void set_body(const std::string& robot_id, const geometry::Polygon& body) override;
  const std::map<std::string, TrafficStatus>& status() const override { return status_; }

 private:
  int number_of(const std::string& robot_id);
  /// Whether the request is one to act on; logs why not.
  bool usable(const model::TrafficRequest& request, const dds::SampleInfo& info);
  void work_beside_roads(const model::TrafficRequest& request, int id, double now_wall);
  std::vector<std::string> names_of(const std::vector<int>& robots) const;
  void report_wait_cycle(double now_sim);

  std::unique_ptr<PlaceTrafficSite> site_;
  coordination::PlaceTraffic& traffic_;
  std::string map_id_;
  SenderGate& gate_;
  Logger log_;
  std::map<std::string, int> numbers_;
  std::vector<std::string> names_;
  std::map<std::string, geometry::Polygon> bodies_;  ///< last known footprint of each robot
  std::set<std::string> routed_;                     ///< robots whose last request had a route
  std::set<std::string> working_;                    ///< robots holding the area of a manoeuvre
  /// Robots answered AREA_WAITING, with the area they wait to sweep: held with their body
  /// whenever it is reported again, until their next request.
  std::map<std::string, geometry::Polygon> waiting_for_area_;
  std::set<std::string> other_map_;
  std::map<std::string, double> waiting_since_;    ///< sim s each robot began waiting
  std::map<std::string, std::uint64_t> rerouted_;  ///< the last route version handed to each robot
  std::map<std::string, TrafficStatus> status_;
  std::string reported_cycle_;
  double settle_until_wall_ = -1.0;
  GrantPublisher grants_;
  TrafficIntake requests_;
};

}  // namespace fleet::server
