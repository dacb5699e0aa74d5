#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "common/latency_histogram.hpp"
#include "common/logging.hpp"
#include "dds/topics.hpp"
#include "emulation/emulated_robot.hpp"
#include "map/site.hpp"
#include "monitor/collision_monitor.hpp"
#include "monitor/progress_monitor.hpp"

namespace fleet::cli {

struct EmulatedFleetOptions {
  std::uint32_t domain = 0;
  std::string fleet_id;
  std::string map_id;
  /// Robot id and home pose, one per emulated robot.
  std::vector<std::pair<std::string, geometry::Pose2>> robots;
  geometry::Polygon body;  ///< the fleet's footprint polygon, body frame
  emulation::EmulationParams params;
  double state_hz = 20.0;               ///< RobotState and traffic progress per sim second, as agent.state_hz
  double traffic_period_wall_s = 0.05;  ///< the server's traffic cycle in wall seconds (50 ms sim)
};

/// What the emulated fleet saw on the wire and on the floor.
struct EmulatedFleetFigures {
  std::int64_t samples_out = 0;  ///< RobotState, TrafficRequest or TrafficProgress, OrderReport and RobotPath written
  std::int64_t samples_in = 0;   ///< TrafficGrant, Order and NeighbourView samples taken for these robots
  LatencyHistogram::Figures grant_latency;  ///< wall seconds from a new route to its first grant
  std::int64_t routes_sent = 0;
  std::int64_t routes_answered_late = 0;  ///< first grant later than two traffic cycles (wall)
  std::int64_t routes_unanswered = 0;     ///< still waiting for a first grant at the end
  std::int64_t orders_done = 0;
  std::int64_t orders_rejected = 0;
  std::size_t collisions = 0;
  std::size_t deadlocks = 0;
  double max_wait_s = 0.0;
};

/// `fleetctl load`'s robots: N emulation::EmulatedRobot on one DDS participant, each speaking to
/// the server as an agent does: RobotState at agent.state_hz, a TrafficRequest for every new
/// route and its progress, the order reports (ACCEPTED, the phases, DONE) and RobotPath. A load
/// generator: the robots have no sensors and exact poses, which also feed a collision and a
/// deadlock watch over the whole fleet.
class EmulatedFleet {
 public:
  EmulatedFleet(EmulatedFleetOptions options, std::shared_ptr<const map::RoadGraph> graph, Logger log);

  /// Takes what arrived, steps every robot to sim time `now_sim`, publishes what is due.
  void run_until(double now_sim);
  EmulatedFleetFigures figures() const;
  /// The grant latency from now on only (the start-up burst left out).
  void restart_latency() { grant_latency_ = {}; }

 private:
  struct Link {
    std::int64_t order_id = 0;  ///< the order being run, 0 when none
    std::uint32_t update_id = 0;
    std::string phase;
    std::map<std::int64_t, std::uint32_t> seen_updates;
    std::vector<model::OrderReport> finished;  ///< the last final reports, repeated when asked again
    std::uint64_t sent_version = 0;
    bool sent_off_road = false;
    double route_sent_wall = -1.0;    ///< unix time the route not yet granted went out, -1 when granted
    std::vector<int> sent_points;     ///< the route's points as last sent in a TrafficRequest
    double request_sent_wall = -1e9;  ///< unix time of the last TrafficRequest (progress goes between)
    std::size_t path_size = 0;
  };

  void take_orders(double now_sim);
  void take_grants();
  void take_pallets();
  void step_all(double now_sim);
  void publish(std::size_t i, double now_sim);
  void report(std::size_t i, const std::string& status, double now_sim, int pallet_id = -1,
              const geometry::Pose2& pallet_pose = {}, const std::string& reason = "");
  void watch(double now_sim);

  EmulatedFleetOptions options_;
  Logger log_;
  emulation::EmulatedRoutes routes_;
  std::vector<emulation::EmulatedRobot> robots_;
  std::vector<Link> links_;
  std::unordered_map<std::string, std::size_t> index_;
  std::map<std::string, int> load_at_;  ///< loading area -> the pallet standing there
  double sim_ = -1.0;                   ///< the robots' sim time
  double next_publish_sim_ = 0.0;
  double next_watch_sim_ = 0.0;
  EmulatedFleetFigures figures_;
  LatencyHistogram grant_latency_;
  monitor::CollisionMonitor collisions_;
  monitor::ProgressMonitor progress_;

  dds::Participant participant_;
  dds::Writer<model::RobotState> state_writer_;
  dds::Writer<model::OrderReport> report_writer_;
  dds::Writer<model::RobotPath> path_writer_;
  dds::Writer<model::TrafficRequest> traffic_writer_;
  dds::Writer<model::TrafficProgress> progress_writer_;
  dds::Reader<model::TrafficGrant> grant_reader_;
  dds::Reader<model::OrderAssignment> order_reader_;
  dds::Reader<model::PalletTruth> pallet_reader_;
  /// Each robot's NeighbourView, in its partition as an agent's; taken and counted, not used (an
  /// emulated robot has no safety stop).
  std::vector<std::unique_ptr<dds::Reader<model::NeighbourView>>> neighbour_readers_;
};

}  // namespace fleet::cli
