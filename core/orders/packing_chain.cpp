#include "orders/packing_chain.hpp"

#include <algorithm>
#include <set>

#include "orders/pick_lines.hpp"
#include "orders/transport_areas.hpp"

namespace fleet::orders {

namespace {

bool live(const Order& o) {
  return o.status != OrderStatus::kFailed && o.status != OrderStatus::kCancelled;
}

/// A transport the chain created to take a station's full pallet away.
bool takes_full_pallet(const Order& o, const std::string& station) {
  return o.kind == OrderKind::kTransport && o.pick_area == station && !o.cause.empty() && !o.caused_by.empty();
}

std::string id_list(const std::vector<std::int64_t>& ids) {
  std::string text;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    if (i > 0) text += i + 1 == ids.size() ? " and " : ", ";
    text += std::to_string(ids[i]);
  }
  return text;
}

/// The first of `places` a load can go to now and none is promised to.
const std::string* free_place(const std::vector<std::string>& places, const AreaLedger& ledger, const OrderBook& book) {
  for (const auto& p : places) {
    if (expected_loads(ledger, book, p) == 0) return &p;
  }
  return nullptr;
}

/// The first of `places` with a load standing on it that no open order takes or brings.
const std::string* spare_load(const std::vector<std::string>& places, const AreaLedger& ledger, const OrderBook& book) {
  for (const auto& p : places) {
    if (ledger.standing_on(p) != nullptr && expected_loads(ledger, book, p) == 1) return &p;
  }
  return nullptr;
}

}  // namespace

int boxes_of(const Order& order) {
  int boxes = 0;
  for (const auto& line : parse_pick_lines(order.lines, "order " + std::to_string(order.id))) boxes += line.quantity;
  return boxes;
}

StationFill station_fill(const OrderBook& book, const std::string& station) {
  StationFill fill;
  std::set<std::int64_t> taken_away;
  for (const auto& [id, o] : book.all()) {
    if (!takes_full_pallet(o, station) || !live(o)) continue;
    taken_away.insert(o.caused_by.begin(), o.caused_by.end());
    if (!is_final(o.status)) fill.pallet_leaving = true;
  }
  for (const auto& [id, o] : book.all()) {
    if (o.kind != OrderKind::kPick || o.drop_area != station || !live(o) || taken_away.contains(id)) continue;
    if (o.status == OrderStatus::kDone) {
      fill.boxes_done += boxes_of(o);
      fill.filled_by.push_back(id);
    } else {
      fill.boxes_promised += boxes_of(o);
    }
  }
  return fill;
}

std::string station_for_tour(const map::Packing& packing, const AreaLedger& ledger, const OrderBook& book,
                             const std::string& requested, int boxes, const std::map<std::string, int>& also_promised) {
  const auto has_room = [&](const std::string& station) {
    if (ledger.standing_on(station) == nullptr) return false;
    const StationFill fill = station_fill(book, station);
    const auto drafted = also_promised.find(station);
    const int promised = fill.boxes_promised + (drafted == also_promised.end() ? 0 : drafted->second);
    return !fill.pallet_leaving && fill.boxes_done + promised + boxes <= packing.boxes_per_pallet;
  };
  const auto& stations = packing.stations;
  const auto at = std::find(stations.begin(), stations.end(), requested);
  if (at == stations.end()) return requested;  // not a packing station: the chain does not apply
  const std::size_t first = static_cast<std::size_t>(at - stations.begin());
  for (std::size_t k = 0; k < stations.size(); ++k) {
    const std::string& station = stations[(first + k) % stations.size()];
    if (has_room(station)) return station;
  }
  return requested;
}

std::optional<ChainTransport> next_chain_transport(const map::Packing& packing, const AreaLedger& ledger,
                                                   const OrderBook& book) {
  for (const auto& station : packing.stations) {
    const StationFill fill = station_fill(book, station);
    if (fill.pallet_leaving || fill.boxes_done < packing.boxes_per_pallet) continue;
    if (ledger.standing_on(station) == nullptr) continue;
    const std::string* to = free_place(packing.full_pallets_to, ledger, book);
    if (to == nullptr) continue;
    return ChainTransport{station, *to,
                          "the pallet at " + station + " is full: " + std::to_string(fill.boxes_done) +
                              " boxes from order" + (fill.filled_by.size() == 1 ? " " : "s ") + id_list(fill.filled_by),
                          fill.filled_by};
  }
  for (const auto& station : packing.stations) {
    // A full pallet taken away for which no empty one came or comes.
    std::set<std::int64_t> replaced;
    for (const auto& [id, o] : book.all()) {
      if (o.kind == OrderKind::kTransport && o.drop_area == station && !o.cause.empty() && live(o))
        replaced.insert(o.caused_by.begin(), o.caused_by.end());
    }
    for (const auto& [id, o] : book.all()) {
      if (!takes_full_pallet(o, station) || !live(o) || replaced.contains(id)) continue;
      const std::string* from = spare_load(packing.empty_pallets_from, ledger, book);
      if (from == nullptr) return std::nullopt;
      return ChainTransport{
          *from,
          station,
          "an empty pallet for " + station + ", whose full pallet order " + std::to_string(id) + " takes away",
          {id}};
    }
  }
  return std::nullopt;
}

bool open_to_random_transports(const map::Packing& packing, const std::string& place) {
  return std::find(packing.stations.begin(), packing.stations.end(), place) == packing.stations.end();
}

}  // namespace fleet::orders
