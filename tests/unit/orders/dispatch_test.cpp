#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <map>
#include <numeric>
#include <random>

#include "orders/dispatch.hpp"
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
  EXPECT_DOUBLE_EQ(total(make_dispatch_policy("nearest")->assign(pointers(orders), {{"fl1", ""}, {"fl2", ""}}, cost)), 11.0);
  EXPECT_DOUBLE_EQ(total(make_dispatch_policy("optimal")->assign(pointers(orders), {{"fl1", ""}, {"fl2", ""}}, cost)), 4.0);
}

TEST(Dispatch, UnknownPolicyNameThrows) { EXPECT_THROW(make_dispatch_policy("fastest"), std::invalid_argument); }

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
