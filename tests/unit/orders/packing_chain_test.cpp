#include "orders/packing_chain.hpp"

#include <gtest/gtest.h>

#include <random>
#include <set>

#include "model/names.hpp"
#include "orders/transport_areas.hpp"

namespace fleet::orders {
namespace {

/// Two stations with a pallet each, two expedition places (EX2 taken), one empty pallet in the
/// packaging corridor; full at 4 boxes.
struct Chain {
  map::Packing packing{4, {"PS1", "PS2"}, {"EX1", "EX2"}, {"PK1", "PK2"}};
  AreaLedger ledger{{{"PS1", {0, 0, 0}},
                     {"PS2", {1, 0, 0}},
                     {"EX1", {2, 0, 0}},
                     {"EX2", {3, 0, 0}},
                     {"PK1", {4, 0, 0}},
                     {"PK2", {5, 0, 0}},
                     {"RB1", {6, 0, 0}}}};
  OrderBook book;
  int next_load = 1;

  Chain() {
    for (const char* place : {"PS1", "PS2", "EX2", "PK2"}) stand(place);
  }
  void stand(const std::string& place) { ledger.record({next_load++, "pallet", {}, place, ""}); }

  std::int64_t pick_tour(const std::string& station, int boxes, OrderStatus status) {
    Order draft;
    draft.kind = OrderKind::kPick;
    draft.pick_area = "RB1";
    draft.drop_area = station;
    draft.lines = "RB1,A1," + std::to_string(boxes) + "\n";
    const std::int64_t id = book.create(std::move(draft), 0.0).id;
    finish(id, status);
    return id;
  }
  std::int64_t create(const ChainTransport& t) {
    Order draft;
    draft.pick_area = t.pick;
    draft.drop_area = t.drop;
    draft.cause = t.cause;
    draft.caused_by = t.caused_by;
    return book.create(std::move(draft), 0.0).id;
  }
  void finish(std::int64_t id, OrderStatus status) {
    if (status == OrderStatus::kQueued) return;
    book.assign(id, "pk1", 0.0);
    if (status == OrderStatus::kAssigned) return;
    book.transition(id, status, 1.0);
  }
  std::optional<ChainTransport> next() const { return next_chain_transport(packing, ledger, book); }
};

TEST(PackingChain, AFullPalletGoesToAFreeExpeditionPlaceAndAnEmptyOneComesInItsPlace) {
  Chain c;
  const auto first = c.pick_tour("PS1", 2, OrderStatus::kDone);
  EXPECT_FALSE(c.next()) << "2 of 4 boxes";
  const auto second = c.pick_tour("PS1", 2, OrderStatus::kDone);
  const auto full = c.next();
  ASSERT_TRUE(full);
  EXPECT_EQ(full->pick, "PS1");
  EXPECT_EQ(full->drop, "EX1") << "EX2 holds a pallet";
  EXPECT_EQ(full->caused_by, (std::vector<std::int64_t>{first, second}));
  EXPECT_EQ(full->cause, "the pallet at PS1 is full: 4 boxes from orders 1 and 2");
  const auto taker = c.create(*full);
  const auto empty = c.next();
  ASSERT_TRUE(empty);
  EXPECT_EQ(empty->pick, "PK2") << "PK1 holds no pallet";
  EXPECT_EQ(empty->drop, "PS1");
  EXPECT_EQ(empty->caused_by, std::vector<std::int64_t>{taker});
  c.create(*empty);
  EXPECT_FALSE(c.next()) << "nothing more is owed";
  // The pallet left: the station counts from zero for the pallet that comes.
  const StationFill fill = station_fill(c.book, "PS1");
  EXPECT_EQ(fill.boxes_done, 0);
  EXPECT_TRUE(fill.pallet_leaving);
}

TEST(PackingChain, WithNowhereToPutAFullPalletNothingIsOwedUntilAPlaceIsFree) {
  Chain c;
  c.stand("EX1");
  c.pick_tour("PS2", 4, OrderStatus::kDone);
  EXPECT_FALSE(c.next());
  auto gone = c.ledger.lifted("fk1", 5, "EX1");
  ASSERT_TRUE(gone);
  c.ledger.record(*gone);
  const auto full = c.next();
  ASSERT_TRUE(full);
  EXPECT_EQ(full->drop, "EX1");
}

TEST(PackingChain, AFailedTransportLeavesTheBoxesOnTheStationAndIsOwedAgain) {
  Chain c;
  c.pick_tour("PS1", 4, OrderStatus::kDone);
  const auto taker = c.create(*c.next());
  c.create(*c.next());
  c.book.transition(taker, OrderStatus::kFailed, 2.0, "no robot reaches EX1");
  const StationFill fill = station_fill(c.book, "PS1");
  EXPECT_EQ(fill.boxes_done, 4);
  EXPECT_FALSE(fill.pallet_leaving);
  const auto again = c.next();
  ASSERT_TRUE(again);
  EXPECT_EQ(again->pick, "PS1");
}

TEST(PackingChain, ATourGoesOnToTheNextStationWithRoomAndAPalletThatStays) {
  Chain c;
  EXPECT_EQ(station_for_tour(c.packing, c.ledger, c.book, "PS1", 2), "PS1");
  c.pick_tour("PS1", 2, OrderStatus::kDone);
  c.pick_tour("PS1", 1, OrderStatus::kAssigned);
  EXPECT_EQ(station_for_tour(c.packing, c.ledger, c.book, "PS1", 1), "PS1") << "3 of 4, one more fits";
  EXPECT_EQ(station_for_tour(c.packing, c.ledger, c.book, "PS1", 2), "PS2") << "promised boxes count";
  EXPECT_EQ(station_for_tour(c.packing, c.ledger, c.book, "PS2", 2), "PS2");
  // PS2's pallet is taken away: the tour wraps round to PS1 if it fits, else stays as asked.
  c.pick_tour("PS2", 4, OrderStatus::kDone);
  c.create(*c.next());
  EXPECT_EQ(station_for_tour(c.packing, c.ledger, c.book, "PS2", 1), "PS1");
  EXPECT_EQ(station_for_tour(c.packing, c.ledger, c.book, "PS2", 2), "PS2") << "no station has room";
  EXPECT_EQ(station_for_tour(c.packing, c.ledger, c.book, "EX1", 2), "EX1") << "not a station";
}

TEST(PackingChain, RandomTransportsLeaveTheStationsPalletsToTheChain) {
  Chain c;
  EXPECT_FALSE(open_to_random_transports(c.packing, "PS1"));
  EXPECT_FALSE(open_to_random_transports(c.packing, "PS2"));
  for (const char* place : {"EX1", "PK2", "RB1"}) EXPECT_TRUE(open_to_random_transports(c.packing, place)) << place;
  // Drawn over and over, the automatic transports pick and drop everywhere but at the stations.
  std::mt19937_64 rng(7);
  const auto open = [&](const std::string& pick, const std::string& drop) {
    return open_to_random_transports(c.packing, pick) && open_to_random_transports(c.packing, drop);
  };
  std::set<std::string> picks, drops;
  for (int k = 0; k < 200; ++k) {
    const auto choice = choose_auto_transport(c.ledger, c.book, rng, open);
    ASSERT_TRUE(choice);
    picks.insert(choice->pick);
    drops.insert(choice->drop);
  }
  EXPECT_EQ(picks, (std::set<std::string>{"EX2", "PK2"}));
  EXPECT_EQ(drops, (std::set<std::string>{"EX1", "PK1", "RB1"}));
}

TEST(PackingChain, OrderIdsTravelAsTextAndBack) {
  EXPECT_EQ(model::ids_text({12, 14, 15}), "12 14 15");
  EXPECT_EQ(model::parse_ids("12 14 15"), (std::vector<std::int64_t>{12, 14, 15}));
  EXPECT_EQ(model::parse_ids(""), std::vector<std::int64_t>{});
  EXPECT_FALSE(model::parse_ids("12,14"));
  EXPECT_FALSE(model::parse_ids("-3"));
}

}  // namespace
}  // namespace fleet::orders
