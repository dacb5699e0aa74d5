#pragma once
// The web API's calls that change something (web_api.cpp), installed by WebServer.

#include <atomic>
#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "common/logging.hpp"
#include "server/web_bridge.hpp"
#include "server/web_server.hpp"

namespace httplib {
class Server;
struct Request;
struct Response;
}  // namespace httplib

namespace fleet::server {

/// Orders, obstacles, maps, robots and automatic orders over HTTP. Each call needs the operator's token,
/// checks its input as fleetctl does (one check, in core/orders for orders) and hands the request
/// to the server loop through the bridge, waiting for its answer.
class WebApi {
 public:
  /// `site` is the web server's own: a map switch it sees is seen here.
  WebApi(const WebOptions& options, WebBridge& bridge, const WebSiteInfo& site, WebGate& gate, Logger log);
  WebApi(const WebApi&) = delete;
  WebApi& operator=(const WebApi&) = delete;

  /// Adds the routes to `http`; this object must outlive its serving.
  void install(httplib::Server& http);

 private:
  using Reply = std::optional<model::RequestReply>;
  /// Whether the request carries the operator's token; answers 401 or 403 when it does not.
  bool authorized(const httplib::Request& req, httplib::Response& res) const;
  /// Hands a request to the server loop and waits for its answer (the same execute() as
  /// fleetctl's requests over DDS); none, after answering 503, when none came in time.
  Reply ask(WebRequest request, httplib::Response& res);
  Reply command(httplib::Response& res, std::string verb, std::string target, std::string value);
  std::string next_request_id();
  std::vector<std::string> robot_ids() const;
  /// 200 with what was done, after the server loop accepted it.
  static void done(httplib::Response& res, const model::RequestReply& reply, nlohmann::json extra);

  void add_order(const httplib::Request& req, httplib::Response& res);
  void cancel_order(const httplib::Request& req, httplib::Response& res);
  void switch_obstacle(const httplib::Request& req, httplib::Response& res);
  void switch_map(const httplib::Request& req, httplib::Response& res);
  void pause_or_resume(const httplib::Request& req, httplib::Response& res);
  void switch_auto_orders(const httplib::Request& req, httplib::Response& res);

  const WebOptions& options_;
  WebBridge& bridge_;
  const WebSiteInfo& site_;
  WebGate& gate_;
  Logger log_;
  std::atomic<std::uint64_t> request_counter_{0};
};

}  // namespace fleet::server
