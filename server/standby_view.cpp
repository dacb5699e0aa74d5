#include "server/standby_view.hpp"

#include <algorithm>
#include <vector>

#include "common/errors.hpp"
#include "common/percentile.hpp"
#include "monitor/robot_health.hpp"
#include "orders/order.hpp"
#include "orders/site_state.hpp"
#include "traffic/order_names.hpp"

namespace fleet::server {

namespace {
constexpr double kHzWall = 5.0;
constexpr std::size_t kRecentEndedOrders = 50;  // as the active server's view

bool is_open(const model::OrderInfo& info) {
  const auto status = orders::parse_status(info.state);
  return status && !orders::is_final(*status);
}
}  // namespace

StandbyView::StandbyView(WebBridge& bridge, Site site)
    : bridge_(bridge),
      site_(std::move(site)),
      // The web API checks requests against them before it hands them on, as on the active server.
      known_names_(
          std::make_shared<const orders::KnownNames>(traffic::order_request_names(*site_.config, *site_.site_map))) {}

void StandbyView::order(const model::OrderInfo& info) {
  if (info.state == "DONE") done_durations_[info.order_id] = info.finished_sim - info.created_sim;
  sim_time_ = std::max(sim_time_, info.updated_sim);
  orders_[info.order_id] = info;
}

void StandbyView::site_state(const std::string& json) {
  std::vector<std::string> robots;
  for (const auto& [fleet, robot] : site_.config->all_robots()) robots.push_back(robot->id);
  try {
    const orders::RestoredSiteState read = orders::site_state_from_json(
        json, orders::site_names_of(site_.site_map->site, robots), "the active server's site state");
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
  std::vector<const model::OrderInfo*> ended;
  for (const auto& [id, info] : orders_) {
    if (is_open(info)) {
      snap.orders.push_back(info);
    } else {
      ended.push_back(&info);
    }
    if (info.state == "FAILED") ++snap.orders_failed;
  }
  for (std::size_t i = ended.size() > kRecentEndedOrders ? ended.size() - kRecentEndedOrders : 0; i < ended.size();
       ++i) {
    snap.orders.push_back(*ended[i]);
  }
  std::vector<double> durations;
  for (const auto& [id, d] : done_durations_) durations.push_back(d);
  snap.orders_done = static_cast<long>(durations.size());
  // Per sim hour since the first order it mirrored was created: the standby did not see the start.
  if (!orders_.empty()) {
    double first_created = sim_time_;
    for (const auto& [id, info] : orders_) first_created = std::min(first_created, info.created_sim);
    const double hours = (sim_time_ - first_created) / 3600.0;
    snap.orders_per_hour = hours > 0 ? snap.orders_done / hours : 0.0;
  }
  snap.order_time_p95_s = common::percentile(std::move(durations), 0.95);
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
