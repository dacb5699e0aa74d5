#include "server/standby_mirror.hpp"

#include <algorithm>
#include <chrono>
#include <thread>

#include "common/clock.hpp"
#include "common/errors.hpp"
#include "dds/qos.hpp"
#include "orders/order_info.hpp"

namespace fleet::server {

StandbyMirror::StandbyMirror(std::uint32_t domain, const std::string& db_path, std::string server_id, Logger log)
    : log_(std::move(log)),
      store_(db_path),
      participant_(domain),
      order_info_reader_(participant_, dds::qos::latched_state()),
      site_state_reader_(participant_, dds::qos::latched_state()),
      load_reader_(participant_, dds::qos::live_state()),
      load_writer_(participant_, dds::qos::live_state()),
      handover_writer_(participant_, dds::qos::latched_state()),
      server_id_(std::move(server_id)) {
  started_wall_ = last_heard_wall_ = SimClock::wall_now();
  log_->info("standby {}: mirroring the active server into {}", server_id_, store_.path());
}

bool StandbyMirror::run_until_active_lost(const std::atomic<bool>& stop, double silence_s) {
  while (!stop) {
    mirror_orders();
    mirror_site_state();
    const double now_wall = SimClock::wall_now();
    if (active_gone(now_wall, silence_s)) return true;
    publish_standing(now_wall);
    show(now_wall);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

void StandbyMirror::hand_over(std::vector<model::OrderInfo> orders) {
  for (model::OrderInfo& info : orders) {
    handed_over_[info.order_id] = info.history.size();
    handover_writer_.write(model::OrderHandover(std::move(info)));
  }
  log_->info("standby {}: handing over {} orders changed since it last heard another server", server_id_,
             handed_over_.size());
}

void StandbyMirror::show_on(WebBridge& bridge, StandbyView::Site site) {
  view_ = std::make_unique<StandbyView>(bridge, std::move(site));
  state_reader_ = std::make_unique<dds::Reader<model::RobotState>>(participant_, dds::qos::live_state(),
                                                                   dds::robot_report_partitions());
}

void StandbyMirror::show(double now_wall) {
  if (!view_) return;
  state_reader_->take_data([&](model::RobotState&& state) { view_->robot(state, now_wall); });
  view_->active_server(active_id_);
  view_->serve(now_wall);
}

void StandbyMirror::mirror_orders() {
  order_info_reader_.take_data([&](model::OrderInfo&& info) {
    if (const auto handed = handed_over_.find(info.order_id);
        handed != handed_over_.end() && info.history.size() >= std::min(handed->second, model::kMaxOrderHistory)) {
      handed_over_.erase(handed);
      if (handed_over_.empty()) log_->info("standby {}: the active server has every order handed over", server_id_);
    }
    try {
      const orders::Order order = orders::order_of(info);
      store_.save(order);
      if (view_) view_->order(order);
      ++orders_mirrored_;
    } catch (const InputError& e) {
      log_->warn("standby: order {} not mirrored: {}", info.order_id, e.what());
    }
  });
}

void StandbyMirror::mirror_site_state() {
  site_state_reader_.take_data([&](model::SiteStateDocument&& document) {
    store_.save_site_state(document.json);
    if (!view_) return;
    const std::string before = view_->problem();
    view_->site_state(document.json);
    if (!view_->problem().empty() && view_->problem() != before) log_->warn("standby view: {}", view_->problem());
  });
}

void StandbyMirror::publish_standing(double now_wall) {
  if (now_wall - last_published_wall_ < 1.0) return;
  last_published_wall_ = now_wall;
  model::ServerLoad standing;
  standing.server_id = server_id_;
  standing.term = heard_term_;
  standing.active = false;
  standing.since_unix_ms = static_cast<std::int64_t>(started_wall_ * 1000.0);
  standing.active_heard_s_ago = now_wall - last_heard_wall_;
  load_writer_.write(standing);
}

bool StandbyMirror::active_gone(double now_wall, double silence_s) {
  // Other standbys write ServerLoad too: only the active server's counts, and only its writer lost.
  load_reader_.take([&](model::ServerLoad&& load, const dds::SampleInfo& info) {
    if (info.valid_data && load.active && load.server_id != server_id_) {
      if (!heard_ || load.server_id != active_id_) {
        log_->info("standby: the active server {} is heard, in term {}", load.server_id, load.term);
      }
      heard_ = true;
      active_id_ = load.server_id;
      heard_term_ = std::max(heard_term_, load.term);
      writer_lost_ = false;
      last_heard_wall_ = now_wall;
    } else if (!info.valid_data && !info.alive && heard_ && load.server_id == active_id_) {
      writer_lost_ = true;
    }
  });
  if (writer_lost_) {
    log_->warn("standby: the active server's liveliness is lost; taking over ({} order updates mirrored)",
               orders_mirrored_);
    return true;
  }
  if (now_wall - last_heard_wall_ > silence_s) {
    log_->warn("standby: {} the active server for {:.1f} s; taking over ({} order updates mirrored)",
               heard_ ? "no word from" : "no sign of", now_wall - last_heard_wall_, orders_mirrored_);
    return true;
  }
  return false;
}

}  // namespace fleet::server
