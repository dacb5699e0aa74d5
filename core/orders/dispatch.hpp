#pragma once

#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "orders/order.hpp"

namespace fleet::orders {

struct FreeRobot {
  FreeRobot(std::string robot_id, std::string fleet, FleetAbility fleet_ability = {})
      : id(std::move(robot_id)), fleet_id(std::move(fleet)), ability(std::move(fleet_ability)) {}
  std::string id;
  std::string fleet_id;
  FleetAbility ability;  ///< what its fleet can do; orders it cannot do are not offered to it
};

struct Assignment {
  std::int64_t order_id = 0;
  std::string robot_id;
};

/// Travel cost from a robot's position to the first place of an order (road-graph metres, on the
/// robot's fleet's lanes); +inf when the robot cannot get there.
using TravelCost = std::function<double(const std::string& robot_id, const std::string& area_id)>;

/// Matches queued orders with free robots. One small interface; policies chosen by name in
/// config (`server.dispatch_policy`).
class DispatchPolicy {
 public:
  virtual ~DispatchPolicy() = default;
  /// `queue` is in dispatch order (priority, then age). Each robot gets at most one order.
  virtual std::vector<Assignment> assign(const std::vector<const Order*>& queue, std::vector<FreeRobot> free_robots,
                                         const TravelCost& cost) const = 0;
};

/// "ascending-id" [Forklift thesis, section 3], "nearest", "optimal" (Hungarian); throws
/// std::invalid_argument for other names.
std::unique_ptr<DispatchPolicy> make_dispatch_policy(std::string_view name);

/// Natural order of robot ids, so that fl2 comes before fl10.
bool robot_id_less(const std::string& a, const std::string& b);

/// The ability of fleet `fleet_id` among `abilities`, nullptr when it has none.
const FleetAbility* ability_of(const std::vector<FleetAbility>& abilities, const std::string& fleet_id);

/// Whether `robot` may take `order`: its fleet can perform every step's actions (at their
/// heights), and a requested robot or fleet, if any, is it.
bool eligible(const Order& order, const FreeRobot& robot);

}  // namespace fleet::orders
