#pragma once
// What the server does when robots are lost, come back, restart or do not acknowledge an order:
// it asks orders::order_recovery for the decision and carries it out on the book, the site's
// loads, traffic and the wire.

#include <cstdint>
#include <memory>
#include <string>

#include "common/clock.hpp"
#include "common/logging.hpp"
#include "config/fleet_config.hpp"
#include "dds/topics.hpp"
#include "orders/order_book.hpp"
#include "orders/order_recovery.hpp"
#include "orders/recovery_watch.hpp"
#include "orders/robot_roster.hpp"
#include "server/order_wire.hpp"
#include "server/robot_body_memory.hpp"
#include "server/site_keeper.hpp"
#include "server/traffic_service.hpp"

namespace fleet::server {

/// The parts of the server recovery acts on; every one must outlive it. `traffic` is null while
/// traffic control is off, and replaced on a map switch.
struct RecoveryParts {
  const config::FleetConfig& config;
  const SimClock& clock;
  Logger log;
  orders::OrderBook& book;
  orders::RobotRoster& robots;
  orders::RecoveryWatch& watch;
  SiteKeeper& site_keeper;
  OrderWire& wire;
  RobotBodyMemory& body_memory;
  const std::unique_ptr<TrafficService>& traffic;
};

class RobotRecovery {
 public:
  explicit RobotRecovery(RecoveryParts parts) : p_(std::move(parts)) {}

  /// `robot` is lost (`why`): its body stays in traffic's way, and its open order waits for it
  /// (server.lost_with_pallet_wait_s) when it carries the load, else goes back to the queue.
  void robot_lost(orders::RobotEntry& robot, const std::string& why);
  /// A lost robot answers again: the orders that waited for it resume when it still carries
  /// their pallet, and fail when it does not (it was restarted).
  void robot_back(const model::RobotState& state);
  /// Hands the order back to the robot that reported it with its pallet lifted
  /// (orders::ReportVerdict::kHandBack). False when the book refuses: the report is then stale.
  bool hand_back(const orders::Order& order, const model::OrderReport& report);
  /// After a restart (before any robot is heard): the robots stored as standing somewhere keep
  /// their bodies there in traffic control until they report.
  void hold_unheard_robots();
  /// Every loop: robots silent for server.robot_lost_after_s are lost, orders that waited too long
  /// for theirs give up, restored orders whose robot never showed up count it lost (after a grace
  /// from `started_wall`), and where the robots stand is remembered.
  void check(double now_wall, double started_wall);
  /// Re-sends assignments not acknowledged in time, up to server.order_resend_limit, then re-queues.
  void check_acknowledgements();

 private:
  /// Back to the queue, taken from `robot_id` (told to drop it), with `reason` in its history.
  void requeue_taken_from(std::int64_t order_id, const std::string& robot_id, const std::string& reason);
  void fail_with_pallet(std::int64_t order_id, const std::string& reason);
  /// The lost robot of a waiting order came back restarted, or did not come back in time: the
  /// order is re-queued when the robot had not lifted the pallet (pallet truth), else failed and
  /// the pallet put back.
  void give_up_on_lost_robot(std::int64_t order_id, orders::Recovery decision, const std::string& why,
                             const std::string& failure);
  void check_orders_waiting_for_lost_robots(double now_wall);
  /// Counts robots of restored orders lost when they have not reported since the restart.
  void check_restored_orders();

  RecoveryParts p_;
};

}  // namespace fleet::server
