// A hot standby with real processes: the active server is killed with SIGKILL mid-run, and the
// standby, which mirrored its orders and site state, takes over; the robots carry on under it.

#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <map>
#include <regex>
#include <thread>

#include "cli/client.hpp"
#include "fleet_harness.hpp"
#include "orders/order.hpp"
#include "scripted_fleet.hpp"

using namespace fleet;
using namespace fleet::testing;
using namespace std::chrono_literals;

TEST(Standby, TakesOverWhenTheActiveServerIsKilledAndLosesNoOrderAndRunsNoneTwice) {
  FleetHarness fleet(73, 10.0);
  fleet.start_server({"--auto-orders"});  // process 0: the active server
  std::vector<std::string> standby{bin("fleet-server"), "--db", fleet.log_dir() + "/standby.db"};
  for (const auto& a : fleet.common_args()) standby.push_back(a);
  for (const char* a : {"--standby", "--auto-orders", "--http-port", "0"}) standby.emplace_back(a);
  fleet.processes().start("fleet-server-standby", standby, fleet.log_dir() + "/fleet-server-standby.log");
  const std::vector<std::string> robots{"fl1", "fl2"};
  for (const auto& r : robots) fleet.start_agent(r);
  cli::FleetClient client(73);
  ASSERT_TRUE(client.find_server(5s));
  // Work under way, and mirrored: at least one order done by the active server.
  const auto before = orders_once_done(client, 1, 60s);
  long done_before = 0;
  for (const auto& [id, info] : before) done_before += info.state == "DONE";
  ASSERT_GE(done_before, 1) << fleet.log_of("fleet-server");

  fleet.processes().signal(0, SIGKILL);  // the active server's host dies
  EXPECT_TRUE(
      eventually([&] { return fleet.log_of("fleet-server-standby").find("taking over") != std::string::npos; }, 10s))
      << fleet.log_of("fleet-server-standby");

  // The robots carry on under the standby: two more orders done.
  const auto orders = orders_once_done(client, done_before + 2, 90s);
  ASSERT_FALSE(orders.empty());
  // Ids are contiguous from 1 across both servers: none vanished, none was given twice.
  EXPECT_EQ(orders.begin()->first, 1);
  EXPECT_EQ(static_cast<std::size_t>(orders.rbegin()->first), orders.size());
  long done = 0;
  for (const auto& [id, info] : orders) {
    done += info.state == "DONE";
    int done_events = 0;
    for (const auto& e : info.history) done_events += e.state == "DONE";
    EXPECT_LE(done_events, 1) << "order " << id;
  }
  EXPECT_GE(done, done_before + 2) << fleet.log_of("fleet-server-standby");
  for (const auto& [id, count] : done_counts(fleet, robots)) EXPECT_EQ(count, 1) << "order " << id << " done twice";
  // Every order the active server had published is there, in a state no earlier than it was.
  for (const auto& [id, info] : before) {
    ASSERT_TRUE(orders.count(id)) << "order " << id << " lost in the takeover";
    EXPECT_GE(orders.at(id).history.size(), info.history.size()) << "order " << id;
  }
  EXPECT_NE(fleet.log_of("fleet-server-standby").find("restored"), std::string::npos)
      << fleet.log_of("fleet-server-standby");
}
