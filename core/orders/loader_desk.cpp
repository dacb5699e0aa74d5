#include "orders/loader_desk.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "orders/pick_lines.hpp"

namespace fleet::orders {

geometry::Pose2 picker_stop_pose(const geometry::Pose2& place, double standoff) {
  return {place.x + standoff * std::cos(place.yaw), place.y + standoff * std::sin(place.yaw),
          geometry::normalize_angle(place.yaw + std::numbers::pi / 2)};
}

bool moving_up_straight(const geometry::Pose2& from, const geometry::Pose2& to, const geometry::Pose2& now,
                        double distance) {
  constexpr double kOnLine = 0.05;       // m across the line: the stands of one rack row
  constexpr double kNearLine = 0.30;     // m across the line: a stacker driving along it
  constexpr double kSameHeading = 0.05;  // rad
  const double cx = std::cos(from.yaw);
  const double sy = std::sin(from.yaw);
  const auto along = [&](const geometry::Pose2& p) { return (p.x - from.x) * cx + (p.y - from.y) * sy; };
  const auto across = [&](const geometry::Pose2& p) { return -(p.x - from.x) * sy + (p.y - from.y) * cx; };
  return std::abs(geometry::normalize_angle(to.yaw - from.yaw)) < kSameHeading && std::abs(across(to)) < kOnLine &&
         along(to) > distance && std::abs(across(now)) < kNearLine && along(now) >= distance && along(now) <= along(to);
}

void LoaderDesk::transport_created(const Order& transport) {
  for (const std::int64_t pick : transport.caused_by) {
    if (auto it = jobs_.find(pick); it != jobs_.end()) it->second.transports[transport.id] = {};
  }
}

const LoaderJob* LoaderDesk::job_of(std::int64_t pick_id) const {
  const auto it = jobs_.find(pick_id);
  return it == jobs_.end() ? nullptr : &it->second.job;
}

bool LoaderDesk::ready_for_picker(const Order& order) const {
  if (!order.loader || order.kind != OrderKind::kPick) return true;
  const auto it = jobs_.find(order.id);
  return it != jobs_.end() && it->second.pallet_ready;
}

std::map<std::string, std::string> LoaderDesk::partners() const {
  std::map<std::string, std::string> pairs;
  for (const auto& [id, entry] : jobs_) {
    // The one behind the picker, and one leaving from there: it starts beside the picker. A
    // transporter gone ahead to a stop no picker works yet pairs with none (empty): its lane closes
    // behind it to every robot until the picker comes.
    for (const PalletRun& run : entry.job.runs()) {
      if (!run.delivered && !run.lost) pairs[run.transporter_id] = entry.job.picker_id();
    }
  }
  return pairs;
}

std::set<std::string> LoaderDesk::reserved_places() const {
  std::set<std::string> places;
  for (const auto& [id, entry] : jobs_) {
    for (const auto& [order, transport] : entry.transports) {
      if (!transport.expedition.empty()) places.insert(transport.expedition);
    }
  }
  return places;
}

void LoaderDesk::keep_expedition_places(Entry& entry, const LoaderView& view) {
  if (!view.site.packing) return;
  for (auto& [id, transport] : entry.transports) {
    const Order* order = view.book.find(id);
    if (order == nullptr || is_final(order->status)) {
      transport.expedition.clear();
    } else if (transport.expedition.empty()) {
      transport.expedition = free_place(view.site.packing->full_pallets_to, false, view);
    }
  }
}

void LoaderDesk::adopt_transports(Entry& entry, std::int64_t pick_id, const LoaderView& view) const {
  // A desk that starts on a book with the job under way (a restarted server, a standby taking
  // over) takes on its open transports that still bring or hold a pallet for it: the stacker
  // with one joins the job again, as when it was assigned. One on its way to expedition ends on
  // its own.
  for (const Order* order : view.book.open_orders()) {
    if (order->kind != OrderKind::kTransport || !order->loader || !order->drop_area.empty()) continue;
    if (std::find(order->caused_by.begin(), order->caused_by.end(), pick_id) == order->caused_by.end()) continue;
    entry.transports[order->id] = {};
  }
}

std::vector<std::int64_t> LoaderDesk::jobs() const {
  std::vector<std::int64_t> ids;
  for (const auto& [id, entry] : jobs_) ids.push_back(id);
  return ids;
}

std::vector<LoaderAction> LoaderDesk::step(const LoaderView& view) {
  std::vector<LoaderAction> actions;
  std::vector<std::string> taken;  // places asked for in this look
  // A loader pick order's job begins with the order: its first pallet is fetched before a picker
  // has it (ready_for_picker).
  for (const Order* order : view.book.open_orders()) {
    if (!order->loader || order->kind != OrderKind::kPick || jobs_.contains(order->id)) continue;
    jobs_.emplace(order->id,
                  Entry{LoaderJob(parse_pick_lines(order->lines, "loader order " + std::to_string(order->id)),
                                  layout_.pallet_boxes, with_a_robot(order->status) ? order->robot_id : ""),
                        {},
                        false,
                        with_a_robot(order->status)});
    adopt_transports(jobs_.at(order->id), order->id, view);
  }
  for (auto it = jobs_.begin(); it != jobs_.end();) {
    Entry& entry = it->second;
    const Order* pick = view.book.find(it->first);
    if (pick == nullptr) {
      it = jobs_.erase(it);
      continue;
    }
    take_picker_facts(entry, *pick, view);
    take_transport_facts(entry, view);
    keep_expedition_places(entry, view);
    if (entry.job.done()) {
      it = jobs_.erase(it);
      continue;
    }
    ask_for_transporter(entry, *pick, view, actions, taken);
    revise_orders(entry, *pick, view, actions);
    ++it;
  }
  return actions;
}

void LoaderDesk::take_picker_facts(Entry& entry, const Order& pick, const LoaderView& view) const {
  LoaderJob& job = entry.job;
  if (is_final(pick.status)) {
    if (entry.ended) return;
    entry.ended = true;
    // DONE: the walk ends at its last stop, every box on a pallet. FAILED or CANCELLED: the stops
    // not loaded are left, their boxes at their places. Either way the pallets go to expedition.
    while (!job.all_loaded()) {
      const int stop = job.next_stop();
      const int left = job.left_at(stop);
      if (pick.status == OrderStatus::kDone && left <= job.room()) {
        job.loaded(stop, left);
      } else {
        job.stop_failed(stop);
      }
    }
    return;
  }
  // Its first pallet on the forks, the walk went to a picker.
  if (job.picker_id().empty() && with_a_robot(pick.status) && !pick.robot_id.empty() && !job.all_loaded()) {
    job.add_picker(pick.robot_id);
  }
  const auto robot = view.robots.find(pick.robot_id);
  if (robot == view.robots.end() || pick.robot_id != job.picker_id()) return;
  const model::RobotState& state = robot->second.last;
  if (state.order_id != pick.id) return;
  if (state.walk_stop >= 0) job.picker_at(pick.robot_id, state.walk_stop);
  // Boxes the arm set on a pallet since the last look went on the stop under way: the picker
  // works only the stop released, and only with its transporter's pallet behind it.
  int fresh = state.boxes_loaded - job.boxes_loaded();
  while (fresh > 0 && !job.all_loaded()) {
    const int stop = job.next_stop();
    const int boxes = std::min({fresh, job.left_at(stop), job.room()});
    if (boxes <= 0) break;
    job.loaded(stop, boxes);
    fresh -= boxes;
  }
}

void LoaderDesk::take_transport_facts(Entry& entry, const LoaderView& view) const {
  LoaderJob& job = entry.job;
  for (auto& [id, transport] : entry.transports) {
    const Order* order = view.book.find(id);
    if (order == nullptr) continue;
    if (transport.robot_id.empty()) {
      if (!with_a_robot(order->status) || !job.wants_transporter()) continue;
      transport.robot_id = order->robot_id;
      job.add_transporter(transport.robot_id);
    }
    if (order->status == OrderStatus::kDone) {
      job.delivered(transport.robot_id);
      continue;
    }
    const auto robot = view.robots.find(transport.robot_id);
    const bool lost = robot != view.robots.end() && robot->second.lost;
    if (order->status == OrderStatus::kFailed || order->status == OrderStatus::kCancelled || lost) {
      job.robot_lost(transport.robot_id);
      continue;
    }
    // Standing with its pallet (HOLDING) where it was sent: behind the picker's stop.
    if (robot == view.robots.end() || !order->stand || transport.stand_stop < 0) continue;
    const model::RobotState& state = robot->second.last;
    if (transport.left_stand && transport.stand_stop == job.next_stop() &&
        moving_up_straight(*transport.left_stand, *order->stand, state.pose, layout_.follow_after_m)) {
      job.transporter_moving_up(transport.robot_id, transport.stand_stop);
    }
    if (state.task_state == "HOLDING" &&
        geometry::distance(state.pose.position(), order->stand->position()) < layout_.in_place_m) {
      job.transporter_in_place(transport.robot_id, transport.stand_stop);
    }
  }
  if (job.pallet_in_place()) entry.pallet_ready = true;
}

void LoaderDesk::ask_for_transporter(const Entry& entry, const Order& pick, const LoaderView& view,
                                     std::vector<LoaderAction>& actions, std::vector<std::string>& taken) const {
  if (!entry.job.wants_transporter() || is_final(pick.status)) return;
  // The next pallet is asked for once the current one has left: a stacker holding its empty
  // pallet at its PK place meanwhile keeps the PK row from the stackers behind it.
  if (!entry.job.current_transporter().empty()) return;
  for (const auto& [id, transport] : entry.transports) {
    const Order* order = view.book.find(id);
    if (order && transport.robot_id.empty() && !is_final(order->status)) return;  // asked already
  }
  if (!view.site.packing) return;
  const std::string source = free_place(view.site.packing->empty_pallets_from, true, view, {}, taken);
  if (source.empty()) return;  // asked again once an empty pallet stands free
  // Nor before its full pallet has a place to go (kept from the next look on).
  const std::string target = free_place(view.site.packing->full_pallets_to, false, view, {}, taken);
  if (target.empty()) return;
  // The drafts are not in the book before the server adds them: another job asking in this look
  // must not count the same places free.
  taken.push_back(source);
  taken.push_back(target);
  Order draft;
  draft.request_id = "loader";
  draft.kind = OrderKind::kTransport;
  draft.pick_area = source;
  draft.fleet_id = layout_.transporter_fleet;
  draft.loader = true;
  draft.priority = pick.priority + 1;  // the picker waits for it
  draft.cause = "pallet " + std::to_string(entry.job.runs().size() + 1) + " of loader order " + std::to_string(pick.id);
  draft.caused_by = {pick.id};
  actions.push_back({.kind = LoaderAction::Kind::kCreate, .draft = std::move(draft), .why = "an empty pallet"});
}

void LoaderDesk::revise_orders(Entry& entry, const Order& pick, const LoaderView& view,
                               std::vector<LoaderAction>& actions) const {
  const LoaderJob& job = entry.job;
  const auto revise = [&](const Order& order, const OrderRevision& revision, std::string why) {
    if (with_a_robot(order.status) && revision != revision_of(order)) {
      actions.push_back(
          {.kind = LoaderAction::Kind::kRevise, .order_id = order.id, .revision = revision, .why = std::move(why)});
    }
  };
  const auto stand_behind = [&](int stop) {
    const map::LoadingArea* place = view.site.find_area(job.walk().at(stop).place);
    const geometry::Pose2 picker = picker_stop_pose(place->pose, layout_.item_standoff);
    return transporter_pose(picker, layout_.deck_x, layout_.pallet_x);
  };
  for (const LoaderInstruction& instruction : job.instructions()) {
    if (instruction.robot_id == job.picker_id() && !is_final(pick.status)) {
      // The stop is released once its pallet stands behind it; the pallet named is the one behind
      // the picker or on its way there (none between two transporters: the picker makes way).
      OrderRevision revision = revision_of(pick);
      const bool released = instruction.task == LoaderTask::kLoad || instruction.task == LoaderTask::kGoToStop;
      if (released) revision.released_stops = std::max<std::uint32_t>(revision.released_stops, instruction.stop + 1);
      // Open to approach only while its pallet moves up ahead of it: taken back when that changes.
      revision.approach_stops =
          instruction.task == LoaderTask::kApproach ? static_cast<std::uint32_t>(instruction.stop + 1) : 0;
      revision.pallet = 0;
      for (const auto& [id, transport] : entry.transports) {
        if (!transport.robot_id.empty() && transport.robot_id == job.current_transporter()) {
          revision.pallet = static_cast<int>(id);
        }
      }
      revise(pick, revision,
             released ? "stop " + std::to_string(instruction.stop + 1) + " released"
             : revision.approach_stops > 0
                 ? "stop " + std::to_string(instruction.stop + 1) + " open to follow its pallet moving up"
                 : "the pallet behind it changed");
      continue;
    }
    for (auto& [id, transport] : entry.transports) {
      const Order* order = view.book.find(id);
      if (transport.robot_id != instruction.robot_id || order == nullptr || is_final(order->status)) continue;
      OrderRevision revision = revision_of(*order);
      std::string why;
      switch (instruction.task) {
        case LoaderTask::kFollow:
          if (transport.stand_stop != instruction.stop) transport.left_stand = revision.stand;
          revision.stand = stand_behind(instruction.stop);
          transport.stand_stop = instruction.stop;
          why = "stand behind the picker at " + job.walk().at(instruction.stop).place;
          break;
        case LoaderTask::kDeliver:
        case LoaderTask::kRelease: {
          if (!view.site.packing) continue;
          // A full pallet goes to expedition; an empty one, not needed after all, goes back.
          const bool full = instruction.task == LoaderTask::kDeliver;
          if (revision.drop_area.empty()) {
            revision.drop_area = full
                                     ? free_place(view.site.packing->full_pallets_to, false, view, transport.expedition)
                                     : free_place(view.site.packing->empty_pallets_from, false, view);
          }
          if (revision.drop_area.empty()) continue;  // once a place is free
          revision.stand.reset();
          transport.stand_stop = -1;
          int boxes = 0;
          for (const PalletRun& run : job.runs()) {
            if (run.transporter_id == instruction.robot_id && !run.delivered && !run.lost) boxes = run.boxes;
          }
          why = full ? "deliver the pallet (" + std::to_string(boxes) + (boxes == 1 ? " box" : " boxes") + ") to " +
                           revision.drop_area
                     : "take the empty pallet back to " + revision.drop_area;
          break;
        }
        default:
          continue;
      }
      revise(*order, revision, std::move(why));
    }
  }
}

std::string LoaderDesk::free_place(const std::vector<std::string>& places, bool with_load, const LoaderView& view,
                                   const std::string& own, const std::vector<std::string>& taken) const {
  const auto open = view.book.open_orders();
  const auto free = [&](const std::string& place) {
    return view.ledger.holds_load(place) == with_load && std::find(taken.begin(), taken.end(), place) == taken.end() &&
           std::none_of(open.begin(), open.end(),
                        [&](const Order* o) { return o->pick_area == place || o->drop_area == place; });
  };
  // Its own kept place first, while it is free; then any place nobody keeps.
  if (!own.empty() && std::find(places.begin(), places.end(), own) != places.end() && free(own)) return own;
  const auto reserved = reserved_places();
  for (const std::string& place : places) {
    if (!reserved.contains(place) && free(place)) return place;
  }
  return {};
}

}  // namespace fleet::orders
