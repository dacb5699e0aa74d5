#pragma once

#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "common/logging.hpp"
#include "dds/topics.hpp"
#include "server/order_store.hpp"
#include "server/standby_view.hpp"

namespace fleet::server {

/// A standby server before it takes over. It mirrors what the active server publishes into its own
/// database: every order with its history (OrderInfo, rebuilt by orders::order_of) and the site's
/// state (SiteState). It watches the active through its ServerLoad writer, whose liveliness lease
/// is 1 s (dds::qos::live_state), and publishes a ServerLoad of its own (not active, the term it
/// heard, how long ago it heard the active) for `fleetctl servers`. The takeover is a server
/// started on that database, in the term above the one heard: the path a restarted server takes.
class StandbyMirror {
 public:
  /// Opens (or creates) the standby's own database at `db_path` and joins DDS domain `domain`.
  StandbyMirror(std::uint32_t domain, const std::string& db_path, std::string server_id, Logger log);

  /// Mirrors until the active server is gone or `stop` becomes true; true when it is gone. Gone:
  /// its ServerLoad writer lost its liveliness, or no ServerLoad came for `silence_s` wall seconds,
  /// also since the start (no active server to stand by for).
  bool run_until_active_lost(const std::atomic<bool>& stop, double silence_s);

  /// Hands `orders` (what this server changed while cut off, FleetServer::orders_to_hand_over) to
  /// the active server on fleet/OrderHandover, latched, so that it has them once it hears this
  /// one; the mirror logs when the active server publishes each of them.
  void hand_over(std::vector<model::OrderInfo> orders);

  /// Shows what it mirrors on a web view, read-only, from now on (StandbyView).
  void show_on(WebBridge& bridge, StandbyView::Site site);

  long orders_mirrored() const { return orders_mirrored_; }
  /// The highest term heard an active server serve in (0 when none was heard).
  std::int64_t heard_term() const { return heard_term_; }

 private:
  void mirror_orders();
  void mirror_site_state();
  /// The web view's robots and snapshot, and its answers to requests.
  void show(double now_wall);
  /// Its own ServerLoad, once a second (wall).
  void publish_standing(double now_wall);
  /// True once the active server is gone (see run_until_active_lost).
  bool active_gone(double now_wall, double silence_s);

  Logger log_;
  OrderStore store_;
  dds::Participant participant_;
  dds::Reader<model::OrderInfo> order_info_reader_;
  dds::Reader<model::SiteStateDocument> site_state_reader_;
  dds::Reader<model::ServerLoad> load_reader_;
  dds::Writer<model::ServerLoad> load_writer_;
  dds::Writer<model::OrderHandover> handover_writer_;
  /// The web view's, when there is one: the robots as they report.
  std::unique_ptr<StandbyView> view_;
  std::unique_ptr<dds::Reader<model::RobotState>> state_reader_;
  /// Orders handed over that the active server has not published since, by id: their history length.
  std::map<std::int64_t, std::size_t> handed_over_;
  std::string server_id_;
  std::string active_id_;  ///< the active server heard last
  std::int64_t heard_term_ = 0;
  double started_wall_ = 0.0;
  double last_published_wall_ = 0.0;
  double last_heard_wall_ = 0.0;
  bool heard_ = false;
  bool writer_lost_ = false;
  long orders_mirrored_ = 0;
};

}  // namespace fleet::server
