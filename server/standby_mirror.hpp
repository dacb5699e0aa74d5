#pragma once

#include <atomic>
#include <cstdint>
#include <string>

#include "common/logging.hpp"
#include "dds/topics.hpp"
#include "server/order_store.hpp"

namespace fleet::server {

/// A standby server before it takes over. It mirrors what the active server publishes into its own
/// database: every order with its history (OrderInfo, rebuilt by orders::order_of) and the site's
/// state (SiteState). It watches the active through its ServerLoad writer, whose liveliness lease
/// is 1 s (dds::qos::live_state). The takeover is a server started on that database: the path a
/// restarted server takes.
class StandbyMirror {
 public:
  /// Opens (or creates) the standby's own database at `db_path` and joins DDS domain `domain`.
  StandbyMirror(std::uint32_t domain, const std::string& db_path, Logger log);

  /// Mirrors until the active server is gone or `stop` becomes true; true when it is gone. Gone:
  /// its ServerLoad writer lost its liveliness, or no ServerLoad came for `silence_s` wall seconds,
  /// also since the start (no active server to stand by for).
  bool run_until_active_lost(const std::atomic<bool>& stop, double silence_s);

  long orders_mirrored() const { return orders_mirrored_; }

 private:
  void mirror_orders();
  void mirror_site_state();
  /// True once the active server is gone (see run_until_active_lost).
  bool active_gone(double now_wall, double silence_s);

  Logger log_;
  OrderStore store_;
  dds::Participant participant_;
  dds::Reader<model::OrderInfo> order_info_reader_;
  dds::Reader<model::SiteStateDocument> site_state_reader_;
  dds::Reader<model::ServerLoad> load_reader_;
  double last_heard_wall_ = 0.0;
  bool heard_ = false;
  bool writer_lost_ = false;
  long orders_mirrored_ = 0;
};

}  // namespace fleet::server
