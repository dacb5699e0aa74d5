#include "orders/dispatch.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "orders/hungarian.hpp"

namespace fleet::orders {

bool robot_id_less(const std::string& a, const std::string& b) {
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (std::isdigit(static_cast<unsigned char>(a[i])) && std::isdigit(static_cast<unsigned char>(b[j]))) {
      std::size_t i2 = i, j2 = j;
      while (i2 < a.size() && std::isdigit(static_cast<unsigned char>(a[i2]))) ++i2;
      while (j2 < b.size() && std::isdigit(static_cast<unsigned char>(b[j2]))) ++j2;
      const std::string na = a.substr(i, i2 - i), nb = b.substr(j, j2 - j);
      if (na.size() != nb.size()) return na.size() < nb.size();
      if (na != nb) return na < nb;
      i = i2;
      j = j2;
    } else {
      if (a[i] != b[j]) return a[i] < b[j];
      ++i;
      ++j;
    }
  }
  return a.size() - i < b.size() - j;
}

const FleetAbility* ability_of(const std::vector<FleetAbility>& abilities, const std::string& fleet_id) {
  const auto ability =
      std::find_if(abilities.begin(), abilities.end(), [&](const FleetAbility& a) { return a.fleet_id == fleet_id; });
  return ability == abilities.end() ? nullptr : &*ability;
}

bool eligible(const Order& order, const FreeRobot& robot) {
  if (order.robot_requested && order.robot_id != robot.id) return false;
  if (!order.fleet_id.empty() && order.fleet_id != robot.fleet_id) return false;
  return !incapability(robot.ability, order.steps).has_value();
}

namespace {

void sort_robots(std::vector<FreeRobot>& robots) {
  std::sort(robots.begin(), robots.end(),
            [](const FreeRobot& a, const FreeRobot& b) { return robot_id_less(a.id, b.id); });
}

/// [Forklift thesis, section 3]: "Orders are sent to the forklifts based on ascending order of forklift id."
class AscendingIdPolicy final : public DispatchPolicy {
 public:
  std::vector<Assignment> assign(const std::vector<const Order*>& queue, std::vector<FreeRobot> robots,
                                 const TravelCost& cost) const override {
    sort_robots(robots);
    std::vector<Assignment> out;
    for (const Order* order : queue) {
      for (auto it = robots.begin(); it != robots.end(); ++it) {
        if (eligible(*order, *it) && std::isfinite(cost(it->id, order->first_place()))) {
          out.push_back({order->id, it->id});
          robots.erase(it);
          break;
        }
      }
    }
    return out;
  }
};

/// Each order in queue order takes the free robot with the least travel cost to its pick area.
class NearestPolicy final : public DispatchPolicy {
 public:
  std::vector<Assignment> assign(const std::vector<const Order*>& queue, std::vector<FreeRobot> robots,
                                 const TravelCost& cost) const override {
    sort_robots(robots);  // ties go to the lower id
    std::vector<Assignment> out;
    for (const Order* order : queue) {
      auto best = robots.end();
      double best_cost = std::numeric_limits<double>::infinity();
      for (auto it = robots.begin(); it != robots.end(); ++it) {
        if (!eligible(*order, *it)) continue;
        const double c = cost(it->id, order->first_place());
        if (c < best_cost) {
          best_cost = c;
          best = it;
        }
      }
      if (best != robots.end()) {
        out.push_back({order->id, best->id});
        robots.erase(best);
      }
    }
    return out;
  }
};

/// Minimum total travel cost over the first orders of the queue (as many as there are robots),
/// by the Hungarian algorithm.
class OptimalPolicy final : public DispatchPolicy {
 public:
  std::vector<Assignment> assign(const std::vector<const Order*>& queue, std::vector<FreeRobot> robots,
                                 const TravelCost& cost) const override {
    sort_robots(robots);
    // The first orders some free robot can take, as many as there are robots: an order no free
    // robot's fleet can do must not hold a slot another order could use.
    std::vector<const Order*> head;
    for (const Order* order : queue) {
      if (head.size() == robots.size()) break;
      if (std::any_of(robots.begin(), robots.end(), [&](const FreeRobot& r) { return eligible(*order, r); })) {
        head.push_back(order);
      }
    }
    if (head.empty()) return {};
    std::vector<std::vector<double>> matrix(head.size(), std::vector<double>(robots.size(), kForbidden));
    for (std::size_t i = 0; i < head.size(); ++i) {
      for (std::size_t j = 0; j < robots.size(); ++j) {
        if (!eligible(*head[i], robots[j])) continue;
        const double c = cost(robots[j].id, head[i]->first_place());
        if (std::isfinite(c)) matrix[i][j] = c;
      }
    }
    const std::vector<int> match = hungarian_assignment(matrix);
    std::vector<Assignment> out;
    for (std::size_t i = 0; i < head.size(); ++i) {
      if (match[i] >= 0) out.push_back({head[i]->id, robots[static_cast<std::size_t>(match[i])].id});
    }
    return out;
  }
};

}  // namespace

std::unique_ptr<DispatchPolicy> make_dispatch_policy(std::string_view name) {
  if (name == "ascending-id") return std::make_unique<AscendingIdPolicy>();
  if (name == "nearest") return std::make_unique<NearestPolicy>();
  if (name == "optimal") return std::make_unique<OptimalPolicy>();
  throw std::invalid_argument("unknown dispatch policy '" + std::string(name) + "' (ascending-id, nearest, optimal)");
}

}  // namespace fleet::orders
