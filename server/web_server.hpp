#pragma once

// The web view of the thesis's visualization server [Forklift thesis, chapter 3, Fig. 3.3]: a page and a JSON API
// served over HTTP, with a server-sent-event stream of what changed. It runs on its own threads
// and touches the server loop only through a WebBridge.

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "common/logging.hpp"
#include "config/fleet_config.hpp"
#include "map/site_map.hpp"
#include "model/web_access.hpp"
#include "server/web_bridge.hpp"

namespace httplib {
class Server;
}

namespace fleet::server {

class WebApi;
class WebGate;

struct WebOptions {
  std::string host = "127.0.0.1";  ///< loopback unless configured otherwise
  int port = 8080;                 ///< 0: any free port (see WebServer::port())
  model::WebTokens tokens;         ///< the viewer's and the operator's; neither may be empty
  std::string tls_certificate;     ///< PEM files: HTTPS (TLS 1.2 at least) when both are set
  std::string tls_key;
  double stream_hz = 20.0;       ///< highest rate of stream frames, wall time
  double reply_timeout_s = 5.0;  ///< how long a request waits for the server loop's answer
  int max_stream_clients = 32;   ///< each holds one thread for as long as it listens
};

/// Everything the page draws that never changes while the server runs, from the site file, its
/// road network and graph, and the fleet configuration.
struct WebSiteInfo {
  const map::SiteMap* site_map = nullptr;
  const config::FleetConfig* config = nullptr;
  std::vector<std::string> maps;  ///< map (site) ids the page may switch to
};

// ---- JSON of the API and stream; free functions so that tests and the benchmark use them too ----

/// GET /api/site: roads as lane outlines and reference polylines (metres, map frame), road
/// width, graph points and edges, loading areas, static obstacles, racks, UWB anchors, homes,
/// bounds, the robots of the configuration with their footprints, the map ids.
nlohmann::json site_json(const WebSiteInfo& info);

/// GET /api/fleets: every fleet of the configuration as a VDA 5050 factsheet
/// ({"fleets": [vehicle::factsheet, ...]}).
nlohmann::json fleets_json(const config::FleetConfig& config);

/// GET /api/state: the whole snapshot; robots and orders as arrays, orders with their history.
nlohmann::json state_json(const LiveSnapshot& snapshot);

/// A stream frame: the snapshot keyed by id ({"robots": {id: {...}}, "orders": {id: {...}},
/// "obstacles", "pallets", "globals"}), rounded to what the page can show (0.1 mm), orders without
/// their history. Diffs are taken between two of these.
/// The robots' paths as JSON text, kept between frames: a path changes when a robot replans, its
/// pose every frame. With hundreds of robots, paths of hundreds of points each made the stream's
/// frames mostly paths; they travel apart, under "paths": {id: [[x, y], ...]}, whole, in the
/// frame a robot's path changed in (and in every full frame).
struct FramePaths {
  struct Entry {
    std::vector<geometry::Vec2> points;
    std::shared_ptr<const std::string> text;
    std::uint64_t version = 0;
  };
  std::map<std::string, Entry> by_robot;
  std::uint64_t next_version = 1;
};
/// With `paths`, each robot carries "path_v" (its path's version in `paths`) instead of "path".
nlohmann::json frame_json(const LiveSnapshot& snapshot, FramePaths* paths = nullptr);

/// The text of `event` (a frame or a diff) with the paths of `ids` spliced in under "paths".
std::string with_paths(const nlohmann::json& event, const FramePaths& paths, const std::vector<std::string>& ids);

/// What changed from `prev` to `next` (both frame_json): per robot and order only the fields that
/// changed (a new id carries all its fields), per obstacle, pallet and global value only the
/// changed ones, and the ids that left under "<section>_removed". Empty sections are omitted.
nlohmann::json frame_diff(const nlohmann::json& prev, const nlohmann::json& next);

/// Applies a frame_diff to a frame, as the page does; frame_apply(a, frame_diff(a, b)) == b.
void frame_apply(nlohmann::json& frame, const nlohmann::json& diff);

/// Serves the page, the API and the stream on its own threads. The bridge must outlive it.
class WebServer {
 public:
  WebServer(WebOptions options, WebBridge& bridge, WebSiteInfo site, Logger log);
  ~WebServer();
  WebServer(const WebServer&) = delete;
  WebServer& operator=(const WebServer&) = delete;

  /// Binds and starts serving. Throws std::runtime_error naming the address when it cannot bind.
  void start();
  /// Stops serving and joins its threads; ends every open stream. Called by the destructor.
  void stop();
  /// The bound port (useful with port 0).
  int port() const { return port_; }

  /// Whether it serves HTTPS.
  bool tls() const { return !options_.tls_certificate.empty(); }
  /// Failed authentications since start.
  std::uint64_t failed_authentications() const;

  /// Stream frames built so far (one per new snapshot, shared by every client).
  std::uint64_t frames_built() const { return frames_built_.load(); }

 private:
  struct Frame;
  std::unique_ptr<httplib::Server> make_http() const;
  void routes();
  void pump();
  std::shared_ptr<const Frame> wait_frame(std::uint64_t after, double timeout_s);

  WebOptions options_;
  WebBridge& bridge_;
  WebSiteInfo site_;
  Logger log_;
  std::string site_body_;  ///< GET /api/site, serialized once per map
  std::mutex site_mutex_;  ///< site_body_ and site_.site_map, replaced when the map is switched
  std::vector<std::shared_ptr<const map::SiteMap>> maps_seen_;
  std::unique_ptr<WebGate> gate_;  ///< who may read and who may change (web_gate.hpp)
  std::unique_ptr<WebApi> api_;    ///< the calls that change something (web_api.hpp)
  std::unique_ptr<httplib::Server> http_;
  int port_ = 0;
  std::thread listener_;
  std::thread pump_;
  std::atomic<bool> stopping_{false};
  std::atomic<int> stream_clients_{0};
  std::atomic<std::uint64_t> frames_built_{0};

  std::mutex frame_mutex_;
  std::condition_variable frame_cv_;
  std::shared_ptr<const Frame> frame_;  ///< the newest frame, guarded by frame_mutex_
};

/// A random token of 32 hex digits from the system's entropy source.
std::string generate_api_token();

}  // namespace fleet::server
