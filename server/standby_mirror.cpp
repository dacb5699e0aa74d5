#include "server/standby_mirror.hpp"

#include <chrono>
#include <thread>

#include "common/clock.hpp"
#include "common/errors.hpp"
#include "dds/qos.hpp"
#include "orders/order_info.hpp"

namespace fleet::server {

StandbyMirror::StandbyMirror(std::uint32_t domain, const std::string& db_path, Logger log)
    : log_(std::move(log)),
      store_(db_path),
      participant_(domain),
      order_info_reader_(participant_, dds::qos::latched_state()),
      site_state_reader_(participant_, dds::qos::latched_state()),
      load_reader_(participant_, dds::qos::live_state()) {
  last_heard_wall_ = SimClock::wall_now();
  log_->info("standby: mirroring the active server into {}", store_.path());
}

bool StandbyMirror::run_until_active_lost(const std::atomic<bool>& stop, double silence_s) {
  while (!stop) {
    mirror_orders();
    mirror_site_state();
    if (active_gone(SimClock::wall_now(), silence_s)) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

void StandbyMirror::mirror_orders() {
  order_info_reader_.take_data([&](model::OrderInfo&& info) {
    try {
      store_.save(orders::order_of(info));
      ++orders_mirrored_;
    } catch (const InputError& e) {
      log_->warn("standby: order {} not mirrored: {}", info.order_id, e.what());
    }
  });
}

void StandbyMirror::mirror_site_state() {
  site_state_reader_.take_data([&](model::SiteStateDocument&& document) { store_.save_site_state(document.json); });
}

bool StandbyMirror::active_gone(double now_wall, double silence_s) {
  load_reader_.take([&](model::ServerLoad&&, const dds::SampleInfo& info) {
    if (info.valid_data) {
      if (!heard_) log_->info("standby: the active server is heard");
      heard_ = true;
      writer_lost_ = false;
      last_heard_wall_ = now_wall;
    } else if (!info.alive) {
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
