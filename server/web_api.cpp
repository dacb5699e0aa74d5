// The web API's calls that change something: orders, obstacles, maps, robots, automatic
// orders.

#include "server/web_api.hpp"

#include <httplib.h>
#include <unistd.h>

#include <algorithm>
#include <regex>

#include "common/errors.hpp"
#include "model/names.hpp"
#include "orders/order_request_check.hpp"
#include "orders/pick_lines.hpp"
#include "server/web_gate.hpp"
#include "server/web_http.hpp"

namespace fleet::server {

using httplib::Request;
using httplib::Response;
using nlohmann::json;

WebApi::WebApi(const WebOptions& options, WebBridge& bridge, const WebSiteInfo& site, WebGate& gate, Logger log)
    : options_(options), bridge_(bridge), site_(site), gate_(gate), log_(std::move(log)) {}

void WebApi::install(httplib::Server& http) {
  // A POST or DELETE that announces no body (curl -X POST without -d) would keep cpp-httplib
  // reading until the client hangs up. Such a request is routed here, before any body is read,
  // and answered as if its body were empty: at once, with the handler's own answer.
  struct RouteWithoutBody {
    std::string method;
    std::regex pattern;
    httplib::Server::Handler handler;
  };
  auto without_body = std::make_shared<std::vector<RouteWithoutBody>>();
  auto route = [&http, without_body, this](const std::string& method, const std::string& pattern,
                                           void (WebApi::*call)(const Request&, Response&)) {
    httplib::Server::Handler handler = [this, call](const Request& req, Response& res) { (this->*call)(req, res); };
    if (method == "POST") {
      http.Post(pattern, handler);
    } else {
      http.Delete(pattern, handler);
    }
    without_body->push_back({method, std::regex(pattern), std::move(handler)});
  };
  http.set_pre_routing_handler([without_body](const Request& req, Response& res) {
    const bool takes_body =
        req.method == "POST" || req.method == "DELETE" || req.method == "PUT" || req.method == "PATCH";
    if (!takes_body || announces_body(req)) return httplib::Server::HandlerResponse::Unhandled;
    Request bodiless = req;
    for (const auto& r : *without_body) {
      if (r.method == bodiless.method && std::regex_match(bodiless.path, bodiless.matches, r.pattern)) {
        r.handler(bodiless, res);
        return httplib::Server::HandlerResponse::Handled;
      }
    }
    send_error(res, 404, "", "no such resource");
    return httplib::Server::HandlerResponse::Handled;
  });
  route("POST", "/api/orders", &WebApi::add_order);
  route("DELETE", R"(/api/orders/([^/]+))", &WebApi::cancel_order);
  route("POST", R"(/api/obstacles/([^/]+))", &WebApi::switch_obstacle);
  route("POST", "/api/map", &WebApi::switch_map);
  route("POST", R"(/api/robots/([^/]+)/(pause|resume))", &WebApi::pause_or_resume);
  route("POST", "/api/auto-orders", &WebApi::switch_auto_orders);
}

bool WebApi::authorized(const Request& req, Response& res) const {
  return gate_.admit(req, res, model::WebRole::kOperator);
}

WebApi::Reply WebApi::ask(WebRequest request, Response& res) {
  // A request that times out stays queued and may still be carried out; the 503 says only that
  // no answer came in time.
  auto reply = bridge_.submit(std::move(request));
  if (reply.wait_for(std::chrono::duration<double>(options_.reply_timeout_s)) != std::future_status::ready) {
    send_error(
        res, 503, "",
        "the server loop did not answer within " + std::to_string(static_cast<int>(options_.reply_timeout_s)) + " s");
    return std::nullopt;
  }
  return reply.get();
}

std::string WebApi::next_request_id() {
  return "web-" + std::to_string(::getpid()) + "-" + std::to_string(++request_counter_);
}

std::vector<std::string> WebApi::robot_ids() const {
  std::vector<std::string> ids;
  for (const auto& [fleet, robot] : site_.config->all_robots()) ids.push_back(robot->id);
  return ids;
}

WebApi::Reply WebApi::command(Response& res, std::string verb, std::string target, std::string value) {
  model::Command c;
  c.request_id = next_request_id();
  c.verb = std::move(verb);
  c.target = std::move(target);
  c.value = std::move(value);
  log_->info("web: {} {} {} ({})", c.verb, c.target, c.value, c.request_id);
  return ask(c, res);
}

void WebApi::done(Response& res, const model::RequestReply& reply, json extra) {
  extra["accepted"] = true;
  extra["request_id"] = reply.request_id;
  send_json(res, 200, extra);
}

void WebApi::add_order(const Request& req, Response& res) {
  if (!authorized(req, res)) return;
  const auto body = body_object(req, res);
  if (!body || !only_fields(*body, {"kind", "from", "to", "robot", "fleet", "priority", "lines"}, res)) return;
  const auto kind = string_field(*body, "kind", false, res);
  if (!kind) return;
  // A pick list's CSV text is bounded by the body's size alone.
  const auto lines = string_field(*body, "lines", false, res, std::string::npos);
  if (!lines) return;
  if (!lines->empty() && *kind != "pick") return send_error(res, 400, "lines", "lines are for kind pick");
  // A move has no pick area; a pick list names its places in its lines.
  auto from = string_field(*body, "from", *kind != "move" && lines->empty(), res);
  if (!from) return;
  std::vector<orders::PickLine> pick_lines;
  if (!lines->empty()) {
    try {
      pick_lines = orders::parse_pick_lines(*lines, "lines");
    } catch (const InputError& e) {
      return send_error(res, 400, "lines", e.what());
    }
    *from = pick_lines.front().place;
  }
  const auto to = string_field(*body, "to", true, res);
  if (!to) return;
  const auto robot = string_field(*body, "robot", false, res);
  if (!robot) return;
  const auto fleet = string_field(*body, "fleet", false, res);
  if (!fleet) return;
  long priority = 0;
  if (const auto it = body->find("priority"); it != body->end()) {
    if (!it->is_number_integer())
      return send_error(res, 400, "priority", "must be an integer, got " + quoted_excerpt(*it));
    priority = it->get<long>();
  }
  // The server's own names for the map it serves (the same check it makes).
  const std::shared_ptr<const orders::KnownNames> names = bridge_.known_names();
  if (!names) return send_error(res, 503, "server", "the server has not published its site yet; try again");
  if (const auto problem = orders::check_order_request({*kind, *from, *to, *robot, *fleet, priority}, *names)) {
    return send_error(res, 400, problem->field, problem->message);
  }
  if (const auto why = pick_lines.empty()
                           ? std::nullopt
                           : orders::check_pick_lines(pick_lines, site_.site_map->site.area_ids(),
                                                      orders::declared_boxes(site_.site_map->site),
                                                      orders::max_pickable_mass(*site_.config), "lines")) {
    return send_error(res, 400, "lines", *why);
  }
  model::OrderRequest request;
  request.lines = *lines;
  request.request_id = next_request_id();
  request.kind = *kind;
  request.pick_area = *from;
  request.drop_area = *to;
  request.robot_id = *robot;
  request.fleet_id = *fleet;
  request.priority = static_cast<int>(priority);
  const auto reply = ask(request, res);
  if (!reply) return;
  if (!reply->accepted) {
    log_->info("web: order {} -> {} refused: {}", *from, *to, reply->error);
    return send_error(res, 409, "", reply->error);
  }
  log_->info("web: order {} created: {} -> {}", reply->order_id, *from, *to);
  nlohmann::json ids = nlohmann::json::array();
  for (int k = 0; k < std::max(1, reply->order_count); ++k) ids.push_back(reply->order_id + k);
  send_json(res, 201,
            {{"accepted", true}, {"request_id", reply->request_id}, {"order_id", reply->order_id}, {"order_ids", ids}});
}

void WebApi::cancel_order(const Request& req, Response& res) {
  if (!authorized(req, res)) return;
  const std::string id = req.matches[1];
  if (id.empty() || id.size() > 18 || !std::all_of(id.begin(), id.end(), [](char c) { return c >= '0' && c <= '9'; })) {
    return send_error(res, 400, "id", "order id '" + id + "' is not a number");
  }
  const auto reply = command(res, "cancel-order", id, "");
  if (!reply) return;
  if (!reply->accepted)
    return send_error(res, reply->error.rfind("unknown order", 0) == 0 ? 404 : 409, "", reply->error);
  done(res, *reply, {{"order_id", std::stoll(id)}, {"state", "CANCELLED"}});
}

void WebApi::switch_obstacle(const Request& req, Response& res) {
  if (!authorized(req, res)) return;
  const std::string id = req.matches[1];
  const map::Site& site = site_.site_map->site;
  if (!site.find_obstacle(id)) {
    std::vector<std::string> ids;
    for (const auto& o : site.static_obstacles) ids.push_back(o.id);
    return send_error(res, 404, "id", model::unknown_name_message("obstacle", id, ids));
  }
  const auto body = body_object(req, res);
  if (!body || !only_fields(*body, {"enabled"}, res)) return;
  const auto enabled = bool_field(*body, "enabled", res);
  if (!enabled) return;
  const auto reply = command(res, "obstacle", id, *enabled ? "on" : "off");
  if (!reply) return;
  if (!reply->accepted) return send_error(res, 409, "", reply->error);
  done(res, *reply, {{"obstacle", id}, {"enabled", *enabled}});
}

void WebApi::switch_map(const Request& req, Response& res) {
  if (!authorized(req, res)) return;
  const auto body = body_object(req, res);
  if (!body || !only_fields(*body, {"map", "robot"}, res)) return;
  const auto map_id = string_field(*body, "map", true, res);
  if (!map_id) return;
  const auto robot = string_field(*body, "robot", false, res);
  if (!robot) return;
  if (std::find(site_.maps.begin(), site_.maps.end(), *map_id) == site_.maps.end()) {
    return send_error(res, 400, "map", model::unknown_name_message("map", *map_id, site_.maps));
  }
  if (!robot->empty() && !site_.config->find_robot(*robot)) {
    return send_error(res, 400, "robot", model::unknown_name_message("robot", *robot, robot_ids()));
  }
  // Empty target: every robot.
  const auto reply = command(res, "map", *robot, *map_id);
  if (!reply) return;
  if (!reply->accepted) return send_error(res, 409, "", reply->error);
  done(res, *reply, {{"map", *map_id}, {"robot", *robot}});
}

void WebApi::pause_or_resume(const Request& req, Response& res) {
  if (!authorized(req, res)) return;
  const std::string id = req.matches[1];
  const std::string verb = req.matches[2];
  if (!site_.config->find_robot(id)) {
    return send_error(res, 404, "id", model::unknown_name_message("robot", id, robot_ids()));
  }
  const auto reply = command(res, verb, id, "");
  if (!reply) return;
  if (!reply->accepted) return send_error(res, 409, "", reply->error);
  done(res, *reply, {{"robot", id}, {"paused", verb == "pause"}});
}

void WebApi::switch_auto_orders(const Request& req, Response& res) {
  if (!authorized(req, res)) return;
  const auto body = body_object(req, res);
  if (!body || !only_fields(*body, {"enabled"}, res)) return;
  const auto enabled = bool_field(*body, "enabled", res);
  if (!enabled) return;
  const auto reply = command(res, "auto-orders", "", *enabled ? "on" : "off");
  if (!reply) return;
  if (!reply->accepted) return send_error(res, 409, "", reply->error);
  done(res, *reply, {{"auto_orders", *enabled}});
}

}  // namespace fleet::server
