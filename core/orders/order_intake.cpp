#include "orders/order_intake.hpp"

#include <algorithm>

#include "common/errors.hpp"
#include "model/names.hpp"
#include "orders/packing_chain.hpp"
#include "orders/transport_areas.hpp"

namespace fleet::orders {

void fill_steps(Order& order, const KnownNames& names) {
  order.steps =
      steps_of({std::string(to_string(order.kind)), order.pick_area, order.drop_area, "", "", order.priority}, names);
}

std::optional<std::string> why_unseen(const std::string& robot_id, const std::set<std::string>& registered) {
  if (registered.contains(robot_id)) return std::nullopt;
  std::string why = "robot ";
  why += robot_id;
  why += " is configured but has not been seen: no fleet-agent --id ";
  why += robot_id;
  why += " has reported to this server";
  if (!registered.empty()) {
    why += " (seen: ";
    why += model::join(std::vector<std::string>(registered.begin(), registered.end()));
    why += ")";
  }
  return why;
}

IntakeDecision OrderIntake::refuse(const model::OrderRequest& request, const std::string& error) {
  return {model::RequestReply{request.request_id, false, 0, error, 0}, {}};
}

IntakeDecision OrderIntake::decide(const model::OrderRequest& request) const {
  if (request.kind == "pick" && !request.lines.empty()) return decide_pick_list(request);
  const OrderRequestFields fields{request.kind,     request.pick_area, request.drop_area,
                                  request.robot_id, request.fleet_id,  request.priority};
  if (const auto problem = check_order_request(fields, view_.names)) {
    return refuse(request, problem->field + ": " + problem->message);
  }
  const OrderKind kind = kind_of(fields);
  if (!request.robot_id.empty()) {
    // An order for a robot that never reported would wait for it for good, unseen.
    if (const auto why = why_unseen(request.robot_id, view_.registered)) return refuse(request, *why);
  }
  const std::string error = kind == OrderKind::kMove
                                ? why_not_parking(request.drop_area, request.robot_id)
                                : why_not_transport(view_.ledger, view_.book, request.pick_area, request.drop_area);
  if (!error.empty()) return refuse(request, error);
  if (view_.reject_when_busy && view_.free_robots.empty()) {
    return refuse(request, "no robot is free (server.reject_when_busy is on)");
  }
  IntakeDecision decision{{request.request_id, true, 0, "", 1}, {}};
  decision.drafts.push_back(draft_of(request, kind));
  return decision;
}

Order OrderIntake::draft_of(const model::OrderRequest& request, OrderKind kind) const {
  Order draft;
  draft.kind = kind;
  draft.request_id = request.request_id;
  draft.pick_area = request.pick_area;
  draft.drop_area = request.drop_area;
  draft.fleet_id = request.fleet_id;
  draft.robot_id = request.robot_id;
  draft.robot_requested = !request.robot_id.empty();
  draft.priority = request.priority;
  fill_steps(draft, view_.names);
  return draft;
}

IntakeDecision OrderIntake::decide_pick_list(const model::OrderRequest& request) const {
  const std::string source = "pick list";
  std::vector<PickLine> lines;
  try {
    lines = parse_pick_lines(request.lines, source);
  } catch (const InputError& e) {
    return refuse(request, std::string("lines: ") + e.what());
  }
  const std::variant<bool, std::string> loader = loader_handling(request);
  if (const auto* why = std::get_if<std::string>(&loader)) return refuse(request, "handling: " + *why);
  const bool as_loader = std::get<bool>(loader);
  // The order's places and fleet as a pick from the first line's place.
  const OrderRequestFields fields{request.kind,     lines.front().place, request.drop_area, request.robot_id,
                                  request.fleet_id, request.priority,    as_loader};
  if (const auto problem = check_order_request(fields, view_.names)) {
    return refuse(request, problem->field + ": " + problem->message);
  }
  if (!request.robot_id.empty()) {
    if (const auto why = why_unseen(request.robot_id, view_.registered)) return refuse(request, *why);
  }
  if (const auto why = check_pick_lines(lines, view_.site.area_ids(), boxes_left(), view_.max_pickable_mass, source)) {
    return refuse(request, "lines: " + *why);
  }
  if (as_loader) return {{request.request_id, true, 0, "", 1}, {loader_order(lines, request)}};
  IntakeDecision decision{{request.request_id, true, 0, "", 0}, pick_tours(lines, request)};
  decision.reply.order_count = static_cast<int>(decision.drafts.size());
  return decision;
}

std::vector<Order> OrderIntake::pick_tours(const std::vector<PickLine>& lines,
                                           const model::OrderRequest& request) const {
  std::vector<Order> drafts;
  // The boxes the earlier tours bring to each station: they count against its pallet's room
  // although they are not in the book yet.
  std::map<std::string, int> drafted_boxes;
  for (const auto& tour : plan_tours(lines, kTourBoxes, place_poses(view_.site))) {
    Order draft;
    draft.kind = OrderKind::kPick;
    draft.request_id = request.request_id;
    draft.pick_area = tour.lines.front().place;
    // A packing pallet without room for the tour's boxes sends the tour on to the next one.
    draft.drop_area = view_.site.packing ? station_for_tour(*view_.site.packing, view_.ledger, view_.book,
                                                            request.drop_area, tour.boxes(), drafted_boxes)
                                         : request.drop_area;
    drafted_boxes[draft.drop_area] += tour.boxes();
    draft.lines = pick_lines_csv(tour.lines);
    draft.fleet_id = request.fleet_id;
    draft.robot_id = request.robot_id;
    draft.robot_requested = !request.robot_id.empty();
    draft.priority = request.priority;
    fill_steps(draft, view_.names);
    drafts.push_back(std::move(draft));
  }
  return drafts;
}

std::string loader_fleet(const config::FleetConfig& config) {
  for (const auto& fleet : config.fleets) {
    if (fleet.robot_type == "stacker") return fleet.id;
  }
  return "";
}

std::variant<bool, std::string> OrderIntake::loader_handling(const model::OrderRequest& request) const {
  const std::string& handling = request.handling;
  if (handling.empty() || handling == "tray") return false;
  if (handling != "loader" && handling != "auto") {
    return "unknown handling '" + handling + "': tray (to a packing station), loader or auto";
  }
  const bool possible = !view_.loader_fleet.empty() && view_.site.packing &&
                        !view_.site.packing->empty_pallets_from.empty() && !view_.site.packing->full_pallets_to.empty();
  if (handling == "loader") {
    if (!possible) {
      return std::string(
                 "a loader walk needs a stacker fleet and a site with empty pallet places and expedition "
                 "places (packing: empty_pallets_from, full_pallets_to); site '") +
             view_.site.name + "' or its fleets lack them";
    }
    return true;
  }
  if (!possible) return false;
  // auto: a loader walk when a transporter is free and an empty pallet stands for it.
  const bool transporter_free = std::any_of(view_.free_robots.begin(), view_.free_robots.end(), [&](const auto& id) {
    const auto fleet = view_.names.fleet_of_robot.find(id);
    return fleet != view_.names.fleet_of_robot.end() && fleet->second == view_.loader_fleet;
  });
  const bool pallet_free =
      std::any_of(view_.site.packing->empty_pallets_from.begin(), view_.site.packing->empty_pallets_from.end(),
                  [&](const std::string& place) { return view_.ledger.holds_load(place); });
  return transporter_free && pallet_free;
}

Order OrderIntake::loader_order(const std::vector<PickLine>& lines, const model::OrderRequest& request) const {
  const auto poses = place_poses(view_.site);
  const PlaceDistance straight = [&](const std::string& from, const std::string& to) {
    return geometry::distance(poses.at(from).position(), poses.at(to).position());
  };
  const std::vector<PickLine> walk =
      loader_walk(lines, view_.loader_pallet_boxes, poses, view_.place_distance ? view_.place_distance : straight);
  Order draft;
  draft.kind = OrderKind::kPick;
  draft.request_id = request.request_id;
  draft.pick_area = walk.front().place;
  draft.lines = pick_lines_csv(walk);
  draft.fleet_id = request.fleet_id;
  draft.robot_id = request.robot_id;
  draft.robot_requested = !request.robot_id.empty();
  draft.priority = request.priority;
  draft.loader = true;
  fill_steps(draft, view_.names);
  return draft;
}

std::map<std::string, map::BoxStock> OrderIntake::boxes_left() const {
  std::map<std::string, map::BoxStock> left = declared_boxes(view_.site);
  // Every pick order not failed nor cancelled has its boxes: taken already, or promised.
  for (const auto& [id, order] : view_.book.all()) {
    if (order.kind != OrderKind::kPick || order.status == OrderStatus::kFailed ||
        order.status == OrderStatus::kCancelled) {
      continue;
    }
    std::string source = "order ";
    source += std::to_string(id);
    for (const auto& line : parse_pick_lines(order.lines, source)) {
      if (auto it = left.find(line.place); it != left.end())
        it->second.count = std::max(0, it->second.count - line.quantity);
    }
  }
  return left;
}

std::string OrderIntake::why_not_parking(const std::string& place, const std::string& robot_id) const {
  // A robot that has not reported stands nowhere yet: its configured home is free to park at.
  for (const auto& [robot, parked] : view_.parked_at) {
    if (parked == place && robot != robot_id && view_.registered.contains(robot)) {
      return "parking place '" + place + "' is " + robot + "'s";
    }
  }
  for (const auto& [id, o] : view_.book.all()) {
    if (!is_final(o.status) && o.kind == OrderKind::kMove && o.drop_area == place) {
      return "parking place '" + place + "' is promised to order " + std::to_string(id) + ", which goes there";
    }
  }
  return "";
}

}  // namespace fleet::orders
