#include "orders/auto_orders.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <set>
#include <utility>

#include "orders/dispatch.hpp"
#include "orders/packing_chain.hpp"
#include "orders/pick_lines.hpp"
#include "orders/transport_areas.hpp"

namespace fleet::orders {

namespace {

/// A rack row: a rack of the site and the way its places face (the lane they are worked from).
using RackRow = std::pair<std::size_t, long>;

std::optional<std::size_t> rack_at(const map::Site& site, geometry::Vec2 point) {
  for (std::size_t r = 0; r < site.racks.size(); ++r) {
    if (geometry::contains(site.racks[r].polygon, point)) return r;
  }
  return std::nullopt;
}

/// The rack row of a place: the rack it stands in and the quarter it faces.
std::optional<RackRow> rack_row_of(const map::Site& site, const std::string& place,
                                   const std::map<std::string, geometry::Pose2>& poses) {
  const auto pose = poses.find(place);
  if (pose == poses.end()) return std::nullopt;
  const auto rack = rack_at(site, pose->second.position());
  if (!rack) return std::nullopt;
  const long quarter = std::lround(geometry::normalize_angle(pose->second.yaw) / (std::numbers::pi / 2.0));
  return RackRow{*rack, (quarter % 4 + 4) % 4};
}

/// The rack row of a place, and the row facing it across its aisle (the rack that lies within
/// kAisleM ahead of it): a robot standing in the aisle is in the way of both rows' lanes.
std::vector<RackRow> aisle_rows_of(const map::Site& site, const std::string& place,
                                   const std::map<std::string, geometry::Pose2>& poses) {
  constexpr double kAisleM = 6.0, kStepM = 0.25;
  const auto own = rack_row_of(site, place, poses);
  if (!own) return {};
  std::vector<RackRow> rows{*own};
  const geometry::Pose2& pose = poses.at(place);
  const geometry::Vec2 ahead{std::cos(pose.yaw), std::sin(pose.yaw)};
  for (double d = kStepM; d <= kAisleM; d += kStepM) {
    const auto across = rack_at(site, {pose.x + d * ahead.x, pose.y + d * ahead.y});
    if (across && *across != own->first) {
      rows.push_back({*across, (own->second + 2) % 4});
      break;
    }
  }
  return rows;
}

/// The rack rows of the aisles of open orders' places: of every open loader walk's lines, and with
/// `every_order` of every other open order's pick and drop places too.
std::set<RackRow> rows_in_work(const IntakeView& view, const std::map<std::string, geometry::Pose2>& poses,
                               bool every_order) {
  std::set<RackRow> rows;
  const auto add = [&](const std::string& place) {
    for (const RackRow& row : aisle_rows_of(view.site, place, poses)) rows.insert(row);
  };
  for (const Order* open : view.book.open_orders()) {
    if (open->loader && open->kind == OrderKind::kPick) {
      for (const PickLine& line : parse_pick_lines(open->lines, "order " + std::to_string(open->id))) add(line.place);
    } else if (every_order) {
      add(open->pick_area);
      add(open->drop_area);
    }
  }
  return rows;
}

bool in_rows(const map::Site& site, const std::string& place, const std::map<std::string, geometry::Pose2>& poses,
             const std::set<RackRow>& rows) {
  const auto row = rack_row_of(site, place, poses);
  return row && rows.contains(*row);
}

}  // namespace

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
  const auto stock = intake.boxes_left();
  std::optional<std::vector<PickLine>> lines;
  if (loader) {
    // One loader pair to an aisle: a second pair in the same one-way lane could not pass the
    // first, nor its transporter. An aisle where no other open order has a place comes first (a
    // robot bound there would wait before the lane the transporter closes); when every aisle has
    // one, any aisle no other walk works.
    for (const bool every_order : {true, false}) {
      auto free_stock = stock;
      const auto taken = rows_in_work(view, poses, every_order);
      std::erase_if(free_stock, [&](const auto& entry) { return in_rows(view.site, entry.first, poses, taken); });
      lines = choose_auto_pick_list(free_stock, poses, view.max_pickable_mass, boxes, rng_);
      if (lines) break;
    }
  } else {
    lines = choose_auto_pick_list(stock, poses, view.max_pickable_mass, boxes, rng_);
  }
  if (!lines) return {};
  if (loader) return {intake.loader_order(*lines, request)};
  request.drop_area = view.site.packing->stations.front();
  return intake.pick_tours(*lines, request);
}

std::optional<Order> AutoOrders::transport(const IntakeView& view) {
  if (!auto_transport_wanted(view.book, free_for(view, OrderKind::kTransport))) return std::nullopt;
  // Nor to or from a rack row a loader pair works: its transporter closes the one-way lane behind
  // it, and a robot bound for a place past it would wait on the road before the lane, in the way
  // of the picker coming to its stop.
  const auto poses = place_poses(view.site);
  const auto worked = rows_in_work(view, poses, /*every_order=*/false);
  const auto doable = [&](const std::string& pick, const std::string& drop) {
    if (in_rows(view.site, pick, poses, worked) || in_rows(view.site, drop, poses, worked)) return false;
    if (view.reserved.contains(drop)) return false;
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
