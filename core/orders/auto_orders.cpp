#include "orders/auto_orders.hpp"

#include <algorithm>

#include "orders/dispatch.hpp"
#include "orders/packing_chain.hpp"
#include "orders/pick_lines.hpp"
#include "orders/transport_areas.hpp"

namespace fleet::orders {

bool AutoOrders::due(double now_wall) {
  if (!on_ || now_wall - last_round_wall_ < kPeriodWallS) return false;
  last_round_wall_ = now_wall;
  return true;
}

long AutoOrders::free_for(const IntakeView& view, OrderKind kind) {
  const auto& abilities = view.names.abilities;
  const auto can = [&](const std::string& robot_id) {
    // Without abilities (a configuration that names none) every robot carries loads and nothing else.
    if (abilities.empty()) return kind == OrderKind::kTransport;
    const auto fleet = view.names.fleet_of_robot.find(robot_id);
    if (fleet == view.names.fleet_of_robot.end()) return false;
    const FleetAbility* ability = ability_of(abilities, fleet->second);
    return ability && !incapability(*ability, order_steps(kind, "", "")).has_value();
  };
  return std::count_if(view.free_robots.begin(), view.free_robots.end(), can);
}

std::vector<Order> AutoOrders::pick_tours(const IntakeView& view) {
  // The pick lists a warehouse system would send, one tour per free picker: boxes from the racks to
  // the packing stations, whose full pallets then go on to expedition by the packing chain.
  if (!view.site.packing || view.site.packing->stations.empty()) return {};
  const long free_pickers = free_for(view, OrderKind::kPick);
  if (free_pickers == 0) return {};
  const auto queue = view.book.with_status(OrderStatus::kQueued);
  const long queued =
      std::count_if(queue.begin(), queue.end(), [](const Order* o) { return o->kind == OrderKind::kPick; });
  if (free_pickers <= queued) return {};
  const OrderIntake intake(view);
  model::OrderRequest request;
  request.request_id = "auto";
  request.kind = "pick";
  request.handling = handling_;
  const auto as_loader = intake.loader_handling(request);
  const bool loader = std::holds_alternative<bool>(as_loader) && std::get<bool>(as_loader);
  // A loader walk fills a few pallets; a tray tour carries what the tray holds.
  const int boxes = loader ? kLoaderWalkBoxes : kTourBoxes;
  const auto poses = place_poses(view.site);
  auto stock = intake.boxes_left();
  if (loader) {
    // One loader pair to a rack row: a second pair in the same one-way lane could not pass the
    // first, and neither could its transporter.
    std::vector<geometry::Pose2> worked;
    for (const Order* open : view.book.open_orders()) {
      if (!open->loader || open->kind != OrderKind::kPick) continue;
      for (const PickLine& line : parse_pick_lines(open->lines, "order " + std::to_string(open->id))) {
        if (const auto pose = poses.find(line.place); pose != poses.end()) worked.push_back(pose->second);
      }
    }
    std::erase_if(stock, [&](const auto& entry) {
      const auto pose = poses.find(entry.first);
      return pose != poses.end() && std::any_of(worked.begin(), worked.end(), [&](const geometry::Pose2& other) {
               return same_rack_row(pose->second, other);
             });
    });
  }
  const auto lines = choose_auto_pick_list(stock, poses, view.max_pickable_mass, boxes, rng_);
  if (!lines) return {};
  if (loader) return {intake.loader_order(*lines, request)};
  request.drop_area = view.site.packing->stations.front();
  return intake.pick_tours(*lines, request);
}

std::optional<Order> AutoOrders::transport(const IntakeView& view) {
  if (!auto_transport_wanted(view.book, free_for(view, OrderKind::kTransport))) return std::nullopt;
  const auto doable = [&](const std::string& pick, const std::string& drop) {
    if (const auto& packing = view.site.packing;
        packing && (!open_to_random_transports(*packing, pick) || !open_to_random_transports(*packing, drop))) {
      return false;
    }
    return !check_order_request({"", pick, drop, "", "", 0}, view.names).has_value();
  };
  const auto choice = choose_auto_transport(view.ledger, view.book, rng_, doable);
  if (!choice) return std::nullopt;
  Order draft;
  draft.request_id = "auto";
  draft.pick_area = choice->pick;
  draft.drop_area = choice->drop;
  fill_steps(draft, view.names);
  return draft;
}

}  // namespace fleet::orders
