#pragma once

#include <map>
#include <string>
#include <vector>

#include "geometry/polygon.hpp"

namespace fleet::server {

/// What the web view shows of a robot's traffic state.
struct TrafficStatus {
  std::string status;  ///< MOVING, WAITING, ARRIVED, STANDING, AREA_WAITING
  double waited_s = 0.0;
  std::vector<std::string> blocked_by;
  std::vector<geometry::Vec2> held;  ///< where the places the robot holds (or is planned through) are
};

/// The server side of traffic control, as the server loop drives it: the agents' TrafficRequests
/// in, TrafficGrants out. `traffic.core` picks the core behind it: TrafficControl (the traffic
/// manager) or PlaceTrafficControl (the coordination core's planner and order of visits).
class TrafficService {
 public:
  virtual ~TrafficService() = default;
  /// Reads the agents' routes and progress (call every loop).
  virtual void handle_requests(double now_sim, double now_wall) = 0;
  /// One cycle and the grants that changed (call at the control rate).
  virtual void update(double now_sim, double now_wall) = 0;
  /// The robot is lost: where its body was last seen stays blocked.
  virtual void robot_lost(const std::string& robot_id, const geometry::Polygon& body, double now_sim) = 0;
  /// Where a robot that answers stands now (its footprint at its reported pose).
  virtual void set_body(const std::string& robot_id, const geometry::Polygon& body) = 0;
  virtual const std::map<std::string, TrafficStatus>& status() const = 0;

  /// Robots that work together at one place, each to its partner (a loader and the transporter
  /// behind it, orders::LoaderDesk::partners): neither's body keeps the other's manoeuvre beside
  /// the roads from starting.
  virtual void set_partners(std::map<std::string, std::string> partners) { partners_ = std::move(partners); }

 protected:
  bool partners(const std::string& a, const std::string& b) const {
    const auto ab = partners_.find(a);
    const auto ba = partners_.find(b);
    return (ab != partners_.end() && ab->second == b) || (ba != partners_.end() && ba->second == a);
  }

 private:
  std::map<std::string, std::string> partners_;
};

}  // namespace fleet::server
