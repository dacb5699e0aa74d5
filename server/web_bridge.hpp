#pragma once

#include <future>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "geometry/polygon.hpp"
#include "map/site_map.hpp"
#include "model/messages.hpp"
#include "orders/order.hpp"
#include "orders/order_request_check.hpp"

namespace fleet::server {

/// A robot as the web view shows it.
struct RobotView {
  model::RobotState state;               ///< what the robot reports: estimated pose, covariance, task
  std::optional<model::SimTruth> truth;  ///< simulation only: its true pose
  std::vector<geometry::Vec2> path;      ///< its planned path
  geometry::Footprint footprint;
  std::string health;  ///< "alive", "stale" (late), "lost"
  double age_s = 0.0;  ///< sim seconds since its last RobotState
  /// Traffic (when on): MOVING, WAITING or ARRIVED, whom it waits for, and where the places it
  /// holds on the road graph are. Empty status: not on the roads.
  std::string traffic;
  std::vector<std::string> waiting_for;
  std::vector<geometry::Vec2> reserved;
};

/// What the server loop publishes for the web view, at up to 20 Hz.
struct LiveSnapshot {
  /// The map the robots drive on now, and its roads (switched at runtime by the map command).
  std::string map;
  std::shared_ptr<const map::SiteMap> site_map;
  /// The names orders are checked against on that map (traffic::order_request_names).
  std::shared_ptr<const orders::KnownNames> known_names;
  double sim_time = 0.0;
  double time_scale = 1.0;
  std::vector<RobotView> robots;
  std::vector<model::OrderInfo> orders;  ///< open orders and the most recent ended ones
  std::map<std::string, bool> obstacle_enabled;
  std::map<std::string, bool> pallet_at;  ///< loading area -> holds a pallet
  bool auto_orders = false;
  long orders_done = 0;
  long orders_failed = 0;
  double orders_per_hour = 0.0;   ///< done orders per sim hour since the server started
  double order_time_p95_s = 0.0;  ///< sim seconds from creation to DONE, p95
  std::string server_id;          ///< the server whose view this is
  /// A standby's view: what it mirrors, read-only; `active_server` is the one it stands by for.
  bool standby = false;
  std::string active_server;
};

/// Puts `orders` into `snapshot` as both servers' views show them: every open order and the 50
/// most recent ended ones, the counts of DONE and FAILED orders, and the p95 order time (the same
/// p95 as `fleetctl stats`, so the page and the CLI agree).
void fill_orders(const std::map<std::int64_t, orders::Order>& orders, LiveSnapshot& snapshot);

/// A request from the web side for the server loop to carry out.
using WebRequest = std::variant<model::OrderRequest, model::Command>;

/// The only meeting point of the web server's threads and the single-threaded server loop: the
/// loop publishes snapshots and drains requests; web threads read snapshots and submit requests,
/// waiting on a future for the reply. Nothing else is shared.
class WebBridge {
 public:
  void publish(LiveSnapshot snapshot) {
    std::lock_guard lock(mutex_);
    snapshot_ = std::move(snapshot);
    ++version_;
  }

  /// The latest snapshot and its version (increases with every publish).
  std::pair<LiveSnapshot, std::uint64_t> latest() const {
    std::lock_guard lock(mutex_);
    return {snapshot_, version_};
  }
  /// The names orders are checked against on the latest snapshot's map, without copying the rest.
  std::shared_ptr<const orders::KnownNames> known_names() const {
    std::lock_guard lock(mutex_);
    return snapshot_.known_names;
  }

  std::future<model::RequestReply> submit(WebRequest request) {
    std::lock_guard lock(mutex_);
    pending_.push_back({std::move(request), {}});
    return pending_.back().reply.get_future();
  }

  struct Pending {
    WebRequest request;
    std::promise<model::RequestReply> reply;
  };

  std::vector<Pending> drain() {
    std::lock_guard lock(mutex_);
    std::vector<Pending> out;
    out.swap(pending_);
    return out;
  }

 private:
  mutable std::mutex mutex_;
  LiveSnapshot snapshot_;
  std::uint64_t version_ = 0;
  std::vector<Pending> pending_;
};

}  // namespace fleet::server
