#pragma once

#include <atomic>
#include <functional>
#include <future>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "common/clock.hpp"
#include "common/logging.hpp"
#include "config/fleet_config.hpp"
#include "dds/security.hpp"
#include "dds/topics.hpp"
#include "map/site_map.hpp"
#include "orders/area_ledger.hpp"
#include "orders/auto_orders.hpp"
#include "orders/dispatcher.hpp"
#include "orders/loader_desk.hpp"
#include "orders/order_book.hpp"
#include "orders/order_info.hpp"
#include "orders/order_intake.hpp"
#include "orders/order_recovery.hpp"
#include "orders/order_request_check.hpp"
#include "orders/recovery_watch.hpp"
#include "orders/robot_roster.hpp"
#include "orders/site_state.hpp"
#include "planning/road_planner.hpp"
#include "planning/road_travel.hpp"
#include "server/order_store.hpp"
#include "server/order_wire.hpp"
#include "server/place_traffic_control.hpp"
#include "server/reply_desk.hpp"
#include "server/robot_body_memory.hpp"
#include "server/robot_recovery.hpp"
#include "server/robot_routing.hpp"
#include "server/sender_gate.hpp"
#include "server/server_load.hpp"
#include "server/server_peers.hpp"
#include "server/site_derivation.hpp"
#include "server/site_keeper.hpp"
#include "server/traffic_control.hpp"
#include "server/web_bridge.hpp"

namespace fleet::server {

struct ServerOptions {
  config::FleetConfig config;
  map::Site site;
  std::uint32_t domain = 0;
  double time_scale = 1.0;
  std::uint64_t seed = 1;
  std::string db_path;                           ///< SQLite file of orders and events
  std::shared_ptr<const map::SiteMap> site_map;  ///< the site with its road graph
  /// The site and its revisions (map::site_revisions): the maps robots can be switched to.
  std::vector<std::string> maps;
  std::string server_id;        ///< this process among the fleet's servers (server.id)
  std::int64_t heard_term = 0;  ///< the highest term heard another server serve in (a standby's)
  bool took_over = false;       ///< it becomes active by taking over from another server
};

/// How FleetServer::run ended.
enum class RunEnd { kStopped, kSteppedDown };

using orders::info_of;
using orders::RobotEntry;

/// The command centre and message router [Forklift thesis, chapter 3]: takes orders, dispatches them,
/// tracks robots, owns the site state (obstacles, pallets) and routes poses as FleetView.
class FleetServer {
 public:
  FleetServer(ServerOptions options, Logger log);
  ~FleetServer();

  /// Runs until `stop` becomes true, or until it hears another active server that outranks it
  /// (orders::outranks): then it steps down and the process goes on as a standby.
  RunEnd run(const std::atomic<bool>& stop);

  /// Connects the web view: the loop then publishes snapshots to it and carries out its
  /// requests. Call before run(); the bridge must outlive the server.
  void attach_web(WebBridge* bridge) { bridge_ = bridge; }

  /// After it stepped down: the orders that changed since it last heard another server (a few
  /// seconds before, for what was on the way), or since it became active when it never heard
  /// one. What the other may not know, for it to merge (orders::merge_handed_over).
  std::vector<model::OrderInfo> orders_to_hand_over() const;

 private:
  /// Whether another active server outranks this one (orders::outranks), listened for a while
  /// when the loop stood still `since_last_loop_s` beyond its liveliness lease.
  bool stepped_aside(const std::atomic<bool>& stop, double since_last_loop_s);
  /// Every robot's map assignment and the current map's obstacles (latched).
  void publish_map_and_obstacles();
  using Answer = std::function<void(const model::RequestReply&)>;
  /// Starts deriving map `command.value` (a revision of the site) off the loop; `answer` hears
  /// of it once finish_map_switch() has switched every robot onto it, or refused. Returns why
  /// not, empty when started.
  std::string begin_map_switch(const model::Command& command, Answer answer);
  /// Switches every robot onto the map begin_map_switch() derived, once it is ready (call every
  /// loop): the map, the fleets' graphs and a new traffic manager.
  void finish_map_switch();
  /// Takes a derived site as the server's own (at the start and on a map switch).
  void adopt(SiteDerivation derived);
  void publish_server_info();
  void handle_order_requests();
  void handle_commands();
  void handle_robot_states();
  void handle_order_reports();
  /// Orders a server that stepped down hands over: merged into the book (orders::merge_handed_over).
  void handle_handed_over_orders();
  /// A current report on an open order (orders::ReportVerdict::kApply): the lifecycle and the
  /// loads it moves.
  void apply_report(const orders::Order& order, const model::OrderReport& report);
  void create_auto_orders();
  void dispatch();
  void handle_web_requests();
  void publish_web_snapshot();

  /// Carries out an order request or a command from DDS or the web view; the reply says how.
  model::RequestReply execute(const model::OrderRequest& request);
  /// A command's reply goes to `answer`: at once, or when a map switch it started is done.
  void execute(const model::Command& command, const Answer& answer);
  /// Creates the transports the packing chain owes (orders::next_chain_transport), if the site
  /// has packing stations and an order changed since it last looked.
  void advance_packing_chain();
  /// Carries out what the loader desk decides for the loader jobs (orders::LoaderDesk): the
  /// transports their pallets need, and each update of their orders.
  void advance_loader_jobs();
  /// What order intake reads of the server's state now: the book, the ledger, the names, the
  /// site, who parks where, which robots reported and which are free, and its settings.
  orders::IntakeView intake_view() const;
  /// Adds the drafts an intake decided to the book in their order, each logged, stored and
  /// published; the first one's id (0 when there is none).
  std::int64_t add_orders(std::vector<orders::Order> drafts);

  /// The loading areas, robots and fleets an order request may name.
  const orders::KnownNames& known_names() const;
  /// Metres along the road graph from a robot to where it stands to pick from `area_id`; +inf
  /// when there is no way.
  double travel_cost(const std::string& robot_id, const std::string& place_id);
  void restore_orders();

  ServerOptions options_;
  Logger log_;
  /// Takes the robots' own messages only from writers that may speak for them.
  SenderGate gate_{!dds::security_identity().empty(), log_};
  OrderStore store_;
  RobotBodyMemory body_memory_{store_};  ///< where robots last stood, for a restarted server
  /// Road-graph travel cost for dispatch, per fleet on the lanes its vehicle fits.
  /// Mutable: it caches the distance fields it computed.
  mutable std::map<std::string, planning::RoadDistances> travel_;
  /// What orders may name on the site served, with each fleet's abilities and the places it
  /// cannot reach (server::derive_site).
  std::shared_ptr<const orders::KnownNames> known_names_;
  /// A map switch under way: its derivation runs off the loop.
  struct MapSwitch {
    std::string request_id;
    std::string map_id;
    std::future<SiteDerivation> derived;
    Answer answer;
  };
  std::optional<MapSwitch> map_switch_;
  SimClock clock_;
  orders::Dispatcher dispatcher_;
  orders::OrderBook book_;
  orders::RobotRoster robots_{options_.config};
  /// Assignments awaiting acknowledgement, and orders waiting for their lost robot.
  orders::RecoveryWatch watch_;
  orders::AutoOrders auto_orders_;
  orders::LoaderDesk loader_desk_{
      {.pallet_boxes = static_cast<int>(options_.config.settings.get_int("server.loader_pallet_boxes")),
       .transporter_fleet = orders::loader_fleet(options_.config)}};
  double started_wall_ = 0.0;
  double last_web_snapshot_wall_ = 0.0;
  WebBridge* bridge_ = nullptr;

  /// The term it serves in: one above every term it held or heard; its writers' ownership strength.
  orders::ServerTerm term_;
  dds::Participant participant_;
  dds::Writer<model::ServerInfo> server_info_writer_;
  dds::Writer<model::MapAssignment> map_writer_;
  dds::Writer<model::RobotControl> control_writer_;
  dds::Reader<model::OrderRequest> request_reader_;
  dds::Reader<model::Command> command_reader_;
  dds::Reader<model::RobotState> robot_state_reader_;
  dds::Reader<model::OrderReport> order_report_reader_;
  dds::Reader<model::OrderHandover> handover_reader_;
  RobotRouting routing_{participant_, options_.config, clock_};
  ReplyDesk replies_{participant_};
  /// What stands where (the pallets' simulation truth), who parks where, which obstacles are on.
  SiteKeeper site_keeper_{participant_, store_, log_};
  /// Null when traffic.enabled is false; replaced on a map switch.
  std::unique_ptr<TrafficService> traffic_;
  /// Stores each order and tells the robots and the other servers.
  OrderWire wire_{participant_, store_, book_, robots_, watch_, options_.site};
  RobotRecovery recovery_{{.config = options_.config,
                           .clock = clock_,
                           .log = log_,
                           .book = book_,
                           .robots = robots_,
                           .watch = watch_,
                           .site_keeper = site_keeper_,
                           .wire = wire_,
                           .body_memory = body_memory_,
                           .traffic = traffic_}};
  dds::WaitSet waitset_;
  ServerLoadMeter load_meter_;
  ServerPeers peers_;
  double next_traffic_sim_ = 0.0;
  double last_traffic_wall_ = 0.0;
};

}  // namespace fleet::server
