// A hot standby with real processes: the active server is killed with SIGKILL mid-run, and the
// standby, which mirrored its orders and site state, takes over; the robots carry on under it.

#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <thread>

#include "cli/client.hpp"
#include "fleet_harness.hpp"
#include "monitor/order_accounting.hpp"
#include "orders/order.hpp"
#include "orders/server_term.hpp"
#include "scripted_fleet.hpp"

using namespace fleet;
using namespace fleet::testing;
using namespace std::chrono_literals;

namespace {

/// Starts `fleet-server --standby` on a database of its own, logging to `name`.log, with `extra`
/// arguments.
void start_standby(FleetHarness& fleet, const std::string& name, const std::vector<std::string>& extra) {
  std::vector<std::string> argv{bin("fleet-server"), "--db", fleet.log_dir() + "/" + name + ".db"};
  for (const auto& a : fleet.common_args()) argv.push_back(a);
  for (const char* a : {"--standby", "--auto-orders", "--http-port", "0"}) argv.emplace_back(a);
  argv.insert(argv.end(), extra.begin(), extra.end());
  fleet.processes().start(name, argv, fleet.log_dir() + "/" + name + ".log");
}

/// The orders in `orders` that are DONE.
long done_in(const std::map<std::int64_t, model::OrderInfo>& orders) {
  long done = 0;
  for (const auto& [id, info] : orders) done += info.state == "DONE";
  return done;
}

/// Starts an agent for each of `robots` and waits for work under way under the active server: at
/// least one order done (and mirrored). Returns the orders then.
std::map<std::int64_t, model::OrderInfo> at_work(FleetHarness& fleet, cli::FleetClient& client,
                                                 const std::vector<std::string>& robots) {
  for (const auto& r : robots) fleet.start_agent(r);
  EXPECT_TRUE(client.find_server(5s));
  return orders_once_done(client, 1, 60s);
}

}  // namespace

TEST(Standby, TakesOverWhenTheActiveServerIsKilledAndLosesNoOrderAndRunsNoneTwice) {
  FleetHarness fleet(73, 10.0);
  fleet.start_server({"--auto-orders"});  // process 0: the active server
  start_standby(fleet, "fleet-server-standby", {});
  const std::vector<std::string> robots{"fl1", "fl2"};
  cli::FleetClient client(73);
  const auto before = at_work(fleet, client, robots);
  const long done_before = done_in(before);
  ASSERT_GE(done_before, 1) << fleet.log_of("fleet-server");

  fleet.processes().signal(0, SIGKILL);  // the active server's host dies
  EXPECT_TRUE(
      eventually([&] { return fleet.log_of("fleet-server-standby").find("taking over") != std::string::npos; }, 10s))
      << fleet.log_of("fleet-server-standby");

  // The robots carry on under the standby: two more orders done.
  const auto orders = orders_once_done(client, done_before + 2, 90s);
  ASSERT_FALSE(orders.empty());
  // Ids run from 1, then from the start of term 2's block for the standby that took over: none
  // vanished, none was given twice.
  EXPECT_EQ(orders.begin()->first, 1);
  const auto tally = monitor::tally_orders(orders);
  EXPECT_EQ(tally.lost, 0);
  EXPECT_EQ(static_cast<std::size_t>(tally.created), orders.size());
  EXPECT_GE(orders.rbegin()->first, orders::first_order_id(2)) << "the takeover's orders begin term 2's block";
  long done = 0;
  for (const auto& [id, info] : orders) {
    done += info.state == "DONE";
    int done_events = 0;
    for (const auto& e : info.history) done_events += e.state == "DONE";
    EXPECT_LE(done_events, 1) << "order " << id;
  }
  EXPECT_GE(done, done_before + 2) << fleet.log_of("fleet-server-standby");
  const auto counts = done_counts(fleet, robots);
  EXPECT_FALSE(counts.empty()) << "no order done in the robots' logs";
  for (const auto& [id, count] : counts) EXPECT_EQ(count, 1) << "order " << id << " done twice";
  // Every order the active server had published is there, in a state no earlier than it was.
  for (const auto& [id, info] : before) {
    ASSERT_TRUE(orders.count(id)) << "order " << id << " lost in the takeover";
    EXPECT_GE(orders.at(id).history.size(), info.history.size()) << "order " << id;
  }
  EXPECT_NE(fleet.log_of("fleet-server-standby").find("restored"), std::string::npos)
      << fleet.log_of("fleet-server-standby");
}

namespace {

/// Occurrences of `what` in `text`.
std::size_t count_of(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size())) ++n;
  return n;
}

}  // namespace

// The active server's host freezes (SIGSTOP) for longer than its liveliness lease: the standby
// takes over in the next term. When the frozen server comes back (SIGCONT) it hears the server of
// the higher term, steps down before it acts on anything, and mirrors it as its standby; killed
// in turn, the new active server is followed by the old one taking over again. The robots go on
// under each, and no order is done twice.
TEST(Standby, AFrozenActiveServerThatComesBackStepsDownAndStandsByForTheOneThatTookOver) {
  FleetHarness fleet(74, 10.0);
  fleet.start_server({"--auto-orders", "--set", "server.id=server-a"});     // process 0
  start_standby(fleet, "fleet-server-b", {"--set", "server.id=server-b"});  // process 1
  const std::vector<std::string> robots{"fl1", "fl2"};
  cli::FleetClient client(74);
  const auto before = at_work(fleet, client, robots);
  const long done_before = done_in(before);
  ASSERT_GE(done_before, 1) << fleet.log_of("fleet-server");

  fleet.processes().signal(0, SIGSTOP);
  ASSERT_TRUE(eventually([&] { return fleet.log_of("fleet-server-b").find("taking over") != std::string::npos; }, 10s))
      << fleet.log_of("fleet-server-b");
  EXPECT_TRUE(
      eventually([&] { return fleet.log_of("fleet-server-b").find("server-b in term 2") != std::string::npos; }, 5s))
      << fleet.log_of("fleet-server-b");
  std::this_thread::sleep_for(3s);  // server b serves a while
  fleet.processes().signal(0, SIGCONT);
  ASSERT_TRUE(eventually([&] { return fleet.log_of("fleet-server").find("stepping down") != std::string::npos; }, 10s))
      << fleet.log_of("fleet-server");
  EXPECT_TRUE(eventually(
      [&] { return fleet.log_of("fleet-server").find("standby server-a: mirroring") != std::string::npos; }, 5s))
      << fleet.log_of("fleet-server");
  // Between coming back and stepping down it created no order: it listened first.
  const std::string a_log = fleet.log_of("fleet-server");
  const auto stood_still = a_log.find("stood still");
  ASSERT_NE(stood_still, std::string::npos) << a_log;
  EXPECT_EQ(count_of(a_log.substr(stood_still, a_log.find("stepping down") - stood_still), " created"), 0u) << a_log;

  // fleetctl servers names server b active in term 2, server a its standby.
  const auto servers = fleet.fleetctl({"servers", "--json"});
  ASSERT_EQ(servers.exit_code, 0) << servers.out << servers.err;
  const auto listed = nlohmann::json::parse(servers.out).at("servers");
  ASSERT_EQ(listed.size(), 2u) << servers.out;
  for (const auto& s : listed) {
    const bool is_b = s.at("server_id") == "server-b";
    EXPECT_EQ(s.at("role"), is_b ? "active" : "standby") << servers.out;
    if (is_b) {
      EXPECT_EQ(s.at("term"), 2) << servers.out;
    } else {
      EXPECT_LT(s.at("active_heard_s_ago").get<double>(), 1.5) << servers.out;
    }
  }

  const auto under_b = orders_once_done(client, done_before + 2, 90s);
  const long done_under_b = done_in(under_b);
  fleet.processes().signal(1, SIGKILL);  // server b's host dies; server a, its standby now, takes over
  ASSERT_TRUE(eventually([&] { return count_of(fleet.log_of("fleet-server"), "taking over") >= 1; }, 10s))
      << fleet.log_of("fleet-server");
  EXPECT_TRUE(
      eventually([&] { return fleet.log_of("fleet-server").find("server-a in term 3") != std::string::npos; }, 5s))
      << fleet.log_of("fleet-server");
  const auto orders = orders_once_done(client, done_under_b + 1, 90s);
  ASSERT_FALSE(orders.empty());
  EXPECT_EQ(orders.begin()->first, 1);
  const auto tally = monitor::tally_orders(orders);
  EXPECT_EQ(tally.lost, 0) << "an order id lost";
  EXPECT_EQ(static_cast<std::size_t>(tally.created), orders.size()) << "an order id given twice or lost";
  EXPECT_GE(orders.rbegin()->first, orders::first_order_id(3)) << "server a's takeover begins term 3's block";
  const auto counts = done_counts(fleet, robots);
  EXPECT_FALSE(counts.empty()) << "no order done in the robots' logs";
  for (const auto& [id, count] : counts) EXPECT_EQ(count, 1) << "order " << id << " done twice";
  for (const auto& [id, info] : under_b) {
    ASSERT_TRUE(orders.count(id)) << "order " << id << " lost in the second takeover";
  }
}
