#include "orders/dispatch.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <map>
#include <numeric>
#include <random>

#include "orders/hungarian.hpp"

using namespace fleet::orders;

namespace {
std::vector<Order> make_orders(std::initializer_list<std::string> picks) {
  std::vector<Order> orders;
  std::int64_t id = 1;
  for (const auto& p : picks) {
    Order o;
    o.id = id++;
    o.pick_area = p;
    orders.push_back(o);
  }
  return orders;
}
std::vector<const Order*> pointers(const std::vector<Order>& orders) {
  std::vector<const Order*> out;
  for (const auto& o : orders) out.push_back(&o);
  return out;
}
}  // namespace

TEST(Dispatch, NaturalRobotIdOrder) {
  EXPECT_TRUE(robot_id_less("fl2", "fl10"));
  EXPECT_FALSE(robot_id_less("fl10", "fl2"));
  EXPECT_TRUE(robot_id_less("a1", "b1"));
}

TEST(Dispatch, AscendingIdGivesTheFirstOrderToTheLowestId) {
  const auto orders = make_orders({"A1", "A2"});
  const auto policy = make_dispatch_policy("ascending-id");
  const auto out = policy->assign(pointers(orders), {{"fl10", "f"}, {"fl2", "f"}, {"fl3", "f"}},
                                  [](const std::string&, const std::string&) { return 1.0; });
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].robot_id, "fl2");
  EXPECT_EQ(out[1].robot_id, "fl3");
}

TEST(Dispatch, NearestTakesTheClosestRobot) {
  const auto orders = make_orders({"A1"});
  const auto out = make_dispatch_policy("nearest")->assign(
      pointers(orders), {{"fl1", "f"}, {"fl2", "f"}},
      [](const std::string& robot, const std::string&) { return robot == "fl2" ? 1.0 : 5.0; });
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].robot_id, "fl2");
}

TEST(Dispatch, RequestedRobotAndFleetAreHonoured) {
  auto orders = make_orders({"A1", "A2"});
  orders[0].robot_id = "fl3";
  orders[0].robot_requested = true;
  orders[1].fleet_id = "pickers";
  for (const char* name : {"ascending-id", "nearest", "optimal"}) {
    const auto out = make_dispatch_policy(name)->assign(pointers(orders), {{"fl1", "forklifts"}, {"fl3", "forklifts"}},
                                                        [](const std::string&, const std::string&) { return 1.0; });
    ASSERT_EQ(out.size(), 1u) << name;
    EXPECT_EQ(out[0].order_id, 1) << name;
    EXPECT_EQ(out[0].robot_id, "fl3") << name;
  }
}

TEST(Dispatch, UnreachableAreasAreNotAssigned) {
  const auto orders = make_orders({"A1"});
  const double inf = std::numeric_limits<double>::infinity();
  for (const char* name : {"ascending-id", "nearest", "optimal"}) {
    const auto out = make_dispatch_policy(name)->assign(pointers(orders), {{"fl1", "f"}},
                                                        [&](const std::string&, const std::string&) { return inf; });
    EXPECT_TRUE(out.empty()) << name;
  }
}

TEST(Dispatch, OptimalBeatsGreedyOnTheClassicCase) {
  // Greedy nearest gives order 1 to fl1 (cost 1) and leaves order 2 with fl2 (cost 10): total 11.
  // The optimum is 2 + 2 = 4.
  const auto orders = make_orders({"P1", "P2"});
  std::map<std::pair<std::string, std::string>, double> c{
      {{"fl1", "P1"}, 1}, {{"fl2", "P1"}, 2}, {{"fl1", "P2"}, 2}, {{"fl2", "P2"}, 10}};
  auto cost = [&](const std::string& r, const std::string& a) { return c.at({r, a}); };
  auto total = [&](const std::vector<Assignment>& out) {
    double t = 0;
    for (const auto& a : out) t += cost(a.robot_id, orders[static_cast<std::size_t>(a.order_id - 1)].pick_area);
    return t;
  };
  EXPECT_DOUBLE_EQ(total(make_dispatch_policy("nearest")->assign(pointers(orders), {{"fl1", ""}, {"fl2", ""}}, cost)),
                   11.0);
  EXPECT_DOUBLE_EQ(total(make_dispatch_policy("optimal")->assign(pointers(orders), {{"fl1", ""}, {"fl2", ""}}, cost)),
                   4.0);
}

TEST(Dispatch, UnknownPolicyNameThrows) {
  EXPECT_THROW(make_dispatch_policy("fastest"), std::invalid_argument);
}

TEST(Hungarian, MatchesBruteForceOnRandomSmallCases) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> value(0.0, 100.0);
  for (int trial = 0; trial < 300; ++trial) {
    const int n = 1 + static_cast<int>(rng() % 5);
    const int m = n + static_cast<int>(rng() % 3);
    std::vector<std::vector<double>> cost(n, std::vector<double>(m));
    for (auto& row : cost)
      for (auto& v : row) v = std::round(value(rng));
    const auto match = hungarian_assignment(cost);
    double got = 0;
    std::vector<bool> used(m, false);
    for (int i = 0; i < n; ++i) {
      ASSERT_GE(match[i], 0);
      ASSERT_FALSE(used[match[i]]);
      used[match[i]] = true;
      got += cost[i][match[i]];
    }
    // Brute force over ordered choices of n distinct columns.
    std::vector<int> cols(m);
    std::iota(cols.begin(), cols.end(), 0);
    double best = std::numeric_limits<double>::infinity();
    do {
      double t = 0;
      for (int i = 0; i < n; ++i) t += cost[i][cols[i]];
      best = std::min(best, t);
    } while (std::next_permutation(cols.begin(), cols.end()));
    EXPECT_DOUBLE_EQ(got, best) << "trial " << trial;
  }
}

TEST(Hungarian, ForbiddenEntriesAreNeverChosen) {
  const auto match = hungarian_assignment({{kForbidden, 3.0}, {kForbidden, kForbidden}});
  EXPECT_EQ(match[0], 1);
  EXPECT_EQ(match[1], -1);
}

namespace {
// Two fleets: floor forklifts (pick, drop at 0 m) and reach trucks (pick, drop up to 4.5 m).
// The reach trucks do not fit the narrow spur to EN1.
const FleetAbility kForklifts{"forklifts", {"pick", "drop"}, 0.0, {}};
const FleetAbility kReachTrucks{"reach_trucks", {"pick", "drop"}, 4.5, {"EN1"}};

Order transport(std::int64_t id, const std::string& from, double from_height) {
  Order o;
  o.id = id;
  o.pick_area = from;
  o.drop_area = "E1";
  o.steps = order_steps(OrderKind::kTransport, from, "E1", from_height, 0.0);
  return o;
}
}  // namespace

TEST(Dispatch, EveryPolicyMatchesOnlyCompatiblePairs) {
  // The high order first in the queue.
  const std::vector<Order> orders{transport(1, "R_HIGH", 3.5), transport(2, "EN1", 0.0)};
  // The reach truck is the nearer robot for both.
  const auto cost = [](const std::string& robot, const std::string&) { return robot == "rt1" ? 1.0 : 9.0; };
  for (const char* name : {"ascending-id", "nearest", "optimal"}) {
    const auto out = make_dispatch_policy(name)->assign(
        pointers(orders), {{"fk1", "forklifts", kForklifts}, {"rt1", "reach_trucks", kReachTrucks}}, cost);
    ASSERT_EQ(out.size(), 2u) << name;
    std::map<std::int64_t, std::string> by_order;
    for (const auto& a : out) by_order[a.order_id] = a.robot_id;
    EXPECT_EQ(by_order[1], "rt1") << name;  // only the reach truck lifts that high
    EXPECT_EQ(by_order[2], "fk1") << name;  // only the forklift reaches EN1
  }
}

TEST(Dispatch, AnOrderNoFreeRobotCanDoHoldsNoSlotOfTheOptimalPolicy) {
  // One free robot, a forklift; the head of the queue is an item pick no forklift performs.
  Order pick;
  pick.id = 1;
  pick.kind = OrderKind::kPick;
  pick.pick_area = "B1";
  pick.drop_area = "P1";
  pick.steps = order_steps(OrderKind::kPick, "B1", "P1");
  const std::vector<Order> orders{pick, transport(2, "A1", 0.0)};
  const auto out = make_dispatch_policy("optimal")->assign(pointers(orders), {{"fk1", "forklifts", kForklifts}},
                                                           [](const std::string&, const std::string&) { return 1.0; });
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].order_id, 2);
}

TEST(OrderKinds, StepsAreVda5050NodesWithActions) {
  const auto transport_steps = order_steps(OrderKind::kTransport, "A1", "A2");
  ASSERT_EQ(transport_steps.size(), 2u);
  EXPECT_EQ(transport_steps[0].actions, std::vector<std::string>{"pick"});
  EXPECT_EQ(transport_steps[1].place, "A2");
  const auto move_steps = order_steps(OrderKind::kMove, "", "H3");
  ASSERT_EQ(move_steps.size(), 1u);
  EXPECT_TRUE(move_steps[0].actions.empty());
  EXPECT_EQ(parse_kind("pick"), OrderKind::kPick);
  EXPECT_FALSE(parse_kind("dance").has_value());
}

TEST(OrderKinds, WhyNoFleetNamesTheActionAndEveryFleet) {
  const auto why = why_no_fleet({kForklifts, kReachTrucks}, order_steps(OrderKind::kPick, "B1", "P1"));
  ASSERT_TRUE(why.has_value());
  EXPECT_NE(why->find("forklifts cannot 'pickItem'"), std::string::npos) << *why;
  EXPECT_NE(why->find("reach_trucks cannot 'pickItem'"), std::string::npos) << *why;
  const auto high = why_no_fleet({kForklifts}, order_steps(OrderKind::kTransport, "R9", "E1", 3.5, 0.0));
  ASSERT_TRUE(high.has_value());
  EXPECT_NE(high->find("lifts to 0.00 m, the load at R9 stands at 3.50 m"), std::string::npos) << *high;
  EXPECT_FALSE(why_no_fleet({kForklifts, kReachTrucks}, order_steps(OrderKind::kTransport, "R9", "E1", 3.5, 0.0)));
}
