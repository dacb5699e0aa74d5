#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>

#include "config/fleet_config.hpp"
#include "map/site_map.hpp"
#include "model/messages.hpp"
#include "orders/order.hpp"
#include "orders/site_state.hpp"
#include "server/web_bridge.hpp"

namespace fleet::server {

/// What a standby's web view shows: the orders and the site's state it mirrors and the robots as
/// they report, read-only. Requests that would change anything are answered with a refusal that
/// names the active server, which takes them.
class StandbyView {
 public:
  struct Site {
    std::shared_ptr<const map::SiteMap> site_map;
    const config::FleetConfig* config = nullptr;  ///< must outlive the view
    double time_scale = 1.0;
    std::string server_id;  ///< this standby
  };

  StandbyView(WebBridge& bridge, Site site);

  /// An order as mirrored (orders::order_of of its OrderInfo).
  void order(const orders::Order& order);
  /// The site's state as the active server wrote it (orders::to_json); a document this site cannot
  /// read is left out with `problem` set.
  void site_state(const std::string& json);
  void robot(const model::RobotState& state, double now_wall);
  void active_server(const std::string& id) { active_id_ = id; }

  /// Publishes a snapshot (at most 5 a second, wall) and answers every waiting request.
  void serve(double now_wall);

  /// The last site state that could not be read, for the log (empty when none).
  const std::string& problem() const { return problem_; }

 private:
  void publish(double now_wall);
  void refuse_requests();

  struct Heard {
    model::RobotState state;
    double wall = 0.0;
  };

  WebBridge& bridge_;
  Site site_;
  std::shared_ptr<const orders::KnownNames> known_names_;
  orders::SiteNames site_names_;  ///< what the site states are read against
  std::map<std::int64_t, orders::Order> orders_;
  std::map<std::string, Heard> robots_;
  std::map<std::string, bool> obstacle_enabled_;
  std::map<std::string, bool> pallet_at_;
  std::string active_id_;
  std::string problem_;
  double sim_time_ = 0.0;
  double last_published_wall_ = 0.0;
};

}  // namespace fleet::server
