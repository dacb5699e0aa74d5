#include "server/standby_view.hpp"

#include <algorithm>
#include <vector>

#include "common/errors.hpp"
#include "monitor/robot_health.hpp"
#include "traffic/order_names.hpp"

namespace fleet::server {

namespace {
constexpr double kHzWall = 5.0;
}  // namespace

StandbyView::StandbyView(WebBridge& bridge, Site site)
    : bridge_(bridge),
      site_(std::move(site)),
      // The web API checks requests against them before it hands them on, as on the active server.
      known_names_(
          std::make_shared<const orders::KnownNames>(traffic::order_request_names(*site_.config, *site_.site_map))),
      site_names_(orders::site_names_of(site_.site_map->site, *site_.config)) {}

void StandbyView::order(const orders::Order& order) {
  sim_time_ = std::max(sim_time_, order.updated_sim);
  orders_.insert_or_assign(order.id, order);
}

void StandbyView::site_state(const std::string& json) {
  try {
    const orders::RestoredSiteState read =
        orders::site_state_from_json(json, site_names_, "the active server's site state");
    obstacle_enabled_ = read.state.obstacle_enabled;
    pallet_at_ = read.state.ledger.occupancy();
    problem_.clear();
  } catch (const InputError& e) {
    problem_ = e.what();
  }
}

void StandbyView::robot(const model::RobotState& state, double now_wall) {
  sim_time_ = std::max(sim_time_, state.sim_time);
  robots_[state.robot_id] = {state, now_wall};
}

void StandbyView::serve(double now_wall) {
  refuse_requests();
  if (now_wall - last_published_wall_ < 1.0 / kHzWall) return;
  last_published_wall_ = now_wall;
  publish(now_wall);
}

void StandbyView::publish(double now_wall) {
  LiveSnapshot snap;
  snap.map = site_.site_map->site.name;
  snap.site_map = site_.site_map;
  snap.known_names = known_names_;
  snap.sim_time = sim_time_;
  snap.time_scale = site_.time_scale;
  snap.server_id = site_.server_id;
  snap.standby = true;
  snap.active_server = active_id_;
  const double lost_after = site_.config->settings.get_double("server.robot_lost_after_s");
  for (const auto& [id, heard] : robots_) {
    RobotView view;
    view.state = heard.state;
    if (const auto spec = site_.config->find_robot(id)) view.footprint = spec->first->footprint;
    view.health = std::string(
        monitor::to_string(monitor::robot_health({.silent_s = now_wall - heard.wall, .lost_after_s = lost_after})));
    view.age_s = std::max(0.0, sim_time_ - heard.state.sim_time);
    snap.robots.push_back(std::move(view));
  }
  fill_orders(orders_, snap);
  // Per sim hour since the first order it mirrored was created: the standby did not see the start.
  if (!orders_.empty()) {
    double first_created = sim_time_;
    for (const auto& [id, order] : orders_) first_created = std::min(first_created, order.created_sim);
    const double hours = (sim_time_ - first_created) / 3600.0;
    snap.orders_per_hour = hours > 0 ? snap.orders_done / hours : 0.0;
  }
  snap.obstacle_enabled = obstacle_enabled_;
  snap.pallet_at = pallet_at_;
  bridge_.publish(std::move(snap));
}

void StandbyView::refuse_requests() {
  for (auto& pending : bridge_.drain()) {
    model::RequestReply reply;
    reply.accepted = false;
    reply.error = site_.server_id + " is a standby server" +
                  (active_id_.empty() ? std::string(" and hears no active server")
                                      : " for " + active_id_ + ": send requests to the active server") +
                  "; its view is read-only";
    pending.reply.set_value(reply);
  }
}

}  // namespace fleet::server
