#include "server/order_store.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "orders/order_book.hpp"
#include "orders/site_state.hpp"
#include "server/robot_body_memory.hpp"

using namespace fleet;

namespace {
std::string fresh_db(const std::string& name) {
  const std::string path = ::testing::TempDir() + "/fleet-store-" + name + ".db";
  for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(path + suffix);
  return path;
}
orders::Order order_between(std::string pick, std::string drop, int priority) {
  orders::Order o{};
  o.pick_area = std::move(pick);
  o.drop_area = std::move(drop);
  o.priority = priority;
  return o;
}
}  // namespace

TEST(OrderStore, OrdersAndTheirEventsSurviveReopening) {
  const std::string path = fresh_db("reopen");
  orders::OrderBook book;
  {
    server::OrderStore store(path);
    const auto id = book.create(order_between("A1", "A2", 3), 10.0).id;
    store.save(*book.find(id));
    book.assign(id, "fl2", 11.0);
    book.locate_last_event(id, 0.5, 0.25);
    store.save(*book.find(id));
    book.set_phase(id, orders::OrderPhase::kPicking, 12.0);
    store.save(*book.find(id));
    store.save(*book.find(id));  // saving again adds no duplicate events
  }
  server::OrderStore reopened(path);
  const auto loaded = reopened.load_all();
  ASSERT_EQ(loaded.size(), 1u);
  const auto& o = loaded[0];
  EXPECT_EQ(o.pick_area, "A1");
  EXPECT_EQ(o.priority, 3);
  EXPECT_EQ(o.robot_id, "fl2");
  EXPECT_EQ(o.status, orders::OrderStatus::kActive);
  EXPECT_EQ(o.phase, orders::OrderPhase::kPicking);
  EXPECT_EQ(o.update_id, 1u);
  ASSERT_EQ(o.history.size(), 3u);
  EXPECT_EQ(o.history[1].status, orders::OrderStatus::kAssigned);
  EXPECT_DOUBLE_EQ(o.history[1].robot_x, 0.5);
  EXPECT_EQ(o.history[2].phase, orders::OrderPhase::kPicking);
  EXPECT_EQ(reopened.next_id(), 2);
}

TEST(OrderStore, NextIdNeverGoesBack) {
  const std::string path = fresh_db("ids");
  server::OrderStore store(path);
  EXPECT_EQ(store.next_id(), 1);
  orders::Order o;
  o.id = 41;
  o.history.push_back({});
  store.save(o);
  EXPECT_EQ(store.next_id(), 42);
}

TEST(OrderStore, UnwritablePathNamesTheFile) {
  try {
    server::OrderStore store("/proc/fleet-no-such-dir/orders.db");
    FAIL() << "opened an impossible path";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("/proc/fleet-no-such-dir"), std::string::npos) << e.what();
  }
}

// A database as the server wrote it before orders had kinds: its exact schema and rows, written
// with SQLite directly.
TEST(OrderStore, DatabaseWrittenBeforeOrderKindsKeepsEveryOrder) {
  const std::string path = fresh_db("schema0");
  {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
    const char* old = R"(
CREATE TABLE orders (id INTEGER PRIMARY KEY, request_id TEXT NOT NULL, pick_area TEXT NOT NULL,
  drop_area TEXT NOT NULL, fleet_id TEXT NOT NULL, robot_id TEXT NOT NULL, robot_requested INTEGER NOT NULL,
  priority INTEGER NOT NULL, status TEXT NOT NULL, phase TEXT NOT NULL, reason TEXT NOT NULL,
  update_id INTEGER NOT NULL, created_sim REAL NOT NULL, updated_sim REAL NOT NULL, assigned_sim REAL NOT NULL,
  finished_sim REAL NOT NULL);
CREATE TABLE order_events (order_id INTEGER NOT NULL, seq INTEGER NOT NULL, sim_time REAL NOT NULL,
  status TEXT NOT NULL, phase TEXT NOT NULL, robot_id TEXT NOT NULL, reason TEXT NOT NULL, robot_x REAL NOT NULL,
  robot_y REAL NOT NULL, PRIMARY KEY (order_id, seq));
INSERT INTO orders VALUES (1,'r1','A1','A2','','fl1',0,0,'DONE','','',3,1.0,9.0,2.0,9.0);
INSERT INTO orders VALUES (2,'r2','A3','A4','','fl2',0,5,'ACTIVE','TO_DROP','',2,3.0,4.0,3.5,0.0);
INSERT INTO orders VALUES (3,'r3','A5','A6','','',0,0,'QUEUED','','',0,5.0,5.0,0.0,0.0);
INSERT INTO order_events VALUES (2,0,3.0,'QUEUED','','','',0,0);
INSERT INTO order_events VALUES (2,1,3.5,'ASSIGNED','','fl2','',0.5,0.5);
)";
    ASSERT_EQ(sqlite3_exec(db, old, nullptr, nullptr, nullptr), SQLITE_OK);
    sqlite3_close(db);
  }
  server::OrderStore store(path);
  EXPECT_EQ(store.schema_version(), 6);
  const auto loaded = store.load_all();
  ASSERT_EQ(loaded.size(), 3u);
  for (const auto& o : loaded) EXPECT_EQ(o.kind, orders::OrderKind::kTransport) << o.id;
  for (const auto& o : loaded) EXPECT_EQ(o.lines, "") << o.id;
  for (const auto& o : loaded) EXPECT_TRUE(o.cause.empty() && o.caused_by.empty()) << o.id;
  EXPECT_EQ(loaded[1].pick_area, "A3");
  EXPECT_EQ(loaded[1].status, orders::OrderStatus::kActive);
  EXPECT_EQ(loaded[1].phase, orders::OrderPhase::kToDrop);
  EXPECT_EQ(loaded[1].history.size(), 2u);
  EXPECT_EQ(store.next_id(), 4);

  // New orders of any kind are stored beside the old ones, and the migration runs once.
  orders::Order move = order_between("", "H3", 0);
  move.id = 4;
  move.kind = orders::OrderKind::kMove;
  store.save(move);
  orders::Order tour = order_between("RB1", "PS1", 0);
  tour.id = 5;
  tour.kind = orders::OrderKind::kPick;
  tour.lines = "RB1,A1,1\nRB3,A3,1\n";
  store.save(tour);
  orders::Order full = order_between("PS1", "EX1", 0);
  full.id = 6;
  full.cause = "the pallet at PS1 is full: 2 boxes from order 5";
  full.caused_by = {5};
  store.save(full);
  server::OrderStore reopened(path);
  EXPECT_EQ(reopened.schema_version(), 6);
  const auto again = reopened.load_all();
  ASSERT_EQ(again.size(), 6u);
  EXPECT_EQ(again[5].cause, "the pallet at PS1 is full: 2 boxes from order 5");
  EXPECT_EQ(again[5].caused_by, std::vector<std::int64_t>{5});
  EXPECT_EQ(again[3].kind, orders::OrderKind::kMove);
  EXPECT_EQ(again[4].kind, orders::OrderKind::kPick);
  EXPECT_EQ(again[4].lines, "RB1,A1,1\nRB3,A3,1\n");
  EXPECT_EQ(again[3].drop_area, "H3");
}

TEST(OrderStore, TheSiteStateIsStoredWholeAndReplaced) {
  const std::string path = fresh_db("site-state");
  {
    server::OrderStore store(path);
    EXPECT_FALSE(store.load_site_state().has_value()) << "a fresh database holds no state: the site file's applies";
    store.save_site_state(R"({"first":1})");
    store.save_site_state(R"({"second":2})");
  }
  server::OrderStore reopened(path);
  EXPECT_EQ(reopened.load_site_state().value_or(""), R"({"second":2})");
}

// A loader job's order keeps what it is, and a drop place named by an update of it.
TEST(OrderStore, ALoaderOrderAndItsRevisedDropPlaceSurviveReopening) {
  const std::string path = fresh_db("loader");
  {
    server::OrderStore store(path);
    orders::Order transport;
    transport.id = 7;
    transport.pick_area = "PK1";
    transport.loader = true;
    store.save(transport);
    transport.drop_area = "EX1";
    store.save(transport);
  }
  server::OrderStore reopened(path);
  const auto orders = reopened.load_all();
  ASSERT_EQ(orders.size(), 1u);
  EXPECT_TRUE(orders[0].loader);
  EXPECT_EQ(orders[0].drop_area, "EX1");
}

TEST(OrderStore, TheServersTermSurvivesReopeningAndStartsAtNone) {
  const std::string path = fresh_db("term");
  {
    server::OrderStore store(path);
    EXPECT_EQ(store.term(), 0) << "a fresh database has served no term";
    store.save_term(3);
    store.save_term(4);
  }
  server::OrderStore reopened(path);
  EXPECT_EQ(reopened.term(), 4);
}

TEST(OrderStore, PalletsOfADatabaseBeforeTheSiteStateMoveIntoIt) {
  const std::string path = fresh_db("schema3-pallets");
  {
    server::OrderStore store(path);  // today's schema, then taken back to version 3 with its pallets table
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
    const char* back = R"(
DROP TABLE site_state;
DROP TABLE server_term;
ALTER TABLE orders DROP COLUMN loader;
CREATE TABLE pallets (id INTEGER PRIMARY KEY, x REAL NOT NULL, y REAL NOT NULL, yaw REAL NOT NULL,
  area_id TEXT NOT NULL, carried_by TEXT NOT NULL);
INSERT INTO pallets VALUES (1, 1.5, 2.0, 0.25, 'A1', '');
INSERT INTO pallets VALUES (2, 7.0, 3.0, -1.0, '', 'fk2');
PRAGMA user_version=3;
)";
    ASSERT_EQ(sqlite3_exec(db, back, nullptr, nullptr, nullptr), SQLITE_OK);
    sqlite3_close(db);
  }
  server::OrderStore store(path);
  EXPECT_EQ(store.schema_version(), 6);
  const auto json = store.load_site_state();
  ASSERT_TRUE(json.has_value());
  const orders::SiteNames names{"site", {{"A1", {1.5, 2.0, 0.0}}, {"A2", {3, 0, 0}}}, {"fk2"}, {}};
  const auto restored = orders::site_state_from_json(*json, names, path);
  EXPECT_TRUE(restored.dropped.empty());
  ASSERT_EQ(restored.state.ledger.loads().size(), 2u);
  EXPECT_TRUE(restored.state.ledger.holds_load("A1"));
  EXPECT_DOUBLE_EQ(restored.state.ledger.find(1)->pose.yaw, 0.25);
  ASSERT_NE(restored.state.ledger.carried_by("fk2"), nullptr);
  EXPECT_EQ(restored.state.ledger.carried_by("fk2")->id, 2);
}

TEST(RobotBodyMemory, WhereRobotsStoodSurvivesReopeningAndOnlyMovesAreWritten) {
  const std::string path = fresh_db("bodies");
  {
    server::OrderStore store(path);
    server::RobotBodyMemory memory(store);
    EXPECT_TRUE(memory.before_start().empty());
    memory.remember({{"fl1", {1.0, 2.0, 0.5}}, {"fl2", {3.0, 4.0, 0.0}}}, 10.0);
    // Too soon after the last write: nothing is stored, however far fl1 went.
    memory.remember({{"fl1", {1.5, 2.0, 0.5}}}, 10.05);
    EXPECT_EQ(store.load_robot_poses().at("fl1").x, 1.0);
    // A centimetre is not a move; half a metre is.
    memory.remember({{"fl1", {1.5, 2.0, 0.5}}, {"fl2", {3.01, 4.0, 0.0}}}, 10.2);
    EXPECT_EQ(store.load_robot_poses().at("fl1").x, 1.5);
    EXPECT_EQ(store.load_robot_poses().at("fl2").x, 3.0);
    // A quarter turn in place is.
    memory.remember({{"fl2", {3.0, 4.0, 1.57}}}, 10.4);
    EXPECT_NEAR(store.load_robot_poses().at("fl2").yaw, 1.57, 1e-9);
  }
  server::OrderStore reopened(path);
  const server::RobotBodyMemory memory(reopened);
  ASSERT_EQ(memory.before_start().size(), 2u);
  EXPECT_EQ(memory.before_start().at("fl1").x, 1.5);
  EXPECT_EQ(memory.before_start().at("fl1").y, 2.0);
  EXPECT_EQ(memory.before_start().at("fl2").y, 4.0);
}
