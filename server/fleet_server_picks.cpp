// Pick orders by lines: a pick list checked whole against what the rack places hold, then cut into
// the tours a picker drives, one order each.
#include <algorithm>

#include "common/errors.hpp"
#include "orders/packing_chain.hpp"
#include "orders/pick_lines.hpp"
#include "server/fleet_server.hpp"

namespace fleet::server {

std::map<std::string, map::BoxStock> FleetServer::boxes_left() const {
  std::map<std::string, map::BoxStock> left = orders::declared_boxes(options_.site);
  // Every pick order not failed nor cancelled has its boxes: taken already, or promised.
  for (const auto& [id, order] : book_.all()) {
    if (order.kind != orders::OrderKind::kPick || order.status == orders::OrderStatus::kFailed ||
        order.status == orders::OrderStatus::kCancelled) {
      continue;
    }
    for (const auto& line : orders::parse_pick_lines(order.lines, "order " + std::to_string(id))) {
      if (auto it = left.find(line.place); it != left.end())
        it->second.count = std::max(0, it->second.count - line.quantity);
    }
  }
  return left;
}

model::RequestReply FleetServer::execute_pick_list(const model::OrderRequest& request) {
  auto refuse = [&](const std::string& error) {
    log_->warn("order request {} refused: {}", request.request_id, error);
    return model::RequestReply{request.request_id, false, 0, error, 0};
  };
  const std::string source = "pick list";
  std::vector<orders::PickLine> lines;
  try {
    lines = orders::parse_pick_lines(request.lines, source);
  } catch (const InputError& e) {
    return refuse(std::string("lines: ") + e.what());
  }
  // The order's places and fleet as a pick from the first line's place.
  const orders::OrderRequestFields fields{request.kind,     lines.front().place, request.drop_area,
                                          request.robot_id, request.fleet_id,    request.priority};
  if (const auto problem = orders::check_order_request(fields, known_names())) {
    return refuse(problem->field + ": " + problem->message);
  }
  if (!request.robot_id.empty()) {
    if (const auto why = not_seen(request.robot_id)) return refuse(*why);
  }
  if (const auto why = orders::check_pick_lines(lines, options_.site.area_ids(), boxes_left(),
                                                orders::max_pickable_mass(options_.config), source)) {
    return refuse("lines: " + *why);
  }
  const auto [first, tours] = create_pick_tours(lines, request);
  return {request.request_id, true, first, "", tours};
}

std::pair<std::int64_t, int> FleetServer::create_pick_tours(const std::vector<orders::PickLine>& lines,
                                                            const model::OrderRequest& request) {
  const auto tours = orders::plan_tours(lines, orders::kTourBoxes, orders::place_poses(options_.site));
  std::int64_t first = 0;
  for (const auto& tour : tours) {
    orders::Order draft;
    draft.kind = orders::OrderKind::kPick;
    draft.request_id = request.request_id;
    draft.pick_area = tour.lines.front().place;
    // A packing pallet without room for the tour's boxes sends the tour on to the next one.
    draft.drop_area = options_.site.packing ? orders::station_for_tour(*options_.site.packing, ledger_, book_,
                                                                       request.drop_area, tour.boxes())
                                            : request.drop_area;
    draft.lines = orders::pick_lines_csv(tour.lines);
    draft.fleet_id = request.fleet_id;
    draft.robot_id = request.robot_id;
    draft.robot_requested = !request.robot_id.empty();
    draft.priority = request.priority;
    fill_steps(draft);
    const orders::Order& order = book_.create(std::move(draft), clock_.now());
    if (first == 0) first = order.id;
    log_->info("order {} created: pick tour of {} box{} from {} line{} to {} (request {})", order.id, tour.boxes(),
               tour.boxes() == 1 ? "" : "es", tour.lines.size(), tour.lines.size() == 1 ? "" : "s", order.drop_area,
               order.request_id);
    publish_order(order);
  }
  return {first, static_cast<int>(tours.size())};
}

void FleetServer::create_auto_pick(long free_pickers) {
  // The pick lists a warehouse system would send, one tour per free picker: boxes from the racks to
  // the packing stations, whose full pallets then go on to expedition by the packing chain.
  if (!options_.site.packing || options_.site.packing->stations.empty()) return;
  const auto queue = book_.with_status(orders::OrderStatus::kQueued);
  const long queued = std::count_if(queue.begin(), queue.end(),
                                    [](const orders::Order* o) { return o->kind == orders::OrderKind::kPick; });
  if (free_pickers <= queued) return;
  const auto lines =
      orders::choose_auto_pick_list(boxes_left(), orders::place_poses(options_.site),
                                    orders::max_pickable_mass(options_.config), orders::kTourBoxes, rng_);
  if (!lines) return;
  model::OrderRequest request;
  request.request_id = "auto";
  request.kind = "pick";
  request.drop_area = options_.site.packing->stations.front();
  create_pick_tours(*lines, request);
}

void FleetServer::advance_packing_chain() {
  if (!options_.site.packing || !chain_stale_) return;
  chain_stale_ = false;
  // Each transport is created before the next is looked for; a handful per cycle at most.
  for (int i = 0; i < 4; ++i) {
    auto due = orders::next_chain_transport(*options_.site.packing, ledger_, book_);
    if (!due) return;
    orders::Order draft;
    draft.request_id = "packing";
    draft.pick_area = due->pick;
    draft.drop_area = due->drop;
    draft.cause = std::move(due->cause);
    draft.caused_by = std::move(due->caused_by);
    fill_steps(draft);
    const orders::Order& order = book_.create(std::move(draft), clock_.now());
    log_->info("order {} created: {} -> {}, {}", order.id, order.pick_area, order.drop_area, order.cause);
    publish_order(order);
  }
}

}  // namespace fleet::server
