#pragma once
// The packing chain [Picker thesis, section 5.3.3.1.3, built across fleets]: pickers fill the
// pallets of the packing stations with boxes; a full pallet goes to expedition by a transport
// order, and an empty pallet comes to the station by another. Everything here is derived from the
// order book and the ledger, so a restarted server picks the chain up where it stood.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "map/site.hpp"
#include "orders/area_ledger.hpp"
#include "orders/order_book.hpp"

namespace fleet::orders {

/// Boxes on a station's pallet: pick orders dropping there that no chain transport has taken
/// away yet.
struct StationFill {
  int boxes_done = 0;                   ///< put down by pick orders that are DONE
  int boxes_promised = 0;               ///< to be put down by open pick orders
  std::vector<std::int64_t> filled_by;  ///< the DONE pick orders, by id
  bool pallet_leaving = false;          ///< an open transport takes the station's pallet away
};

/// Boxes a pick order carries: the quantities of its lines.
int boxes_of(const Order& order);

StationFill station_fill(const OrderBook& book, const std::string& station);

/// Where a pick tour of `boxes` drops: `requested` when its pallet stands there, stays and has
/// room for them; else the first station after it (in the site's order, wrapping round) that
/// does; `requested` when none does (the tour's boxes then wait on the picker's tray for it).
/// `also_promised` counts, by station, the boxes of tours drafted before this one that are not in
/// `book` yet (the earlier tours of one pick list).
std::string station_for_tour(const map::Packing& packing, const AreaLedger& ledger, const OrderBook& book,
                             const std::string& requested, int boxes,
                             const std::map<std::string, int>& also_promised = {});

/// Whether the automatic transports [Forklift thesis, section 3] may pick at or drop to `place`:
/// not at a packing station, whose pallet only the chain moves (a pallet taken away half full
/// would leave the station without one until a random transport brought another).
bool open_to_random_transports(const map::Packing& packing, const std::string& place);

/// A transport the chain owes now, with why.
struct ChainTransport {
  std::string pick;
  std::string drop;
  std::string cause;
  std::vector<std::int64_t> caused_by;
};

/// The next transport the chain owes, if any: a full station's pallet (boxes_per_pallet boxes
/// put down) to a free `full_pallets_to` place; else an empty pallet from an `empty_pallets_from`
/// place to a station whose full pallet a chain transport took or takes away. A step whose places
/// are all taken is owed again later. Create it and ask again for the next one.
std::optional<ChainTransport> next_chain_transport(const map::Packing& packing, const AreaLedger& ledger,
                                                   const OrderBook& book);

}  // namespace fleet::orders
