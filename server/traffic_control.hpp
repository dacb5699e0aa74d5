#pragma once

#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "common/logging.hpp"
#include "dds/topics.hpp"
#include "map/road_graph.hpp"
#include "server/grant_publisher.hpp"
#include "server/sender_gate.hpp"
#include "server/traffic_intake.hpp"
#include "server/traffic_service.hpp"
#include "traffic/traffic_manager.hpp"

namespace fleet::server {

/// The server side of traffic control: agents' TrafficRequests into a
/// traffic::TrafficManager, its grants out as TrafficGrant, one update per cycle.
class TrafficControl : public TrafficService {
 public:
  /// `manager` is built on the road graph of map `map_id` (server::derive_site, off the server
  /// loop on a map switch): requests for another map are ignored.
  TrafficControl(std::unique_ptr<traffic::TrafficManager> manager, std::string map_id, dds::Participant& participant,
                 SenderGate& gate, Logger log);

  /// Reads the agents' routes and progress (call every loop).
  void handle_requests(double now_sim, double now_wall) override;
  /// One manager cycle and the grants that changed (call at the control rate).
  void update(double now_sim, double now_wall) override;
  /// The robot is lost: it keeps the places its body (last footprint) stands on, the rest of
  /// what it held is freed at once.
  void robot_lost(const std::string& robot_id, const geometry::Polygon& body, double now_sim) override;
  /// Where a robot that answers stands now (its footprint at its reported pose). A robot without
  /// a route — parked, or not admitted yet — holds the places its body overlaps. A robot's first
  /// body opens the writer of its grants, so that its reader has matched by the first grant.
  void set_body(const std::string& robot_id, const geometry::Polygon& body) override;
  void set_partners(std::map<std::string, std::string> partners) override;

  const std::map<std::string, TrafficStatus>& status() const override { return status_; }

 private:
  int number_of(const std::string& robot_id);
  /// Holds the places under the robot's body when it has no route (see set_body). True when it
  /// now stands holding places; false when its body is clear of the roads (it is removed).
  bool hold_body(const std::string& robot_id, int id, const geometry::Polygon& body, double now_sim);
  /// Drops the robot's route and holds the places under its body instead (none when its body is
  /// unknown or clear of the roads); true when it holds some. `keep_turn`: a robot still in the
  /// place it turned into off its route (TrafficManager::turn_area) holds that area with its body.
  bool stand_where_it_is(const std::string& robot_id, int id, double now_sim, bool keep_turn = false);
  /// Whether the robot, standing (frozen), is on graph point `point` and holds its place.
  bool stands_at(const std::string& robot_id, int id, int point) const;
  /// A robot off the roads with a work area (model::TrafficRequest::work_area): holds the area
  /// once it is clear and answers AREA_CLEAR, else holds the body and answers AREA_WAITING.
  void work_beside_roads(const model::TrafficRequest& request, int id, double now_sim, double now_wall);
  /// Answers a robot beside the roads that it waits to enter for `blockers` (granted_index -1).
  void wait_to_enter(const model::TrafficRequest& request, std::vector<std::string> blockers, double now_sim,
                     double now_wall);
  /// What traffic holds for a manoeuvre: the hull of the request's work_area and the body the
  /// robot stands with.
  geometry::Polygon area_with_body(const model::TrafficRequest& request) const;
  /// Robots holding places the area touches or standing in it (TrafficManager::holders_in_area).
  std::vector<int> robots_in_area(int id, const geometry::Polygon& area) const;
  /// A standing robot's way out onto the road (its request's work_area) is free: it is held for
  /// it. Otherwise the robot is answered WAITING for those in it.
  bool way_out_clear(const model::TrafficRequest& request, int id, double now_sim, double now_wall);
  /// A wait cycle the manager found no way out of (TrafficEvent kUnresolvedDeadlock, `others` its
  /// members): logged at debug, and once as a warning when it lasts (stuck_cycles_).
  void note_stuck_cycle(const traffic::TrafficEvent& e, const std::string& others, double now_sim);

  std::unique_ptr<traffic::TrafficManager> manager_;
  std::string map_id_;
  std::set<std::string> other_map_;  ///< robots whose last request was for another map (logged once)
  SenderGate& gate_;
  Logger log_;
  std::map<std::string, int> numbers_;  ///< robot id -> the manager's integer id
  std::map<int, std::string> names_;
  std::set<std::string> working_;  ///< robots holding their work area
  std::map<std::string, TrafficStatus> status_;
  /// Wait cycles the manager finds no way out of, by their members: a cycle that lasts is
  /// reported once as a warning, naming each member's route (see update()).
  struct StuckCycle {
    double since = 0.0;      ///< sim s, first seen
    double last_seen = 0.0;  ///< sim s
    bool reported = false;
  };
  std::map<std::string, StuckCycle> stuck_cycles_;
  struct Trim {
    std::uint64_t version = 0;
    int skipped = 0;      ///< route points cut off behind the robot when it entered
    double offset = 0.0;  ///< metres cut off
  };
  std::map<std::string, Trim> trims_;
  std::set<std::string> heard_;                           ///< robots that sent this manager a request
  double settle_until_wall_ = -1.0;                       ///< requests wait until then: robots' bodies are learnt first
  std::map<std::string, geometry::Polygon> bodies_;       ///< last known footprint of each robot
  std::map<std::string, geometry::Polygon> held_bodies_;  ///< the footprint its standing places were found for
  GrantPublisher grants_;
  TrafficIntake requests_;
};

}  // namespace fleet::server
