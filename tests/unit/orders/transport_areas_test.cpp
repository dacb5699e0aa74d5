#include "orders/transport_areas.hpp"

#include <gtest/gtest.h>

#include <set>

using namespace fleet::orders;

namespace {
const TransportFilter kAnyPair = [](const std::string&, const std::string&) { return true; };
struct Site {
  AreaLedger ledger{{{"A1", {}}, {"A2", {}}, {"A3", {}}, {"A4", {}}}};
  OrderBook book;

  Site() {
    ledger.record({1, "pallet", {}, "A1", ""});
    ledger.record({2, "pallet", {}, "A2", ""});
  }
  const Order& order(const std::string& pick, const std::string& drop) {
    Order draft;
    draft.pick_area = pick;
    draft.drop_area = drop;
    return book.create(std::move(draft), 0.0);
  }
};
}  // namespace

TEST(TransportAreas, ExpectedLoadsCountOpenOrders) {
  Site site;
  EXPECT_EQ(expected_loads(site.ledger, site.book, "A1"), 1);
  EXPECT_EQ(expected_loads(site.ledger, site.book, "A3"), 0);
  const Order& o = site.order("A1", "A3");
  EXPECT_EQ(expected_loads(site.ledger, site.book, "A1"), 0);
  EXPECT_EQ(expected_loads(site.ledger, site.book, "A3"), 1);
  site.book.transition(o.id, OrderStatus::kCancelled, 1.0);
  EXPECT_EQ(expected_loads(site.ledger, site.book, "A1"), 1);
}

TEST(TransportAreas, RefusesAPickWithoutALoadAndADropThatHoldsOne) {
  Site site;
  EXPECT_EQ(why_not_transport(site.ledger, site.book, "A1", "A3"), "");
  EXPECT_EQ(why_not_transport(site.ledger, site.book, "A3", "A4"), "loading area 'A3' holds no pallet to pick");
  EXPECT_EQ(why_not_transport(site.ledger, site.book, "A1", "A2"), "loading area 'A2' holds a pallet");
}

TEST(TransportAreas, RefusalsNameTheOrderThatHoldsThePromise) {
  Site site;
  const Order& first = site.order("A1", "A3");
  EXPECT_EQ(why_not_transport(site.ledger, site.book, "A1", "A4"),
            "the pallet on loading area 'A1' is promised to order " + std::to_string(first.id) + ", which picks it up");
  EXPECT_EQ(why_not_transport(site.ledger, site.book, "A2", "A3"),
            "loading area 'A3' is promised to order " + std::to_string(first.id) + ", which drops its pallet there");
  // Chained behind it: A3 will hold the pallet.
  EXPECT_EQ(why_not_transport(site.ledger, site.book, "A3", "A4"), "");
}

TEST(TransportAreas, AChainedOrderIsNotReadyUntilItsLoadArrives) {
  Site site;
  const Order& first = site.order("A1", "A3");
  const Order& second = site.order("A3", "A4");
  EXPECT_TRUE(ready_to_dispatch(site.ledger, first));
  EXPECT_FALSE(ready_to_dispatch(site.ledger, second));
  site.ledger.record({1, "pallet", {}, "A3", ""});
  EXPECT_TRUE(ready_to_dispatch(site.ledger, second));
  EXPECT_FALSE(ready_to_dispatch(site.ledger, site.order("A2", "A3")));
}

TEST(TransportAreas, AnOrderWaitsWhileARobotStandsOnItsPlaces) {
  Site site;
  const Order& order = site.order("A1", "A3");
  std::set<std::string> taken{"A3"};
  const PlaceTaken stands = [&](const std::string& place) { return taken.contains(place); };
  EXPECT_FALSE(ready_to_dispatch(site.ledger, order, stands));
  taken = {"A1"};
  EXPECT_FALSE(ready_to_dispatch(site.ledger, order, stands));
  taken.clear();
  EXPECT_TRUE(ready_to_dispatch(site.ledger, order, stands));
}

TEST(TransportAreas, ABodyStandsOnAPlaceWhereItCoversTheLoadOrTheApproach) {
  using fleet::geometry::Footprint;
  using fleet::geometry::footprint_polygon;
  fleet::map::LoadingArea area;
  area.pose = {10.0, 5.0, 1.5707963};  // approached from the north: the approach point is (10, 6.2)
  const Footprint body{1.0, 0.6};
  EXPECT_TRUE(body_stands_on(footprint_polygon({10.0, 5.0, 0.0}, body), area, 1.2));
  EXPECT_TRUE(body_stands_on(footprint_polygon({10.0, 6.4, 0.0}, body), area, 1.2));
  EXPECT_FALSE(body_stands_on(footprint_polygon({10.0, 5.7, 0.0}, body), area, 1.2));  // between them
  EXPECT_FALSE(body_stands_on(footprint_polygon({11.0, 5.0, 0.0}, body), area, 1.2));
  EXPECT_FALSE(body_stands_on({}, area, 1.2));
}

TEST(TransportAreas, QueuedPickToursHoldNoAutomaticTransportBack) {
  Site site;
  EXPECT_TRUE(auto_transport_wanted(site.book, 1));
  EXPECT_FALSE(auto_transport_wanted(site.book, 0));
  for (int tour = 0; tour < 2; ++tour) {
    Order pick;
    pick.kind = OrderKind::kPick;
    pick.drop_area = "PACK1";
    site.book.create(std::move(pick), 0.0);
  }
  EXPECT_TRUE(auto_transport_wanted(site.book, 1)) << "two pick tours wait for pickers, not for this robot";
  site.order("A1", "A3");
  EXPECT_FALSE(auto_transport_wanted(site.book, 1)) << "one transport waits for the one free robot";
  EXPECT_TRUE(auto_transport_wanted(site.book, 2));
}

TEST(TransportAreas, AnAutomaticTransportUsesNoPromisedPlace) {
  Site site;
  site.order("A1", "A3");
  std::set<std::string> picks, drops;
  for (std::uint64_t seed = 0; seed < 20; ++seed) {
    std::mt19937_64 rng(seed);
    const auto choice = choose_auto_transport(site.ledger, site.book, rng, kAnyPair);
    ASSERT_TRUE(choice.has_value());
    picks.insert(choice->pick);
    drops.insert(choice->drop);
  }
  EXPECT_EQ(picks, std::set<std::string>{"A2"});
  EXPECT_EQ(drops, std::set<std::string>{"A4"});
}

TEST(TransportAreas, NoAutomaticTransportWithoutAFreePlace) {
  Site site;
  site.ledger.record({3, "pallet", {}, "A3", ""});
  site.ledger.record({4, "pallet", {}, "A4", ""});
  std::mt19937_64 rng(1);
  EXPECT_FALSE(choose_auto_transport(site.ledger, site.book, rng, kAnyPair).has_value());
}

TEST(TransportAreas, AnAutomaticTransportIsReproducibleFromItsSeed) {
  Site site;
  std::mt19937_64 a(42), b(42);
  const auto first = choose_auto_transport(site.ledger, site.book, a, kAnyPair);
  const auto second = choose_auto_transport(site.ledger, site.book, b, kAnyPair);
  ASSERT_TRUE(first && second);
  EXPECT_EQ(first->pick, second->pick);
  EXPECT_EQ(first->drop, second->drop);
}

TEST(TransportAreas, AutomaticOrdersAreOnlyPairsTheFilterAccepts) {
  // Only one pair is doable (a fleet that reaches one drop place): every choice is that pair.
  Site site;
  std::mt19937_64 rng(3);
  int chosen = 0;
  for (int i = 0; i < 50; ++i) {
    const auto choice = choose_auto_transport(
        site.ledger, site.book, rng,
        [](const std::string& pick, const std::string& drop) { return pick == "A1" && drop == "A3"; });
    if (!choice) continue;
    ++chosen;
    EXPECT_EQ(choice->pick, "A1");
    EXPECT_EQ(choice->drop, "A3");
  }
  EXPECT_GT(chosen, 0);
}
