#include "vda5050/vehicle_order.hpp"

#include <algorithm>
#include <set>

#include "vda5050/json_read.hpp"

namespace fleet::vda5050 {

using nlohmann::json;
using namespace json_read;

namespace {

constexpr std::size_t kInstantActionsKept = 20;

std::vector<ReceivedAction> read_action_list(const json& actions, const std::string& where) {
  std::vector<ReceivedAction> out;
  for (std::size_t i = 0; i < actions.size(); ++i) {
    std::string at = where + ".actions[";
    at += std::to_string(i);
    at += ']';
    const json& a = actions[i];
    if (!a.is_object()) throw MessageError(at + " is not an object");
    // 2.0.0's instantActions schema names the type actionName; the text and every order say actionType.
    const char* type_key = a.contains("actionType") || !a.contains("actionName") ? "actionType" : "actionName";
    ReceivedAction action{text(a, "actionId", at), text(a, type_key, at), text(a, "blockingType", at), {}};
    if (action.blocking != "NONE" && action.blocking != "SOFT" && action.blocking != "HARD") {
      throw MessageError(at + ": blockingType '" + action.blocking + "' is none of NONE, SOFT, HARD");
    }
    if (const auto p = a.find("actionParameters"); p != a.end() && p->is_array()) {
      for (const json& parameter : *p) {
        if (!parameter.is_object()) throw MessageError(at + ".actionParameters: an entry is not an object");
        const json& value = required(parameter, "value", at + ".actionParameters");
        action.parameters.emplace_back(text(parameter, "key", at + ".actionParameters"),
                                       value.is_string() ? value.get<std::string>() : value.dump());
      }
    }
    out.push_back(std::move(action));
  }
  return out;
}

std::vector<ReceivedAction> read_actions(const json& element, const std::string& where) {
  return read_action_list(list(element, "actions", where), where);
}

ReceivedNode read_node(const json& n, const std::string& at) {
  if (!n.is_object()) throw MessageError(at + " is not an object");
  ReceivedNode node;
  node.id = text(n, "nodeId", at);
  node.sequence = count(n, "sequenceId", at);
  node.released = flag(n, "released", at);
  if (const auto p = n.find("nodePosition"); p != n.end() && !p->is_null()) {
    const std::string where = at + ".nodePosition";
    node.has_position = true;
    node.x = number(*p, "x", where);
    node.y = number(*p, "y", where);
    if (p->contains("theta")) node.theta = number(*p, "theta", where);
    node.map_id = text(*p, "mapId", where);
    for (const char* key : {"allowedDeviationXy", "allowedDeviationXY"}) {
      if (p->contains(key)) node.allowed_deviation = number(*p, key, where);
    }
    if (node.allowed_deviation < 0.0) throw MessageError(where + ": the allowed deviation is negative");
  }
  node.actions = read_actions(n, at);
  return node;
}

ReceivedEdge read_edge(const json& e, const std::string& at) {
  if (!e.is_object()) throw MessageError(at + " is not an object");
  ReceivedEdge edge;
  edge.id = text(e, "edgeId", at);
  edge.sequence = count(e, "sequenceId", at);
  edge.released = flag(e, "released", at);
  edge.start_node = text(e, "startNodeId", at);
  edge.end_node = text(e, "endNodeId", at);
  edge.actions = read_actions(e, at);
  return edge;
}

std::string indexed(const char* name, std::size_t i) {
  std::string out = name;
  out += '[';
  out += std::to_string(i);
  out += ']';
  return out;
}

/// The rules that tie nodes and edges into one path [VDA 5050, section 6.6.2].
void check_graph(const ReceivedOrder& order) {
  if (order.nodes.empty()) throw MessageError("nodes: an order has at least one node");
  if (order.edges.size() + 1 != order.nodes.size()) {
    throw MessageError("edges: " + std::to_string(order.edges.size()) + " edges for " +
                       std::to_string(order.nodes.size()) + " nodes; an order has one edge fewer than nodes");
  }
  if (order.nodes.front().sequence % 2 != 0) throw MessageError("nodes[0].sequenceId: a node's sequenceId is even");
  if (!order.nodes.front().released) throw MessageError("nodes[0].released: the first node is released");
  bool horizon = false;
  std::set<std::string> action_ids;
  for (std::size_t i = 0; i < order.nodes.size(); ++i) {
    const ReceivedNode& node = order.nodes[i];
    if (node.sequence != order.nodes.front().sequence + 2 * i) {
      throw MessageError(indexed("nodes", i) + ".sequenceId: " + std::to_string(node.sequence) + " where " +
                         std::to_string(order.nodes.front().sequence + 2 * i) + " follows");
    }
    if (horizon && node.released) throw MessageError(indexed("nodes", i) + ": released after an unreleased node");
    horizon = horizon || !node.released;
    for (const ReceivedAction& a : node.actions) {
      if (!action_ids.insert(a.id).second) throw MessageError("actionId '" + a.id + "' given twice");
    }
  }
  for (std::size_t i = 0; i < order.edges.size(); ++i) {
    const ReceivedEdge& edge = order.edges[i];
    const std::string at = indexed("edges", i);
    if (edge.sequence != order.nodes[i].sequence + 1) {
      throw MessageError(at + ".sequenceId: " + std::to_string(edge.sequence) + " where " +
                         std::to_string(order.nodes[i].sequence + 1) + " follows");
    }
    if (edge.start_node != order.nodes[i].id || edge.end_node != order.nodes[i + 1].id) {
      throw MessageError(at + ": joins '" + edge.start_node + "' to '" + edge.end_node + "', not '" +
                         order.nodes[i].id + "' to '" + order.nodes[i + 1].id + "'");
    }
    if (edge.released != order.nodes[i + 1].released) {
      throw MessageError(at + ".released: differs from the node it leads to");
    }
    for (const ReceivedAction& a : edge.actions) {
      if (!action_ids.insert(a.id).second) throw MessageError("actionId '" + a.id + "' given twice");
    }
  }
}

bool ended(const ActionStatus& a) {
  return a.status == "FINISHED" || a.status == "FAILED";
}

ActionStatus waiting(const ReceivedAction& a) {
  return {a.id, a.type, "WAITING", ""};
}

}  // namespace

ReceivedOrder read_order(const json& message) {
  if (!message.is_object()) throw MessageError("the order is not a JSON object");
  ReceivedOrder order;
  order.header_id = count(message, "headerId", "order");
  order.order_id = text(message, "orderId", "order");
  order.update_id = count(message, "orderUpdateId", "order");
  const json& nodes = list(message, "nodes", "order");
  for (std::size_t i = 0; i < nodes.size(); ++i) order.nodes.push_back(read_node(nodes[i], indexed("nodes", i)));
  const json& edges = list(message, "edges", "order");
  for (std::size_t i = 0; i < edges.size(); ++i) order.edges.push_back(read_edge(edges[i], indexed("edges", i)));
  check_graph(order);
  return order;
}

std::vector<ReceivedAction> read_instant_actions(const json& message) {
  if (!message.is_object()) throw MessageError("the instant actions are not a JSON object");
  std::vector<ReceivedAction> out;
  bool found = false;
  for (const char* key : {"actions", "instantActions"}) {
    if (!message.contains(key)) continue;
    found = true;
    for (ReceivedAction& a : read_action_list(list(message, key, "instantActions"), key)) {
      const bool seen = std::any_of(out.begin(), out.end(), [&](const ReceivedAction& b) { return b.id == a.id; });
      if (!seen) out.push_back(std::move(a));
    }
  }
  if (!found) throw MessageError("instantActions: key 'actions' is missing");
  return out;
}

VehicleError order_error(const std::string& type, const std::string& description, const json& message,
                         std::vector<std::pair<std::string, std::string>> more) {
  VehicleError error{type, "WARNING", description, {{"topic", "order"}}};
  if (message.is_object()) {
    if (const auto h = message.find("headerId"); h != message.end() && h->is_number_integer()) {
      error.references.emplace_back("headerId", h->dump());
    }
    if (const auto o = message.find("orderId"); o != message.end() && o->is_string()) {
      error.references.emplace_back("orderId", o->get<std::string>());
    }
    if (const auto u = message.find("orderUpdateId"); u != message.end() && u->is_number_integer()) {
      error.references.emplace_back("orderUpdateId", u->dump());
    }
  }
  error.references.insert(error.references.end(), more.begin(), more.end());
  return error;
}

json error_json(const VehicleError& error) {
  json references = json::array();
  for (const auto& [key, value] : error.references) {
    references.push_back({{"referenceKey", key}, {"referenceValue", value}});
  }
  return {{"errorType", error.type},
          {"errorLevel", error.level},
          {"errorDescription", error.description},
          {"errorReferences", references}};
}

const ReceivedNode& VehicleOrder::base_end() const {
  const ReceivedNode* end = &last_node_;
  for (const ReceivedNode& n : nodes_) {
    if (n.released) end = &n;
  }
  return *end;
}

bool VehicleOrder::active() const {
  return std::any_of(nodes_.begin(), nodes_.end(), [](const ReceivedNode& n) { return n.released; }) ||
         std::any_of(actions_.begin(), actions_.end(), [](const ActionStatus& a) { return !ended(a); });
}

OrderVerdict VehicleOrder::check(const ReceivedOrder& order, const json& message, bool at_first_node) const {
  const ReceivedNode& first = order.nodes.front();
  const ReceivedNode& end = base_end();
  const bool starts_at_base_end = !order_id_.empty() && first.id == end.id && first.sequence == end.sequence;
  std::string base_end_text = "node '";
  base_end_text += end.id;
  base_end_text += "' sequenceId ";
  base_end_text += std::to_string(end.sequence);
  if (order.order_id == order_id_) {
    if (order.update_id < update_id_) {
      return {std::nullopt, order_error("orderUpdateError",
                                        "orderUpdateId " + std::to_string(order.update_id) + " is lower than " +
                                            std::to_string(update_id_) + ", the update the vehicle runs",
                                        message)};
    }
    if (order.update_id == update_id_) return {OrderIntake::kRepeat, std::nullopt};
  }
  if (order.order_id == order_id_ || active()) {
    if (!starts_at_base_end) {
      return {std::nullopt,
              order_error("orderUpdateError",
                          "the order begins at node '" + first.id + "' sequenceId " + std::to_string(first.sequence) +
                              ", not at the end of the current base, " + base_end_text,
                          message, {{"nodeId", first.id}})};
    }
    return {active() ? OrderIntake::kStitch : OrderIntake::kUpdate, std::nullopt};
  }
  if (!at_first_node && !(first.id == last_node_.id && !order_id_.empty())) {
    return {std::nullopt,
            order_error("noRouteError",
                        "the vehicle does not stand at the first node '" + first.id + "' within its allowed deviation",
                        message, {{"nodeId", first.id}})};
  }
  return {OrderIntake::kNew, std::nullopt};
}

std::vector<ReceivedNode> VehicleOrder::nodes_taking(const ReceivedOrder& order, OrderIntake intake) const {
  std::vector<ReceivedNode> out;
  if (intake == OrderIntake::kRepeat) return nodes_;
  if (intake != OrderIntake::kNew) {
    for (const ReceivedNode& n : nodes_) {
      if (n.released) out.push_back(n);
    }
  }
  out.insert(out.end(), order.nodes.begin() + 1, order.nodes.end());
  return out;
}

void VehicleOrder::take(const ReceivedOrder& order, OrderIntake intake) {
  if (intake == OrderIntake::kRepeat) return;
  if (intake == OrderIntake::kNew) {
    nodes_.clear();
    edges_.clear();
    actions_.clear();
    last_node_ = order.nodes.front();
    for (const ReceivedAction& a : last_node_.actions) actions_.push_back(waiting(a));
  } else {
    // The horizon is replaced; the base stays as it was released [VDA 5050, section 6.6.3].
    std::erase_if(nodes_, [](const ReceivedNode& n) { return !n.released; });
    std::erase_if(edges_, [](const ReceivedEdge& e) { return !e.released; });
    std::set<std::string> kept;
    for (const ReceivedNode& n : nodes_) {
      for (const ReceivedAction& a : n.actions) kept.insert(a.id);
    }
    for (const ReceivedEdge& e : edges_) {
      for (const ReceivedAction& a : e.actions) kept.insert(a.id);
    }
    for (const ReceivedAction& a : last_node_.actions) kept.insert(a.id);
    std::erase_if(actions_, [&](const ActionStatus& a) { return a.status == "WAITING" && !kept.contains(a.id); });
  }
  order_id_ = order.order_id;
  update_id_ = order.update_id;
  for (std::size_t i = 1; i < order.nodes.size(); ++i) {
    nodes_.push_back(order.nodes[i]);
    for (const ReceivedAction& a : order.nodes[i].actions) actions_.push_back(waiting(a));
  }
  for (const ReceivedEdge& e : order.edges) {
    edges_.push_back(e);
    for (const ReceivedAction& a : e.actions) actions_.push_back(waiting(a));
  }
}

void VehicleOrder::passed(std::uint32_t sequence) {
  const auto node =
      std::find_if(nodes_.begin(), nodes_.end(), [&](const ReceivedNode& n) { return n.sequence == sequence; });
  if (node == nodes_.end()) return;
  last_node_ = *node;
  std::erase_if(nodes_, [&](const ReceivedNode& n) { return n.sequence <= sequence; });
  std::erase_if(edges_, [&](const ReceivedEdge& e) { return e.sequence < sequence; });
}

void VehicleOrder::set_action_status(const std::string& action_id, const std::string& status,
                                     const std::string& result) {
  for (auto* list : {&actions_, &instant_actions_}) {
    for (ActionStatus& a : *list) {
      if (a.id != action_id) continue;
      a.status = status;
      a.result = result;
      return;
    }
  }
}

std::string VehicleOrder::action_type(const std::string& action_id) const {
  for (const ActionStatus& a : actions_) {
    if (a.id == action_id) return a.type;
  }
  return "";
}

bool VehicleOrder::cancel() {
  if (!active()) return false;
  nodes_.clear();
  edges_.clear();
  for (ActionStatus& a : actions_) {
    if (!ended(a)) a.status = "FAILED";
  }
  return true;
}

void VehicleOrder::add_instant_action(const ActionStatus& action) {
  instant_actions_.push_back(action);
  if (instant_actions_.size() > kInstantActionsKept) instant_actions_.erase(instant_actions_.begin());
}

json VehicleOrder::node_states() const {
  json out = json::array();
  for (const ReceivedNode& n : nodes_) {
    json state = {{"nodeId", n.id}, {"sequenceId", n.sequence}, {"released", n.released}};
    // The 2.0.0 schema requires theta in a node state's position: without one, no position.
    if (n.has_position && n.theta) {
      state["nodePosition"] = {{"x", n.x}, {"y", n.y}, {"theta", *n.theta}, {"mapId", n.map_id}};
    }
    out.push_back(std::move(state));
  }
  return out;
}

json VehicleOrder::edge_states() const {
  json out = json::array();
  for (const ReceivedEdge& e : edges_) {
    out.push_back({{"edgeId", e.id}, {"sequenceId", e.sequence}, {"released", e.released}});
  }
  return out;
}

json VehicleOrder::action_states_json() const {
  json out = json::array();
  for (const auto* list : {&actions_, &instant_actions_}) {
    for (const ActionStatus& a : *list) {
      json state = {{"actionId", a.id}, {"actionType", a.type}, {"actionStatus", a.status}};
      if (!a.result.empty()) state["resultDescription"] = a.result;
      out.push_back(std::move(state));
    }
  }
  return out;
}

}  // namespace fleet::vda5050
