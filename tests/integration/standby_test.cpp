// A hot standby with real processes: the active server is killed with SIGKILL mid-run, and the
// standby, which mirrored its orders and site state, takes over; the robots carry on under it.

#include <gtest/gtest.h>
#include <httplib.h>
#include <signal.h>

#include <chrono>
#include <functional>
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
/// arguments; its web view on `http_port` (0: none) with the operator's token kStandbyToken.
constexpr const char* kStandbyToken = "standby-test-token";
void start_standby(FleetHarness& fleet, const std::string& name, const std::vector<std::string>& extra,
                   int http_port = 0) {
  std::vector<std::string> argv{bin("fleet-server"), "--db", fleet.log_dir() + "/" + name + ".db"};
  for (const auto& a : fleet.common_args()) argv.push_back(a);
  for (const char* a : {"--standby", "--auto-orders", "--api-token", kStandbyToken}) argv.emplace_back(a);
  argv.insert(argv.end(), {"--http-port", std::to_string(http_port)});
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

const httplib::Headers kStandbyAuth{{"Authorization", std::string("Bearer ") + kStandbyToken}};

/// The standby's /api/state once `ready` holds for it (within 10 s), or the last one read.
nlohmann::json standby_state(httplib::Client& http, const std::function<bool(const nlohmann::json&)>& ready) {
  nlohmann::json state;
  eventually(
      [&] {
        const auto r = http.Get("/api/state", kStandbyAuth);
        if (!r || r->status != 200) return false;
        state = nlohmann::json::parse(r->body, nullptr, false);
        return !state.is_discarded() && ready(state);
      },
      10s);
  return state;
}

bool shows_order(const nlohmann::json& state, std::int64_t id) {
  for (const auto& o : state["orders"]) {
    if (o["id"] == id) return true;
  }
  return false;
}

}  // namespace

TEST(Standby, TakesOverWhenTheActiveServerIsKilledAndLosesNoOrderAndRunsNoneTwice) {
  constexpr int kStandbyPort = 18173;  // unique to this test
  FleetHarness fleet(73, 10.0);
  fleet.start_server({"--auto-orders", "--set", "server.id=server-a"});  // process 0: the active server
  start_standby(fleet, "fleet-server-standby", {}, kStandbyPort);
  const std::vector<std::string> robots{"fl1", "fl2"};
  cli::FleetClient client(73);
  const auto before = at_work(fleet, client, robots);
  const long done_before = done_in(before);
  ASSERT_GE(done_before, 1) << fleet.log_of("fleet-server");

  // Meanwhile the standby's web view shows what it mirrors and the robots, and takes no request.
  httplib::Client http("127.0.0.1", kStandbyPort);
  const auto mirrored = standby_state(http, [&](const nlohmann::json& s) {
    return s["robots"].size() == robots.size() && shows_order(s, before.begin()->first);
  });
  EXPECT_EQ(mirrored["standby"], true) << mirrored.dump();
  EXPECT_EQ(mirrored["active_server"], "server-a") << mirrored.dump();
  EXPECT_EQ(mirrored["robots"].size(), robots.size()) << mirrored.dump();
  EXPECT_TRUE(shows_order(mirrored, before.begin()->first)) << mirrored.dump();
  const auto refused = http.Post("/api/orders", kStandbyAuth, R"({"from": "A1", "to": "A2"})", "application/json");
  ASSERT_TRUE(refused);
  EXPECT_EQ(refused->status, 409) << refused->body;
  EXPECT_NE(refused->body.find("standby server for server-a"), std::string::npos) << refused->body;

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
  // The same web view now serves the fleet.
  const auto serving = standby_state(http, [](const nlohmann::json& s) { return s["standby"] == false; });
  EXPECT_EQ(serving["standby"], false) << serving.dump();
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
  auto orders = orders_once_done(client, done_under_b + 1, 90s);
  // An order server b gave out may be the next one done, before server a has created one of its own.
  for (int more = 0; more < 3 && !orders.empty() && orders.rbegin()->first < orders::first_order_id(3); ++more) {
    orders = orders_once_done(client, done_in(orders) + 1, 60s);
  }
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
