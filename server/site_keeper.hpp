#pragma once
// The site's state beyond its orders (orders::SiteState: the loads, who parks where, which
// obstacles are on), kept whole: stored after every change, before anyone hears of it, published
// for a standby to mirror (SiteState), and told to the robots (PalletTruth for the simulation,
// StaticObstacleState). The orders' reports move loads through it.

#include <string>

#include "common/logging.hpp"
#include "config/fleet_config.hpp"
#include "dds/topics.hpp"
#include "map/site.hpp"
#include "orders/order.hpp"
#include "orders/site_state.hpp"
#include "server/order_store.hpp"

namespace fleet::server {

class SiteKeeper {
 public:
  /// `store` must outlive it.
  SiteKeeper(dds::Participant& participant, OrderStore& store, Logger log);

  /// The state as `site`'s file starts it (its pallets, the robots' homes, its obstacles),
  /// overridden by what the database holds; stored and published.
  void restore(const map::Site& site, const config::FleetConfig& config);

  const orders::SiteState& state() const { return state_; }

  /// Stores the state whole and publishes it for a standby.
  void save();
  /// The obstacles of `site` as its file sets them at the start (not stored: call save()).
  void reset_obstacles(const map::Site& site);
  /// Switches `obstacle` of map `map_id` on or off: stored, then published.
  void switch_obstacle(const map::StaticObstacle& obstacle, const std::string& map_id, bool on);
  /// Publishes every obstacle of `site` as it stands (latched, for robots that start later).
  void publish_obstacles(const map::Site& site);
  /// The map a switch moved every robot onto: its obstacles as its file starts them; stored.
  void switched_to(const map::Site& site);
  /// `robot_id` goes home to `place` from now on; stored.
  void park(const std::string& robot_id, const std::string& place);

  /// A transport's robot put its pallet down at the drop area (DONE), where the simulation says.
  void put_down(const orders::Order& order, const model::OrderReport& report, const map::Site& site);
  /// A transport's robot lifted the pallet at the pick area.
  void lifted(const orders::Order& order, const model::OrderReport& report);
  /// A transport's robot found the pick area empty: free unless a pallet stands there by the record.
  void found_empty(const orders::Order& order, const model::OrderReport& report);
  /// Simulation: the pallet a restarted robot carried goes back on `preferred_area`, or the first
  /// free area, as an operator would take it off the crashed robot.
  void return_pallet_of(const std::string& robot_id, const std::string& preferred_area);
  /// The pallet of a transport adopted from a server that stepped down, recorded where that
  /// order took it (lifted, or put down at its drop area).
  void follow(const orders::Order& adopted, const map::Site& site);

 private:
  /// Records a load's new truth: in the ledger, stored, and published as PalletTruth.
  void record(orders::Load load);

  OrderStore& store_;
  Logger log_;
  orders::SiteState state_;
  dds::Writer<model::PalletTruth> pallet_writer_;
  dds::Writer<model::StaticObstacleState> obstacle_writer_;
  dds::Writer<model::SiteStateDocument> site_state_writer_;
};

}  // namespace fleet::server
