#include "server/site_keeper.hpp"

#include <algorithm>
#include <vector>

#include "dds/qos.hpp"
#include "orders/order_recovery.hpp"

namespace fleet::server {

namespace {
constexpr const char* kPallet = "pallet";  // the only kind of load this simulation moves

model::PalletTruth pallet_of(const orders::Load& load) {
  return {load.id, load.pose, load.place, load.carried_by};
}
}  // namespace

SiteKeeper::SiteKeeper(dds::Participant& participant, OrderStore& store, Logger log)
    : store_(store),
      log_(std::move(log)),
      pallet_writer_(participant, dds::qos::latched_state()),
      obstacle_writer_(participant, dds::qos::latched_state()),
      site_state_writer_(participant, dds::qos::latched_state()) {}

void SiteKeeper::restore(const map::Site& site, const config::FleetConfig& config) {
  const orders::SiteNames names = orders::site_names_of(site, config);
  state_ = orders::SiteState{site.name, orders::AreaLedger(names.places), {}, {}};
  for (const auto& [fleet, robot] : config.all_robots()) state_.parked_at[robot->id] = robot->home;
  reset_obstacles(site);
  const std::optional<std::string> stored = store_.load_site_state();
  if (!stored) {
    // A fresh database: the pallets of the site file, standing exactly on their areas.
    int next_id = 1;
    for (const auto& area : site.loading_areas) {
      if (!area.pallet_at_start) continue;
      orders::Load load{next_id++, kPallet, area.pose, area.id, ""};
      pallet_writer_.write(pallet_of(load));
      state_.ledger.record(std::move(load));
    }
    save();  // once for all of them
    return;
  }
  orders::RestoredSiteState restored = orders::site_state_from_json(*stored, names, store_.path());
  for (const auto& dropped : restored.dropped) log_->warn("site state in {}: {}", store_.path(), dropped);
  state_.ledger = std::move(restored.state.ledger);
  for (auto& [robot, place] : restored.state.parked_at) state_.parked_at[robot] = std::move(place);
  for (const auto& [id, on] : restored.state.obstacle_enabled) state_.obstacle_enabled[id] = on;
  for (const auto& [id, load] : state_.ledger.loads()) pallet_writer_.write(pallet_of(load));
  save();  // as read against the site now, and published for a standby
  log_->info("restored the site's state from {}: {} pallets, {} obstacles on", store_.path(),
             state_.ledger.loads().size(),
             std::count_if(state_.obstacle_enabled.begin(), state_.obstacle_enabled.end(),
                           [](const auto& entry) { return entry.second; }));
}

void SiteKeeper::save() {
  std::string json = orders::to_json(state_);
  store_.save_site_state(json);
  site_state_writer_.write({state_.map_id, std::move(json)});
}

void SiteKeeper::reset_obstacles(const map::Site& site) {
  state_.obstacle_enabled.clear();
  for (const auto& obstacle : site.static_obstacles) state_.obstacle_enabled[obstacle.id] = obstacle.enabled_at_start;
}

void SiteKeeper::switch_obstacle(const map::StaticObstacle& obstacle, const std::string& map_id, bool on) {
  state_.obstacle_enabled[obstacle.id] = on;
  save();
  obstacle_writer_.write({obstacle.id, map_id, on, obstacle.polygon});
}

void SiteKeeper::publish_obstacles(const map::Site& site) {
  for (const auto& obstacle : site.static_obstacles) {
    obstacle_writer_.write({obstacle.id, site.name, state_.obstacle_enabled[obstacle.id], obstacle.polygon});
  }
}

void SiteKeeper::switched_to(const map::Site& site) {
  reset_obstacles(site);
  state_.map_id = site.name;
  save();
}

void SiteKeeper::park(const std::string& robot_id, const std::string& place) {
  state_.parked_at[robot_id] = place;
  save();
}

void SiteKeeper::record(orders::Load load) {
  const model::PalletTruth pallet = pallet_of(load);
  state_.ledger.record(std::move(load));
  save();
  pallet_writer_.write(pallet);
}

void SiteKeeper::put_down(const orders::Order& order, const model::OrderReport& report, const map::Site& site) {
  // The pallet stands where the robot really put it (simulation truth), so a sloppy drop makes
  // the next pick from that area harder.
  auto placed = state_.ledger.put_down(report.pallet_id, report.pallet_pose, order.drop_area);
  if (!placed) {
    log_->warn("order {} done by {} without naming the pallet it put down; pallet truth unchanged", order.id,
               report.robot_id);
    state_.ledger.record_unnamed_drop(order.drop_area);
    save();
    return;
  }
  const auto* drop = site.find_area(order.drop_area);
  const double error = drop ? geometry::distance(placed->pose.position(), drop->pose.position()) : 0.0;
  record(std::move(*placed));
  log_->info("order {} done by {}: pallet {} placed at {} ({:.3f} m from the area's centre)", order.id, report.robot_id,
             report.pallet_id, order.drop_area, error);
}

void SiteKeeper::found_empty(const orders::Order& order, const model::OrderReport& report) {
  const auto* standing = state_.ledger.found_empty(order.pick_area);
  save();
  if (standing) {
    log_->warn(
        "order {}: {} found loading area {} empty, but pallet {} stands there at ({:.3f}, {:.3f}) "
        "by the record; the area stays occupied",
        order.id, report.robot_id, order.pick_area, standing->id, standing->pose.x, standing->pose.y);
  }
}

void SiteKeeper::lifted(const orders::Order& order, const model::OrderReport& report) {
  auto lifted = state_.ledger.lifted(report.robot_id, report.pallet_id, order.pick_area);
  if (!lifted) return;
  const int load_id = lifted->id;
  record(std::move(*lifted));
  log_->info("pallet {} lifted by {} from {}", load_id, report.robot_id, order.pick_area);
}

void SiteKeeper::return_pallet_of(const std::string& robot_id, const std::string& preferred_area) {
  // A simulated robot restarts at its home with empty forks, so the pallet it carried would be
  // nowhere, and a fleet that loses one pallet per crash soon has no work. Where a real fleet's
  // operator takes the pallet off the crashed robot and puts it back, the simulation puts it on
  // the order's pick area, or the first free one.
  const orders::Load* carried = state_.ledger.carried_by(robot_id);
  if (!carried) return;
  auto back = state_.ledger.returned_from(robot_id, preferred_area);
  if (!back) {
    log_->warn("pallet {} of restarted robot {} has no free loading area to go back to", carried->id, robot_id);
    return;
  }
  log_->info("pallet {} of restarted robot {} put back on {} (simulation: the operator's part)", back->id, robot_id,
             back->place);
  record(std::move(*back));
}

void SiteKeeper::follow(const orders::Order& adopted, const map::Site& site) {
  // The pallet a transport adopted from the other side moved there: this server's record follows,
  // so that no order here goes for a pallet that is gone or onto a place that now holds one.
  if (adopted.kind != orders::OrderKind::kTransport) return;
  const bool done = adopted.status == orders::OrderStatus::kDone;
  if (!done && !(adopted.status == orders::OrderStatus::kActive && orders::restored_robot_carried_load(adopted.phase)))
    return;
  auto lifted = state_.ledger.lifted(adopted.robot_id, -1, adopted.pick_area);
  if (!lifted) return;
  const int load_id = lifted->id;
  record(std::move(*lifted));
  const auto* drop = site.find_area(adopted.drop_area);
  if (!done || drop == nullptr) return;
  if (auto placed = state_.ledger.put_down(load_id, drop->pose, adopted.drop_area)) record(std::move(*placed));
  log_->info("pallet {} recorded at {}: order {} moved it on the server that stepped down", load_id, adopted.drop_area,
             adopted.id);
}

}  // namespace fleet::server
