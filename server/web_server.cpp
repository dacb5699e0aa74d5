#include "server/web_server.hpp"

#include <httplib.h>
#include <openssl/ssl.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>
#include <stdexcept>

#include "model/names.hpp"
#include "server/web_api.hpp"
#include "server/web_gate.hpp"
#include "server/web_http.hpp"
#include "server/web_json.hpp"

namespace fleet::server {

// The page's files, compiled into the binary by server/web/embed_assets.cmake so that the server
// serves the page it was built with, wherever it runs from. The same declaration is in the
// generated source.
namespace web_assets {
struct Entry {
  const char* path;
  const unsigned char* data;
  std::size_t size;
};
extern const Entry kEntries[];
extern const std::size_t kEntryCount;
}  // namespace web_assets

using nlohmann::json;

namespace {

using namespace web_json;

json path_array(const std::vector<geometry::Vec2>& path) {
  json out = json::array();
  for (const auto& p : path) out.push_back(point(p.x, p.y));
  return out;
}

json robot_json(const RobotView& view, FramePaths* paths = nullptr) {
  const auto& s = view.state;
  json j{{"fleet", s.fleet_id},
         {"map", s.map_id},
         {"x", r4(s.pose.x)},
         {"y", r4(s.pose.y)},
         {"yaw", r4(s.pose.yaw)},
         // x-x, x-y, y-y and yaw-yaw of the row-major 3x3 covariance: what the ellipse and the
         // heading uncertainty need.
         {"cov",
          json::array({sig3(s.covariance[0]), sig3(s.covariance[1]), sig3(s.covariance[4]), sig3(s.covariance[8])})},
         {"score", r3(s.localization_score)},
         {"speed", r3(s.speed)},
         {"state", s.task_state},
         {"detail", s.detail},
         {"order", s.order_id},
         {"carrying", s.carrying_pallet},
         {"health", view.health},
         {"age", round_places(view.age_s, 1)},
         {"fp", json::array({view.footprint.length, view.footprint.width})}};
  if (paths) {
    auto& entry = paths->by_robot[view.state.robot_id];
    if (!entry.text || entry.points != view.path) {
      entry.points = view.path;
      entry.text = std::make_shared<const std::string>(path_array(view.path).dump());
      entry.version = paths->next_version++;
    }
    j["path_v"] = entry.version;
  } else {
    j["path"] = path_array(view.path);
  }
  if (!view.traffic.empty()) {
    json reserved = json::array();
    for (const auto& p : view.reserved) reserved.push_back(point(p.x, p.y));
    j["traffic"] = {{"status", view.traffic}, {"waiting_for", view.waiting_for}, {"reserved", std::move(reserved)}};
  }
  // Absent rather than null: a frame never holds null, so null in a diff means "removed".
  if (!s.docking_targets.empty()) {
    json targets = json::array();
    for (const auto& p : s.docking_targets) targets.push_back(point(p.x, p.y));
    j["dock_targets"] = std::move(targets);
  }
  if (s.detected_pallet) {
    j["detected_pallet"] =
        json::array({r4(s.detected_pallet->x), r4(s.detected_pallet->y), r4(s.detected_pallet->yaw)});
  }
  if (view.truth) {
    j["truth"] = json::array({r4(view.truth->pose.x), r4(view.truth->pose.y), r4(view.truth->pose.yaw)});
    j["truth_carrying"] = view.truth->carrying_pallet;
  }
  return j;
}

json order_json(const model::OrderInfo& o) {
  return json{{"id", o.order_id},
              {"kind", o.kind},
              {"from", o.pick_area},
              {"to", o.drop_area},
              {"fleet", o.fleet_id},
              {"robot", o.robot_id},
              {"state", o.state},
              {"phase", o.phase},
              {"reason", o.reason},
              {"priority", o.priority},
              {"created", r3(o.created_sim)},
              {"updated", r3(o.updated_sim)},
              {"cause", o.cause},
              {"caused_by", o.caused_by}};
}

json globals_json(const LiveSnapshot& s) {
  return json{{"map", s.map},
              {"sim_time", r3(s.sim_time)},
              {"time_scale", s.time_scale},
              {"auto_orders", s.auto_orders},
              {"orders_done", s.orders_done},
              {"orders_failed", s.orders_failed},
              {"orders_per_hour", round_places(s.orders_per_hour, 1)},
              {"order_time_p95_s", round_places(s.order_time_p95_s, 1)},
              {"server", s.server_id},
              {"standby", s.standby},
              {"active_server", s.active_server}};
}

const json kEmptyObject = json::object();

const json& section_of(const json& frame, const char* name) {
  const auto it = frame.find(name);
  return it == frame.end() ? kEmptyObject : *it;
}

/// Changed and removed values of a flat object (id -> value).
void diff_flat(const json& prev, const json& next, const char* name, json& out) {
  json changed = json::object();
  json removed = json::array();
  for (const auto& [key, value] : next.items()) {
    const auto it = prev.find(key);
    if (it == prev.end() || *it != value) changed[key] = value;
  }
  for (const auto& [key, value] : prev.items()) {
    if (!next.contains(key)) removed.push_back(key);
  }
  if (!changed.empty()) out[name] = std::move(changed);
  if (!removed.empty()) out[std::string(name) + "_removed"] = std::move(removed);
}

/// Per entity (id -> object) the changed fields; a new entity whole; a vanished field as null.
void diff_keyed(const json& prev, const json& next, const char* name, json& out) {
  json changed = json::object();
  json removed = json::array();
  for (const auto& [id, entity] : next.items()) {
    const auto it = prev.find(id);
    if (it == prev.end()) {
      changed[id] = entity;
      continue;
    }
    json fields = json::object();
    for (const auto& [key, value] : entity.items()) {
      const auto f = it->find(key);
      if (f == it->end() || *f != value) fields[key] = value;
    }
    for (const auto& [key, value] : it->items()) {
      if (!entity.contains(key)) fields[key] = nullptr;
    }
    if (!fields.empty()) changed[id] = std::move(fields);
  }
  for (const auto& [id, entity] : prev.items()) {
    if (!next.contains(id)) removed.push_back(id);
  }
  if (!changed.empty()) out[name] = std::move(changed);
  if (!removed.empty()) out[std::string(name) + "_removed"] = std::move(removed);
}

constexpr const char* kKeyedSections[] = {"robots", "orders"};
constexpr const char* kFlatSections[] = {"obstacles", "pallets", "globals"};

std::string mime_of(const std::string& path) {
  auto ends = [&](const char* ext) {
    const std::string e(ext);
    return path.size() >= e.size() && path.compare(path.size() - e.size(), e.size(), e) == 0;
  };
  if (ends(".html")) return "text/html; charset=utf-8";
  if (ends(".js")) return "text/javascript; charset=utf-8";
  if (ends(".css")) return "text/css; charset=utf-8";
  if (ends(".svg")) return "image/svg+xml";
  if (ends(".png")) return "image/png";
  return "application/octet-stream";
}

std::string sse_text(const char* name, std::uint64_t version, const std::string& data) {
  return std::string("event: ") + name + "\nid: " + std::to_string(version) + "\ndata: " + data + "\n\n";
}

}  // namespace

// ---- JSON --------------------------------------------------------------------------------------

json state_json(const LiveSnapshot& snapshot) {
  json j = globals_json(snapshot);
  json robots = json::array();
  for (const auto& view : snapshot.robots) {
    json r = robot_json(view);
    r["id"] = view.state.robot_id;
    robots.push_back(std::move(r));
  }
  j["robots"] = std::move(robots);
  json orders = json::array();
  for (const auto& o : snapshot.orders) {
    json order = order_json(o);
    json history = json::array();
    for (const auto& e : o.history) {
      history.push_back({{"sim_time", r3(e.sim_time)},
                         {"state", e.state},
                         {"phase", e.phase},
                         {"robot", e.robot_id},
                         {"reason", e.reason},
                         {"robot_x", r4(e.robot_x)},
                         {"robot_y", r4(e.robot_y)}});
    }
    order["history"] = std::move(history);
    orders.push_back(std::move(order));
  }
  j["orders"] = std::move(orders);
  j["obstacles"] = snapshot.obstacle_enabled;
  j["pallets"] = snapshot.pallet_at;
  return j;
}

json frame_json(const LiveSnapshot& snapshot, FramePaths* paths) {
  json robots = json::object();
  for (const auto& view : snapshot.robots) robots[view.state.robot_id] = robot_json(view, paths);
  json orders = json::object();
  for (const auto& o : snapshot.orders) orders[std::to_string(o.order_id)] = order_json(o);
  return json{{"globals", globals_json(snapshot)},
              {"robots", std::move(robots)},
              {"orders", std::move(orders)},
              {"obstacles", snapshot.obstacle_enabled},
              {"pallets", snapshot.pallet_at}};
}

std::string with_paths(const json& event, const FramePaths& paths, const std::vector<std::string>& ids) {
  std::string text = event.dump();
  std::string spliced;
  for (const std::string& id : ids) {
    const auto it = paths.by_robot.find(id);
    if (it == paths.by_robot.end() || !it->second.text) continue;
    if (!spliced.empty()) spliced.push_back(',');
    spliced.append(json(id).dump()).push_back(':');
    spliced.append(*it->second.text);
  }
  if (spliced.empty()) return text;
  text.pop_back();  // the closing brace of the event's object
  if (text.size() > 1) text.push_back(',');
  text.append("\"paths\":{").append(spliced).append("}}");
  return text;
}

json frame_diff(const json& prev, const json& next) {
  json out = json::object();
  for (const char* name : kKeyedSections) diff_keyed(section_of(prev, name), section_of(next, name), name, out);
  for (const char* name : kFlatSections) diff_flat(section_of(prev, name), section_of(next, name), name, out);
  return out;
}

void frame_apply(json& frame, const json& diff) {
  for (const char* name : kKeyedSections) {
    json& section = frame[name];
    if (!section.is_object()) section = json::object();
    if (const auto it = diff.find(name); it != diff.end()) {
      for (const auto& [id, fields] : it->items()) {
        json& entity = section[id];
        if (!entity.is_object()) entity = json::object();
        for (const auto& [key, value] : fields.items()) {
          if (value.is_null()) {
            entity.erase(key);
          } else {
            entity[key] = value;
          }
        }
      }
    }
    if (const auto it = diff.find(std::string(name) + "_removed"); it != diff.end()) {
      for (const auto& id : *it) section.erase(id.get<std::string>());
    }
  }
  for (const char* name : kFlatSections) {
    json& section = frame[name];
    if (!section.is_object()) section = json::object();
    if (const auto it = diff.find(name); it != diff.end()) {
      for (const auto& [key, value] : it->items()) section[key] = value;
    }
    if (const auto it = diff.find(std::string(name) + "_removed"); it != diff.end()) {
      for (const auto& key : *it) section.erase(key.get<std::string>());
    }
  }
}

std::string generate_api_token() {
  std::random_device entropy;
  std::string token;
  static constexpr char kHex[] = "0123456789abcdef";
  for (int i = 0; i < 32; ++i) token += kHex[entropy() % 16];
  return token;
}

// ---- the server --------------------------------------------------------------------------------

/// One stream frame, shared by every client: the full frame for clients that join or fell
/// behind, and the diff from the frame before it for clients that received that one.
struct WebServer::Frame {
  std::uint64_t version = 0;
  std::uint64_t prev_version = 0;
  json frame;
  std::string diff_event;

  /// Written only when a client needs it (it joined or fell behind): with hundreds of robots the
  /// whole frame is megabytes of text, and clients that keep up take the diff.
  const std::string& full_event() const {
    std::call_once(full_once_, [this] {
      std::vector<std::string> ids;
      for (const auto& [id, entry] : paths.by_robot) ids.push_back(id);
      full_event_ = sse_text("full", version, with_paths(frame, paths, ids));
    });
    return full_event_;
  }
  /// The paths as of this frame (their texts shared with the frames before and after).
  FramePaths paths;

 private:
  mutable std::once_flag full_once_;
  mutable std::string full_event_;
};

WebServer::WebServer(WebOptions options, WebBridge& bridge, WebSiteInfo site, Logger log)
    : options_(std::move(options)), bridge_(bridge), site_(std::move(site)), log_(std::move(log)) {
  if (options_.tokens.operator_token.empty() || options_.tokens.viewer.empty()) {
    throw std::invalid_argument("web server: an empty token (the viewer's and the operator's must both be set)");
  }
  if (options_.tokens.operator_token == options_.tokens.viewer) {
    throw std::invalid_argument("web server: the viewer's token is the operator's: a viewer could change everything");
  }
  if (options_.tls_certificate.empty() != options_.tls_key.empty()) {
    throw std::invalid_argument("web server: HTTPS needs both a certificate and its key");
  }
  if (!site_.site_map) throw std::invalid_argument("web server: no site map");
  site_body_ = site_json(site_).dump();
}

WebServer::~WebServer() {
  stop();
}

std::unique_ptr<httplib::Server> WebServer::make_http() const {
  if (!tls()) return std::make_unique<httplib::Server>();
  for (const auto& file : {options_.tls_certificate, options_.tls_key}) {
    if (access(file.c_str(), R_OK) != 0) throw std::runtime_error("HTTPS: cannot read " + file);
  }
  auto https = std::make_unique<httplib::SSLServer>(options_.tls_certificate.c_str(), options_.tls_key.c_str());
  if (!https->is_valid()) {
    throw std::runtime_error("HTTPS: " + options_.tls_certificate + " and " + options_.tls_key +
                             " are not a PEM certificate and its private key");
  }
  SSL_CTX_set_min_proto_version(https->ssl_context(), TLS1_2_VERSION);
  return https;
}

std::uint64_t WebServer::failed_authentications() const {
  return gate_ ? gate_->failures() : 0;
}

void WebServer::start() {
  http_ = make_http();
  // Every stream client holds a thread while it listens; the rest serve the API and the page.
  const auto threads = static_cast<std::size_t>(options_.max_stream_clients + 8);
  http_->new_task_queue = [threads] { return new httplib::ThreadPool(threads); };
  http_->set_payload_max_length(64 * 1024);
  http_->set_keep_alive_timeout(2);
  // Exclusive: cpp-httplib's default adds SO_REUSEPORT, with which a second server on the same
  // port binds too and the kernel spreads requests over both.
  http_->set_socket_options([](socket_t sock) {
    const int yes = 1;
    setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
  routes();
  port_ = options_.port == 0 ? http_->bind_to_any_port(options_.host) : options_.port;
  if (port_ <= 0 || (options_.port != 0 && !http_->bind_to_port(options_.host, options_.port))) {
    http_.reset();
    throw std::runtime_error("cannot listen on " + std::string(tls() ? "https" : "http") + "://" + options_.host + ":" +
                             std::to_string(options_.port) + ": the port is in use, or the address is not this host's");
  }
  stopping_ = false;
  pump_ = std::thread([this] { pump(); });
  listener_ = std::thread([this] { http_->listen_after_bind(); });
}

void WebServer::stop() {
  if (!http_) return;
  {
    std::lock_guard lock(frame_mutex_);
    stopping_ = true;
  }
  frame_cv_.notify_all();
  http_->stop();
  if (listener_.joinable()) listener_.join();
  if (pump_.joinable()) pump_.join();
  http_.reset();
}

void WebServer::pump() {
  const auto period = std::chrono::duration<double>(1.0 / options_.stream_hz);
  std::uint64_t seen = 0;
  std::shared_ptr<const Frame> previous;
  FramePaths paths;
  while (true) {
    {
      std::unique_lock lock(frame_mutex_);
      frame_cv_.wait_for(lock, period, [this] { return stopping_.load(); });
      if (stopping_) return;
    }
    auto [snapshot, version] = bridge_.latest();
    // Version 0 is the empty snapshot before the server loop's first publish.
    if (version == seen || version == 0) continue;
    if (snapshot.site_map && snapshot.site_map.get() != site_.site_map) {
      // The robots were switched to another map of the site: serve its roads from now on. Maps
      // seen stay alive: request handlers may still read the previous one.
      std::lock_guard lock(site_mutex_);
      maps_seen_.push_back(snapshot.site_map);
      site_.site_map = snapshot.site_map.get();
      site_body_ = site_json(site_).dump();
    }
    seen = version;
    auto frame = std::make_shared<Frame>();
    frame->version = version;
    frame->frame = frame_json(snapshot, &paths);
    // Robots that left take their paths with them.
    std::erase_if(paths.by_robot, [&](const auto& e) { return !frame->frame["robots"].contains(e.first); });
    frame->paths = paths;
    if (previous) {
      frame->prev_version = previous->version;
      const json diff = frame_diff(previous->frame, frame->frame);
      std::vector<std::string> changed;
      if (const auto robots = diff.find("robots"); robots != diff.end()) {
        for (const auto& [id, fields] : robots->items()) {
          if (fields.contains("path_v")) changed.push_back(id);
        }
      }
      frame->diff_event = sse_text("diff", version, with_paths(diff, paths, changed));
    }
    previous = frame;
    ++frames_built_;
    {
      std::lock_guard lock(frame_mutex_);
      frame_ = std::move(frame);
    }
    frame_cv_.notify_all();
  }
}

std::shared_ptr<const WebServer::Frame> WebServer::wait_frame(std::uint64_t after, double timeout_s) {
  std::unique_lock lock(frame_mutex_);
  frame_cv_.wait_for(lock, std::chrono::duration<double>(timeout_s),
                     [&] { return stopping_.load() || (frame_ && frame_->version > after); });
  if (stopping_ || !frame_ || frame_->version <= after) return nullptr;
  return frame_;
}

void WebServer::routes() {
  using httplib::Request;
  using httplib::Response;
  httplib::Server& http = *http_;

  // Every answer: no caching of live data, no sniffing, nothing loaded from elsewhere. No CORS
  // headers, so other origins cannot read the API from a browser.
  http.set_default_headers({{"Cache-Control", "no-store"},
                            {"X-Content-Type-Options", "nosniff"},
                            {"Content-Security-Policy",
                             "default-src 'self'; img-src 'self' data:; style-src 'self'; script-src 'self'; "
                             "connect-src 'self'; frame-ancestors 'none'"}});
  http.set_error_handler(httplib::Server::HandlerWithResponse([](const Request&, Response& res) {
    // Errors the handlers answered keep their JSON; the library's own (404 for an unknown path)
    // get one too.
    if (!res.body.empty()) return httplib::Server::HandlerResponse::Unhandled;
    send_error(res, res.status, "", res.status == 404 ? "no such resource" : "request failed");
    return httplib::Server::HandlerResponse::Handled;
  }));
  http.set_exception_handler([this](const Request& req, Response& res, std::exception_ptr ep) {
    std::string what = "unknown error";
    try {
      std::rethrow_exception(ep);
    } catch (const std::exception& e) {
      what = e.what();
    } catch (...) {
    }
    log_->error("web: {} {} failed: {}", req.method, req.path, what);
    send_error(res, 500, "", what);
  });

  // ---- the page ----
  auto serve_asset = [](const std::string& name, Response& res) {
    for (std::size_t i = 0; i < web_assets::kEntryCount; ++i) {
      const auto& entry = web_assets::kEntries[i];
      if (name == entry.path) {
        res.set_content(reinterpret_cast<const char*>(entry.data), entry.size, mime_of(name));
        return true;
      }
    }
    return false;
  };
  http.Get("/", [serve_asset](const Request&, Response& res) { serve_asset("index.html", res); });
  http.Get(R"(/([a-z_]+\.(?:js|css|html|svg|png)))", [serve_asset](const Request& req, Response& res) {
    if (!serve_asset(req.matches[1], res)) send_error(res, 404, "", "no such file");
  });

  // ---- reading: the viewer's token or the operator's ----
  gate_ = std::make_unique<WebGate>(options_.tokens, log_);
  const auto viewer = [this](const Request& req, Response& res) {
    return gate_->admit(req, res, model::WebRole::kViewer);
  };
  http.Get("/api/site", [this, viewer](const Request& req, Response& res) {
    if (!viewer(req, res)) return;
    std::string body;
    {
      std::lock_guard lock(site_mutex_);
      body = site_body_;
    }
    res.set_content(body, "application/json");
  });
  http.Get("/api/fleets", [this, viewer](const Request& req, Response& res) {
    if (!viewer(req, res)) return;
    std::lock_guard lock(site_mutex_);
    send_json(res, 200, fleets_json(*site_.config));
  });
  http.Get("/api/state", [this, viewer](const Request& req, Response& res) {
    if (!viewer(req, res)) return;
    const LiveSnapshot snapshot = bridge_.latest().first;
    json state = state_json(snapshot);
    // The map the robots drive on now (the server's snapshot is ahead of the served roads by at
    // most one stream period).
    if (!snapshot.map.empty()) {
      state["site"] = snapshot.map;
    } else {
      std::lock_guard lock(site_mutex_);
      state["site"] = site_.site_map->site.name;
    }
    state["failed_authentications"] = gate_->failures();
    send_json(res, 200, state);
  });
  http.Get("/api/stream", [this, viewer](const Request& req, Response& res) {
    if (!viewer(req, res)) return;
    if (stream_clients_.fetch_add(1) >= options_.max_stream_clients) {
      --stream_clients_;
      send_error(res, 503, "", "too many stream clients (" + std::to_string(options_.max_stream_clients) + ")");
      return;
    }
    auto last_sent = std::make_shared<std::uint64_t>(0);
    res.set_header("Cache-Control", "no-cache");
    res.set_chunked_content_provider(
        "text/event-stream",
        [this, last_sent](std::size_t, httplib::DataSink& sink) {
          if (stopping_) return false;
          const auto frame = wait_frame(*last_sent, 5.0);
          if (stopping_) return false;
          if (!frame) {
            // A comment line: keeps proxies from timing out and finds clients that left while
            // the server loop publishes nothing.
            static const std::string keepalive = ": keepalive\n\n";
            return sink.write(keepalive.data(), keepalive.size());
          }
          const bool diff_fits = *last_sent != 0 && frame->prev_version == *last_sent && !frame->diff_event.empty();
          const std::string& event = diff_fits ? frame->diff_event : frame->full_event();
          *last_sent = frame->version;
          return sink.write(event.data(), event.size());
        },
        [this](bool) { --stream_clients_; });
  });

  api_ = std::make_unique<WebApi>(options_, bridge_, site_, *gate_, log_);
  api_->install(*http_);
}

}  // namespace fleet::server
