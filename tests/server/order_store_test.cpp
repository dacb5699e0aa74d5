#include "server/order_store.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "orders/order_book.hpp"

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
