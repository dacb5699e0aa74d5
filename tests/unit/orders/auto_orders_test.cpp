#include "orders/auto_orders.hpp"

#include <gtest/gtest.h>

#include <map>
#include <numbers>
#include <set>
#include <string>
#include <vector>

namespace fleet::orders {
namespace {

/// Loading areas A1 (a pallet on it), A2 and A3 (empty); rack places R1 and R2 with boxes of item
/// BX, in rack K1; packing station PS1 with a pallet. Forklifts fl1 and fl2 carry pallets, picker pk1 picks
/// boxes; who is free is set per test.
struct Yard {
  map::Site site;
  AreaLedger ledger;
  OrderBook book;
  KnownNames names;
  std::map<std::string, std::string> parked_at;
  std::set<std::string> free_robots;

  Yard() {
    std::vector<Place> places;
    double x = 0.0;
    for (const char* id : {"A1", "A2", "A3", "R1", "R2", "PS1"}) {
      map::LoadingArea area;
      area.id = id;
      area.pose = {x, 0.0, 0.0};
      x += 2.0;
      if (area.id[0] == 'R') area.boxes = map::BoxStock{"BX", 5};
      site.loading_areas.push_back(area);
      places.push_back({area.id, area.pose});
      names.areas.push_back(area.id);
    }
    site.packing = map::Packing{3, {"PS1"}, {"A3"}, {"A2"}};
    site.racks = {{"K1", {{5.5, -0.5}, {8.5, -0.5}, {8.5, 0.5}, {5.5, 0.5}}},  // R1 and R2
                  {"K2", {{5.5, 4.5}, {8.5, 4.5}, {8.5, 5.5}, {5.5, 5.5}}}};
    names.robots = {"fl1", "fl2", "pk1"};
    names.fleets = {"forklifts", "pickers"};
    names.fleet_of_robot = {{"fl1", "forklifts"}, {"fl2", "forklifts"}, {"pk1", "pickers"}};
    names.abilities = {{"forklifts", {"pick", "drop"}, 2.0, {}}, {"pickers", {"pickItem", "dropItem"}, 2.0, {}}};
    ledger = AreaLedger(places);
    ledger.record({1, "pallet", {}, "A1", ""});
    ledger.record({2, "pallet", {}, "PS1", ""});
  }

  /// Rack place R3 with boxes of item BY, in rack K2: a second rack row.
  void add_second_row() {
    map::LoadingArea r3;
    r3.id = "R3";
    r3.pose = {6.0, 5.0, 0.0};
    r3.boxes = map::BoxStock{"BY", 5};
    site.loading_areas.push_back(r3);
    names.areas.push_back("R3");
  }

  IntakeView view() const {
    return {.book = book,
            .ledger = ledger,
            .names = names,
            .site = site,
            .parked_at = parked_at,
            .registered = {"fl1", "fl2", "pk1"},
            .free_robots = free_robots,
            .reject_when_busy = false,
            .max_pickable_mass = 5.0};
  }
};

TEST(AutoOrders, ARoundIsDueOnlyWhenOnAndNotWithinThePeriod) {
  AutoOrders off(false, 1);
  EXPECT_FALSE(off.due(100.0));
  AutoOrders source(true, 1);
  EXPECT_TRUE(source.due(0.0));
  EXPECT_FALSE(source.due(AutoOrders::kPeriodWallS / 2));
  EXPECT_TRUE(source.due(AutoOrders::kPeriodWallS));
  source.set_on(false);
  EXPECT_FALSE(source.due(200.0));
}

TEST(AutoOrders, ATransportLeavesThePackingStationsAloneAndWaitsForAFreeCarrier) {
  Yard yard;
  AutoOrders source(true, 7);
  yard.free_robots = {"pk1"};
  EXPECT_FALSE(source.transport(yard.view())) << "a picker carries no pallet";
  yard.free_robots = {"fl1"};
  const auto draft = source.transport(yard.view());
  ASSERT_TRUE(draft);
  EXPECT_EQ(draft->request_id, "auto");
  EXPECT_EQ(draft->pick_area, "A1") << "the only load not on a packing station";
  EXPECT_NE(draft->drop_area, "PS1");
  EXPECT_NE(draft->drop_area, "A1");
  ASSERT_EQ(draft->steps.size(), 2u) << "the steps are filled";
  yard.book.create(*draft, 0.0);
  EXPECT_FALSE(source.transport(yard.view())) << "one queued transport for one free forklift";
}

TEST(AutoOrders, PickToursGoToThePackingStationWhileFreePickersOutnumberQueuedPicks) {
  Yard yard;
  AutoOrders source(true, 3);
  yard.free_robots = {"fl1", "fl2"};
  EXPECT_TRUE(source.pick_tours(yard.view()).empty()) << "no free picker";
  yard.free_robots = {"pk1"};
  const auto tours = source.pick_tours(yard.view());
  ASSERT_FALSE(tours.empty());
  for (const Order& tour : tours) {
    EXPECT_EQ(tour.kind, OrderKind::kPick);
    EXPECT_EQ(tour.drop_area, "PS1");
    EXPECT_EQ(tour.request_id, "auto");
    EXPECT_TRUE(tour.pick_area == "R1" || tour.pick_area == "R2") << tour.pick_area;
  }
  yard.book.create(tours.front(), 0.0);
  EXPECT_TRUE(source.pick_tours(yard.view()).empty()) << "one queued pick order for one free picker";
}

TEST(AutoOrders, ASiteWithoutPackingStationsGetsNoPickTours) {
  Yard yard;
  yard.site.packing.reset();
  yard.free_robots = {"pk1"};
  AutoOrders source(true, 3);
  EXPECT_TRUE(source.pick_tours(yard.view()).empty());
}

// Loader walks keep to a rack row each: a second pair in the row of an open walk could not pass
// the first on its one-way lane.
TEST(AutoOrders, ALoaderWalkTakesARackRowNoOtherOpenWalkWorks) {
  Yard yard;
  yard.add_second_row();
  yard.names.robots.push_back("pk2");
  yard.names.fleet_of_robot["pk2"] = "pickers";
  yard.free_robots = {"pk1", "pk2"};
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    yard.book = OrderBook();
    AutoOrders source(true, seed, "loader");
    IntakeView view = yard.view();
    view.loader_fleet = "stackers";
    const auto first = source.pick_tours(view);
    ASSERT_EQ(first.size(), 1u);
    ASSERT_TRUE(first[0].loader);
    const bool in_r3 = first[0].pick_area == "R3";
    yard.book.create(first[0], 0.0);
    const auto second = source.pick_tours(view);
    ASSERT_EQ(second.size(), 1u) << "seed " << seed;
    for (const PickLine& line : parse_pick_lines(second[0].lines, "second")) {
      EXPECT_EQ(line.place == "R3", !in_r3) << "seed " << seed << ": " << second[0].lines;
    }
  }
}

// A loader's transporter closes its lane behind it: no automatic transport goes to or from a
// place in the rack row of an open walk, where it would wait on the road before the lane, in the
// way of the picker.
TEST(AutoOrders, ATransportStaysOutOfTheRackRowOfAnOpenLoaderWalk) {
  Yard yard;
  // R1 and R2 face north onto an aisle; across it, S1 in rack K3 faces south onto the same aisle.
  for (auto& area : yard.site.loading_areas) {
    if (area.id[0] == 'R') area.pose.yaw = std::numbers::pi / 2.0;
  }
  yard.site.racks.push_back({"K3", {{5.5, 2.5}, {8.5, 2.5}, {8.5, 3.5}, {5.5, 3.5}}});
  map::LoadingArea s1;
  s1.id = "S1";
  s1.pose = {6.0, 3.0, -std::numbers::pi / 2.0};
  yard.site.loading_areas.push_back(s1);
  yard.names.areas.push_back("S1");
  std::vector<Place> places = yard.ledger.places();
  places.push_back({"S1", s1.pose});
  yard.ledger = AreaLedger(places);
  yard.ledger.record({1, "pallet", {}, "A1", ""});
  yard.ledger.record({2, "pallet", {}, "PS1", ""});
  yard.free_robots = {"fl1"};
  const auto drops_of = [&](const Yard& y) {
    std::set<std::string> drops;
    for (std::uint64_t seed = 1; seed <= 24; ++seed) {
      AutoOrders source(true, seed);
      if (const auto draft = source.transport(y.view())) drops.insert(draft->drop_area);
    }
    return drops;
  };
  const auto before = drops_of(yard);
  ASSERT_TRUE(before.contains("R1") || before.contains("R2")) << "the rack row is a drop like any other";
  ASSERT_TRUE(before.contains("S1"));
  yard.free_robots = {"fl1", "pk1"};
  IntakeView view = yard.view();
  view.loader_fleet = "stackers";
  AutoOrders walks(true, 1, "loader");
  const auto walk = walks.pick_tours(view);
  ASSERT_EQ(walk.size(), 1u);
  ASSERT_TRUE(walk[0].loader);
  yard.book.create(walk[0], 0.0);
  yard.free_robots = {"fl1"};
  const auto after = drops_of(yard);
  EXPECT_FALSE(after.empty());
  EXPECT_FALSE(after.contains("R1") || after.contains("R2")) << "a transport into the walk's row";
  EXPECT_FALSE(after.contains("S1")) << "a transport into the row across the walk's aisle";
}

// Nor does a walk take a row where another open order has a place while another row is free:
// that robot would stand in the pair's lane, or wait before it once the transporter closes it.
TEST(AutoOrders, ALoaderWalkTakesNoRackRowAnOpenTransportGoesTo) {
  Yard yard;
  yard.add_second_row();
  Order transport;
  transport.pick_area = "A1";
  transport.drop_area = "R2";
  yard.book.create(transport, 0.0);
  yard.free_robots = {"pk1"};
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    AutoOrders source(true, seed, "loader");
    IntakeView view = yard.view();
    view.loader_fleet = "stackers";
    const auto walk = source.pick_tours(view);
    ASSERT_EQ(walk.size(), 1u);
    for (const PickLine& line : parse_pick_lines(walk[0].lines, "walk")) {
      EXPECT_EQ(line.place, "R3") << "seed " << seed << ": " << walk[0].lines;
    }
  }
  // With every aisle in use, a walk takes one no other walk works.
  yard.site.loading_areas.back().boxes->count = 0;
  AutoOrders source(true, 1, "loader");
  IntakeView view = yard.view();
  view.loader_fleet = "stackers";
  const auto walk = source.pick_tours(view);
  ASSERT_EQ(walk.size(), 1u) << "no walk while a transport goes to the only rack row with boxes";
  EXPECT_TRUE(walk[0].lines.find("R1") != std::string::npos || walk[0].lines.find("R2") != std::string::npos)
      << walk[0].lines;
}

TEST(AutoOrders, TheSameSeedDrawsTheSameOrders) {
  Yard yard;
  yard.free_robots = {"fl1", "pk1"};
  AutoOrders first(true, 11), second(true, 11);
  const auto a = first.pick_tours(yard.view()), b = second.pick_tours(yard.view());
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].lines, b[i].lines);
  EXPECT_EQ(first.transport(yard.view())->drop_area, second.transport(yard.view())->drop_area);
}

}  // namespace
}  // namespace fleet::orders
