#include "config/schema.hpp"

#include <sstream>

namespace fleet::config {

namespace {

KeySpec number(std::string key, double def, std::string unit, double lo, double hi, std::string what) {
  std::ostringstream d;
  d << def;
  return {std::move(key), ValueType::kDouble, d.str(), std::move(unit), lo, hi, {}, std::move(what)};
}
KeySpec integer(std::string key, long def, std::string unit, long lo, long hi, std::string what) {
  return {std::move(key),
          ValueType::kInt,
          std::to_string(def),
          std::move(unit),
          static_cast<double>(lo),
          static_cast<double>(hi),
          {},
          std::move(what)};
}
KeySpec flag(std::string key, bool def, std::string what) {
  return {std::move(key), ValueType::kBool, def ? "true" : "false", "", 0, 0, {}, std::move(what)};
}
KeySpec text(std::string key, std::string def, std::string what) {
  return {std::move(key), ValueType::kString, std::move(def), "", 0, 0, {}, std::move(what)};
}
KeySpec choice(std::string key, std::string def, std::vector<std::string> choices, std::string what) {
  return {std::move(key), ValueType::kChoice, std::move(def), "", 0, 0, std::move(choices), std::move(what)};
}

std::vector<KeySpec> make_schema() {
  return {
      // Whole system
      text("site", "table_a", "site to load: maps/<site>.yaml"),
      number("time_scale", 1.0, "", 0.01, 100.0, "sim_time = time_scale x wall_time, read by every process"),
      integer("dds.domain", 0, "", 0, 232, "DDS domain id"),
      text("dds.security", "",
           "security folder made by fleetctl security init: every process joins the DDS domain with DDS Security, "
           "presenting its own credentials from it (--security; env FLEET_SECURITY overrides the file); empty: "
           "without"),
      integer("seed", 1, "", 0, 2147483647, "seed of every random engine; a run is reproducible from it"),

      // Server
      choice("server.dispatch_policy", "ascending-id", {"ascending-id", "nearest", "optimal"},
             "how queued orders are matched with free robots"),
      flag("server.auto_orders", false, "create random orders whenever a robot is free [Forklift thesis, section 3]"),
      choice("server.auto_pick_handling", "tray", {"tray", "loader", "auto"},
             "how the automatic pick lists travel: tours to a packing station on the picker's tray, or walks whose "
             "boxes go on the pallet of a stacker behind the picker (docs/loader.md); auto: loader when a stacker "
             "and an empty pallet are free"),
      integer("server.loader_pallet_boxes", 6, "boxes", 1, 6,
              "boxes a loader sets on one transporter's pallet before it goes to expedition: the picker's arm "
              "reaches a row of three behind it, two layers high (docs/loader.md)"),
      flag("server.reject_when_busy", false,
           "reject manual orders while no robot is free (the Forklift thesis's mode) instead of queueing them"),
      number("server.fleet_view_hz", 20.0, "Hz", 1.0, 100.0,
             "rate of FleetView (per map, for observers) and of each agent's NeighbourView, in sim time"),
      number("server.neighbour_radius", 100.0, "m", 1.0, 1000.0,
             "each agent is sent the robots within this distance of it (NeighbourView); the default covers every "
             "robot of the shipped sites but the big warehouse, whose configuration sets 8 m"),
      number("server.robot_lost_after_s", 1.0, "s", 0.1, 60.0,
             "wall seconds without RobotState after which a robot is marked lost"),
      number("server.lost_with_pallet_wait_s", 60.0, "s", 1.0, 3600.0,
             "wall seconds an order waits for its lost robot that carries the pallet to come back with it "
             "before it is FAILED"),
      number("server.order_ack_timeout_s", 2.0, "s", 0.1, 60.0,
             "wall seconds an agent has to acknowledge an order before it is re-sent"),
      text("server.db_path", "fleet.db",
           "SQLite database of orders and their events, relative to the state folder (FLEET_STATE_DIR; var/ "
           "in the source tree) unless absolute"),
      integer("server.order_resend_limit", 2, "", 0, 100, "re-sends of an unacknowledged order before it is re-queued"),
      flag("server.standby", false,
           "start as a standby (fleet-server --standby): mirror the active server's orders and site state into "
           "server.db_path and take over when it is gone"),
      text("server.id", "",
           "this server process's name among the fleet's servers (fleetctl servers; of two active servers in one "
           "term, the greater id stays active); empty: the host name and the process id"),
      number("server.standby_silence_s", 3.0, "s", 1.5, 60.0,
             "wall seconds without the active server's ServerLoad (once a second) after which a standby takes over; "
             "a dead server's liveliness lapses sooner, after 1 s"),
      // Web view and HTTP API (server/web_server.hpp)
      integer("server.http_port", 8080, "", 0, 65535, "port of the web view and JSON API; 0 turns them off"),
      text("server.http_host", "127.0.0.1", "address the web view binds; keep loopback unless it must be reachable"),
      text("server.api_token", "",
           "the operator's token: every call of the API; env FLEET_API_TOKEN overrides it; empty: generated and "
           "logged"),
      text("server.viewer_token", "",
           "the viewer's token: the API's reading calls and the live stream; env FLEET_VIEWER_TOKEN overrides it; "
           "empty: generated and logged"),
      text("server.http_tls_cert", "",
           "PEM certificate of the web view: with server.http_tls_key it serves HTTPS (TLS 1.2 at least); empty: "
           "HTTP"),
      text("server.http_tls_key", "", "PEM private key of server.http_tls_cert"),
      number("server.web_stream_hz", 20.0, "Hz", 1.0, 50.0, "highest rate of the web view's live stream, wall time"),

      // Agent
      number("agent.state_hz", 20.0, "Hz", 1.0, 200.0, "RobotState publication rate, in sim time"),
      number("agent.sim_step_s", 0.005, "s", 0.0005, 0.05, "integration step of the simulated body, sim time"),
      number("agent.max_speed", 0.2, "m/s", 0.01, 2.0, "forward speed limit"),
      number("agent.max_yaw_rate", 1.5, "rad/s", 0.1, 10.0, "turn rate limit"),
      number("agent.goal_tolerance", 0.01, "m", 0.001, 0.5, "distance at which a target pose counts as reached"),

      // Traffic (core/traffic): reservations on the road graph, granted by the server
      flag("traffic.enabled", true,
           "robots drive only into road stretches the server granted them; false: the Forklift thesis's local "
           "avoidance only"),
      number("traffic.lookahead", 0.6, "m", 0.1, 5.0, "route granted ahead of a robot when the road is free"),
      number("traffic.priority_wait_s", 8.0, "s", 0.0, 600.0,
             "sim seconds a stopped robot waits before its next stretch is reserved for it"),
      number("traffic.reroute_wait_s", 30.0, "s", 1.0, 3600.0,
             "bound on waiting: a robot waiting this long (sim seconds) is re-routed around its blockers"),
      number("traffic.lost_reroute_wait_s", 3.0, "s", 0.1, 3600.0,
             "a robot waiting this long (sim seconds) only on lost robots is re-routed around them"),
      number("traffic.margin", 0.03, "m", 0.0, 1.0,
             "the traffic manager: gap kept between the regions of reservations; larger values make junction "
             "zones swallow whole corridors (0.06 m jams 8 robots on table_a), the agents' safety stop keeps its "
             "own distance"),
      number("traffic.places_margin", 0.12, "m", 0.0, 1.0,
             "the places core: gap kept between the bodies of robots at conflicting places, in place of "
             "traffic.margin; the agents' look ahead keeps half of it, the other half is for two robots standing "
             "or driving off the places they are counted at"),
      flag("traffic.one_way", true,
           "the traffic manager: give corridors on cycles of the road network one driving direction"),
      flag("traffic.places_one_way", false,
           "the places core: give corridors on cycles one driving direction, as traffic.one_way does for the "
           "manager (robots pushed aside still back up against it); off, robots drive every lane both ways and "
           "the plan settles who makes room"),
      choice("traffic.core", "manager", {"manager", "places"},
             "what grants the roads: the traffic manager, or the coordination core's planner and order of "
             "visits (docs/coordination.md)"),
      number("traffic.plan_period_s", 0.0, "s", 0.0, 10.0,
             "the places core: sim seconds between plan steps; 0: a move between neighbouring places at the "
             "slowest fleet's top speed"),
      integer("traffic.plan_ahead", 4, "moves", 1, 20,
              "the places core: moves a robot's plan may run ahead of where the robot is, so how far it is "
              "granted beyond its place"),

      // VDA 5050 (fleet-vda5050): vehicles of fleets of robot type vda5050, over MQTT
      text("vda5050.broker", "tcp://127.0.0.1:1883", "the MQTT broker fleet-vda5050 connects to"),
      number("vda5050.state_timeout_s", 35.0, "s", 1.0, 600.0,
             "wall seconds without a vehicle's state after which it is lost; VDA 5050 vehicles send state at least "
             "every 30 s"),

      // Fault injection (soak tests only; everything off by default)
      number("faults.pose_delay_ms", 0.0, "ms", 0.0, 10000.0,
             "agents publish RobotState this much late (wall time), as a slow network would deliver it"),
      number("faults.pose_delay_jitter_ms", 0.0, "ms", 0.0, 10000.0, "uniform +- jitter on faults.pose_delay_ms"),
  };
}

}  // namespace

const std::vector<KeySpec>& schema() {
  static const std::vector<KeySpec> table = make_schema();
  return table;
}

const KeySpec* find_key(const std::string& key) {
  for (const KeySpec& spec : schema()) {
    if (spec.key == key) return &spec;
  }
  return nullptr;
}

std::string markdown_row(const KeySpec& spec) {
  std::string allowed;
  switch (spec.type) {
    case ValueType::kDouble: {
      std::ostringstream r;
      r << spec.min << " .. " << spec.max;
      allowed = r.str();
      break;
    }
    case ValueType::kInt:
      allowed =
          std::to_string(static_cast<long long>(spec.min)) + " .. " + std::to_string(static_cast<long long>(spec.max));
      break;
    case ValueType::kBool:
      allowed = "true, false";
      break;
    case ValueType::kString:
      allowed = "text";
      break;
    case ValueType::kChoice:
      for (std::size_t i = 0; i < spec.choices.size(); ++i) allowed += (i ? ", " : "") + spec.choices[i];
      break;
  }
  std::ostringstream out;
  out << "| `" << spec.key << "` | " << spec.default_value << " | " << spec.unit << " | " << allowed << " | "
      << spec.description << " |\n";
  return out.str();
}

std::string schema_markdown() {
  std::string out = std::string(kMarkdownHeader);
  for (const KeySpec& spec : schema()) out += markdown_row(spec);
  return out;
}

}  // namespace fleet::config
