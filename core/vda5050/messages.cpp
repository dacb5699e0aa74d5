#include "vda5050/messages.hpp"

#include <cmath>
#include <ctime>

#include "vda5050/json_read.hpp"

namespace fleet::vda5050 {

using nlohmann::json;

std::string topic(const VehicleAddress& vehicle, const std::string& name) {
  std::string out = vehicle.interface_name;
  out += "/v";
  out += vehicle.version.substr(0, vehicle.version.find('.'));
  for (const std::string* part : {&vehicle.manufacturer, &vehicle.serial_number, &name}) {
    out += '/';
    out += *part;
  }
  return out;
}

std::string iso_timestamp(double unix_time) {
  const auto seconds = static_cast<std::time_t>(std::floor(unix_time));
  const int millis = std::min(999, static_cast<int>(std::lround((unix_time - static_cast<double>(seconds)) * 1000.0)));
  std::tm utc{};
  gmtime_r(&seconds, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%S", &utc);
  std::string out = text;
  out += '.';
  out += std::to_string(1000 + millis).substr(1);  // zero-padded to three digits
  out += 'Z';
  return out;
}

json header(const VehicleAddress& vehicle, std::uint32_t header_id, double unix_time) {
  return {{"headerId", header_id},
          {"timestamp", iso_timestamp(unix_time)},
          {"version", vehicle.version},
          {"manufacturer", vehicle.manufacturer},
          {"serialNumber", vehicle.serial_number}};
}

namespace {

json action_json(const NodeAction& action) {
  json parameters = json::array();
  for (const auto& [key, value] : action.parameters) parameters.push_back({{"key", key}, {"value", value}});
  return {{"actionType", action.type},
          {"actionId", action.id},
          {"blockingType", action.blocking},
          {"actionParameters", parameters}};
}

}  // namespace

json order_json(const OrderMessage& order) {
  const std::vector<OrderNode>& nodes = *order.nodes;
  json out = {{"orderId", order.order_id}, {"orderUpdateId", order.update_id}};
  json node_list = json::array();
  json edge_list = json::array();
  for (std::size_t k = order.first; k < nodes.size(); ++k) {
    const OrderNode& node = nodes[k];
    const char* deviation = order.version == "2.0.0" ? "allowedDeviationXy" : "allowedDeviationXY";
    json position = {{"x", node.x}, {"y", node.y}, {"mapId", order.map_id}, {deviation, order.allowed_deviation_xy}};
    // The schemas bound theta to [-pi, pi]; a site's yaw of 3.141593 is just past it.
    if (node.theta) position["theta"] = std::atan2(std::sin(*node.theta), std::cos(*node.theta));
    json actions = json::array();
    for (const NodeAction& a : node.actions) actions.push_back(action_json(a));
    node_list.push_back({{"nodeId", node.id},
                         {"sequenceId", order.first_sequence + 2 * k},
                         {"released", k <= order.released_through},
                         {"nodePosition", position},
                         {"actions", actions}});
    if (k + 1 < nodes.size()) {
      edge_list.push_back({{"edgeId", node.id + "-" + nodes[k + 1].id},
                           {"sequenceId", order.first_sequence + 2 * k + 1},
                           {"released", k + 1 <= order.released_through},
                           {"startNodeId", node.id},
                           {"endNodeId", nodes[k + 1].id},
                           {"actions", json::array()}});
    }
  }
  out["nodes"] = std::move(node_list);
  out["edges"] = std::move(edge_list);
  return out;
}

json instant_action_json(const std::string& type, const std::string& action_id, const std::string& version,
                         const std::vector<std::pair<std::string, json>>& parameters) {
  json list = json::array();
  for (const auto& [key, value] : parameters) list.push_back({{"key", key}, {"value", value}});
  json action = {{"actionType", type}, {"actionId", action_id}, {"blockingType", "NONE"}, {"actionParameters", list}};
  if (version == "2.0.0") action["actionName"] = type;
  const json actions = json::array({action});
  return {{"actions", actions}, {"instantActions", actions}};
}

namespace {

using namespace json_read;

std::vector<std::pair<std::string, std::string>> references(const json& error, const std::string& where) {
  std::vector<std::pair<std::string, std::string>> out;
  const auto it = error.find("errorReferences");
  if (it == error.end() || !it->is_array()) return out;
  for (const json& r : *it) {
    if (!r.is_object()) throw MessageError(where + ".errorReferences: an entry is not an object");
    const json& value = required(r, "referenceValue", where + ".errorReferences");
    out.emplace_back(text(r, "referenceKey", where + ".errorReferences"),
                     value.is_string() ? value.get<std::string>() : value.dump());
  }
  return out;
}

}  // namespace

namespace {

void read_position(const json& p, const std::string& where, VehicleState& s) {
  s.x = number(p, "x", where);
  s.y = number(p, "y", where);
  s.theta = number(p, "theta", where);
  s.map_id = text(p, "mapId", where);
  const auto initialized = p.find("positionInitialized");
  s.has_position = initialized == p.end() || !initialized->is_boolean() || initialized->get<bool>();
  s.position_uninitialized = !s.has_position;
}

void read_velocity(const json& message, VehicleState& s) {
  const auto v = message.find("velocity");
  if (v == message.end() || !v->is_object()) return;
  const double vx = v->value("vx", 0.0);
  const double vy = v->value("vy", 0.0);
  if (std::isfinite(vx) && std::isfinite(vy)) s.speed = std::hypot(vx, vy);
}

}  // namespace

bool read_visualization(const json& message, VehicleState& state) {
  if (!message.is_object()) throw MessageError("visualization: not a JSON object");
  const auto p = message.find("agvPosition");
  if (p == message.end() || p->is_null()) return false;
  read_position(*p, "visualization.agvPosition", state);
  read_velocity(message, state);
  return true;
}

VehicleState parse_state(const json& message) {
  if (!message.is_object()) throw MessageError("state: not a JSON object");
  VehicleState s;
  s.order_id = text(message, "orderId", "state");
  s.update_id = count(message, "orderUpdateId", "state");
  s.last_node_id = text(message, "lastNodeId", "state");
  s.last_node_sequence_id = count(message, "lastNodeSequenceId", "state");
  s.driving = flag(message, "driving", "state");
  if (const auto p = message.find("paused"); p != message.end() && p->is_boolean()) s.paused = p->get<bool>();
  for (const json& n : list(message, "nodeStates", "state")) {
    s.node_sequence_ids.push_back(count(n, "sequenceId", "state.nodeStates"));
    if (const auto r = n.find("released"); r != n.end() && r->is_boolean() && r->get<bool>()) ++s.released_nodes_left;
  }
  list(message, "edgeStates", "state");
  if (const auto p = message.find("agvPosition"); p != message.end() && !p->is_null()) {
    read_position(*p, "state.agvPosition", s);
  }
  read_velocity(message, s);
  for (const json& a : list(message, "actionStates", "state")) {
    ActionStatus status{text(a, "actionId", "state.actionStates"), "", text(a, "actionStatus", "state.actionStates"),
                        ""};
    if (const auto t = a.find("actionType"); t != a.end() && t->is_string()) status.type = t->get<std::string>();
    if (const auto r = a.find("resultDescription"); r != a.end() && r->is_string())
      status.result = r->get<std::string>();
    s.actions.push_back(std::move(status));
  }
  for (const json& e : list(message, "errors", "state")) {
    VehicleError error{text(e, "errorType", "state.errors"), text(e, "errorLevel", "state.errors"), "",
                       references(e, "state.errors")};
    if (const auto d = e.find("errorDescription"); d != e.end() && d->is_string())
      error.description = d->get<std::string>();
    s.errors.push_back(std::move(error));
  }
  if (const auto loads = message.find("loads"); loads != message.end() && loads->is_array()) s.loaded = !loads->empty();
  return s;
}

FactsheetFigures parse_factsheet(const json& message) {
  if (!message.is_object()) throw MessageError("factsheet: not a JSON object");
  FactsheetFigures f;
  const auto physical = message.find("physicalParameters");
  if (physical == message.end() || !physical->is_object()) return f;
  const auto read = [&](const char* key, std::optional<double>& into) {
    if (!physical->contains(key)) return;
    const double v = number(*physical, key, "factsheet.physicalParameters");
    if (v <= 0.0) throw MessageError(std::string("factsheet.physicalParameters: key '") + key + "' must be positive");
    into = v;
  };
  read("length", f.length);
  read("width", f.width);
  read("speedMax", f.speed_max);
  return f;
}

std::vector<std::string> factsheet_differences(const FactsheetFigures& sheet, double length, double width,
                                               double speed_max) {
  if (!sheet.length && !sheet.width && !sheet.speed_max) return {"its factsheet gives no physicalParameters"};
  std::vector<std::string> out;
  const auto compare = [&](const std::optional<double>& given, double planned, const char* what, const char* unit,
                           double tolerance) {
    if (!given || std::abs(*given - planned) <= tolerance) return;
    char text[160];
    std::snprintf(text, sizeof text, "its factsheet says %s %.3g %s, the fleet's profile %.3g %s", what, *given, unit,
                  planned, unit);
    out.emplace_back(text);
  };
  compare(sheet.length, length, "length", "m", 0.01);
  compare(sheet.width, width, "width", "m", 0.01);
  compare(sheet.speed_max, speed_max, "speedMax", "m/s", 0.01);
  return out;
}

std::string parse_connection(const json& message) {
  if (!message.is_object()) throw MessageError("connection: not a JSON object");
  const std::string state = text(message, "connectionState", "connection");
  if (state != "ONLINE" && state != "OFFLINE" && state != "CONNECTIONBROKEN") {
    throw MessageError("connection: key 'connectionState': '" + state + "' is not ONLINE, OFFLINE or CONNECTIONBROKEN");
  }
  return state;
}

}  // namespace fleet::vda5050
