#include "server/order_store.hpp"

#include <filesystem>

#include "model/names.hpp"

namespace fleet::server {

namespace {

constexpr const char* kSchema = R"(
CREATE TABLE IF NOT EXISTS orders (
  id INTEGER PRIMARY KEY,
  request_id TEXT NOT NULL,
  pick_area TEXT NOT NULL,
  drop_area TEXT NOT NULL,
  fleet_id TEXT NOT NULL,
  robot_id TEXT NOT NULL,
  robot_requested INTEGER NOT NULL,
  priority INTEGER NOT NULL,
  status TEXT NOT NULL,
  phase TEXT NOT NULL,
  reason TEXT NOT NULL,
  update_id INTEGER NOT NULL,
  created_sim REAL NOT NULL,
  updated_sim REAL NOT NULL,
  assigned_sim REAL NOT NULL,
  finished_sim REAL NOT NULL
);
CREATE TABLE IF NOT EXISTS order_events (
  order_id INTEGER NOT NULL,
  seq INTEGER NOT NULL,
  sim_time REAL NOT NULL,
  status TEXT NOT NULL,
  phase TEXT NOT NULL,
  robot_id TEXT NOT NULL,
  reason TEXT NOT NULL,
  robot_x REAL NOT NULL,
  robot_y REAL NOT NULL,
  PRIMARY KEY (order_id, seq)
);
CREATE TABLE IF NOT EXISTS robot_bodies (
  robot_id TEXT PRIMARY KEY,
  x REAL NOT NULL,
  y REAL NOT NULL,
  yaw REAL NOT NULL
);
CREATE TABLE IF NOT EXISTS pallets (
  id INTEGER PRIMARY KEY,
  x REAL NOT NULL,
  y REAL NOT NULL,
  yaw REAL NOT NULL,
  area_id TEXT NOT NULL,
  carried_by TEXT NOT NULL
);
)";

/// Schema changes since the first release, applied in order to a database whose user_version is
/// below their number; a database written before any of them (version 0) keeps every order.
constexpr const char* kMigrations[] = {
    // 1: orders have a kind (transport, move, pick); every earlier order was a transport.
    "ALTER TABLE orders ADD COLUMN kind TEXT NOT NULL DEFAULT 'transport';",
    // 2: a pick order keeps its tour's lines (CSV); no earlier order had any.
    "ALTER TABLE orders ADD COLUMN lines TEXT NOT NULL DEFAULT '';",
    // 3: an order the server created for the packing chain says why, and after which orders.
    "ALTER TABLE orders ADD COLUMN cause TEXT NOT NULL DEFAULT '';"
    "ALTER TABLE orders ADD COLUMN caused_by TEXT NOT NULL DEFAULT '';",
    // 4: the site's state (orders::SiteState) is one JSON document; the pallets it held move into it.
    "CREATE TABLE site_state (id INTEGER PRIMARY KEY CHECK (id = 1), json TEXT NOT NULL);"
    "INSERT INTO site_state SELECT 1, json_object('version', 1, 'map', '', 'loads', json_group_array(json_object("
    "'id', id, 'kind', 'pallet', 'x', x, 'y', y, 'yaw', yaw, 'place', area_id, 'carried_by', carried_by)), "
    "'held_unnamed', json_array(), 'parked_at', json_object(), 'obstacles', json_object()) "
    "FROM pallets HAVING COUNT(*) > 0;"
    "DROP TABLE pallets;",
    // 5: the last term the server served in as active (orders::ServerTerm).
    "CREATE TABLE server_term (id INTEGER PRIMARY KEY CHECK (id = 1), term INTEGER NOT NULL);",
    // 6: a pick order worked as a loader walk, and the transports of its pallets.
    "ALTER TABLE orders ADD COLUMN loader INTEGER NOT NULL DEFAULT 0;",
};

std::string text_column(sqlite3_stmt* stmt, int column) {
  const auto* t = sqlite3_column_text(stmt, column);
  return t ? reinterpret_cast<const char*>(t) : "";
}

}  // namespace

OrderStore::OrderStore(const std::string& path) : path_(path) {
  const auto parent = std::filesystem::path(path).parent_path();
  std::error_code error;
  if (!parent.empty()) std::filesystem::create_directories(parent, error);
  if (error) throw StoreError(path + ": cannot create the folder of the order database: " + error.message());
  if (sqlite3_open(path.c_str(), &db_) != SQLITE_OK) {
    const std::string why = db_ ? sqlite3_errmsg(db_) : "out of memory";
    sqlite3_close(db_);
    db_ = nullptr;
    throw StoreError(path + ": cannot open the order database: " + why);
  }
  sqlite3_busy_timeout(db_, 2000);
  exec("PRAGMA journal_mode=WAL");
  exec("PRAGMA synchronous=NORMAL");
  // The first schema, which the migrations then bring up to date; a database past it has its tables.
  if (schema_version() == 0) exec(kSchema);
  migrate();
  auto prepare = [&](const char* sql, sqlite3_stmt** stmt) {
    if (sqlite3_prepare_v2(db_, sql, -1, stmt, nullptr) != SQLITE_OK) {
      throw StoreError(path_ + ": " + sqlite3_errmsg(db_));
    }
  };
  prepare(
      "INSERT INTO orders VALUES (?1,?2,?3,?4,?5,?6,?7,?8,?9,?10,?11,?12,?13,?14,?15,?16,?17,?18,?19,?20,?21) "
      "ON CONFLICT(id) DO UPDATE SET drop_area=?4, robot_id=?6, status=?9, phase=?10, reason=?11, update_id=?12, "
      "updated_sim=?14, assigned_sim=?15, finished_sim=?16",
      &upsert_);
  prepare("SELECT COUNT(*) FROM order_events WHERE order_id=?1", &count_events_);
  prepare("INSERT INTO order_events VALUES (?1,?2,?3,?4,?5,?6,?7,?8,?9)", &insert_event_);
  prepare("INSERT OR REPLACE INTO site_state VALUES (1, ?1)", &upsert_site_state_);
}

OrderStore::~OrderStore() {
  sqlite3_finalize(upsert_);
  sqlite3_finalize(count_events_);
  sqlite3_finalize(insert_event_);
  sqlite3_finalize(upsert_site_state_);
  sqlite3_close(db_);
}

int OrderStore::schema_version() const {
  sqlite3_stmt* stmt = nullptr;
  sqlite3_prepare_v2(db_, "PRAGMA user_version", -1, &stmt, nullptr);
  const int version = sqlite3_step(stmt) == SQLITE_ROW ? sqlite3_column_int(stmt, 0) : 0;
  sqlite3_finalize(stmt);
  return version;
}

void OrderStore::migrate() {
  const int latest = static_cast<int>(std::size(kMigrations));
  for (int version = schema_version(); version < latest; ++version) {
    exec("BEGIN IMMEDIATE");
    try {
      exec(kMigrations[version]);
      exec(("PRAGMA user_version=" + std::to_string(version + 1)).c_str());
      exec("COMMIT");
    } catch (const StoreError& e) {
      sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr);
      throw StoreError(std::string(e.what()) + " (while migrating the order database to schema version " +
                       std::to_string(version + 1) + ")");
    }
  }
}

void OrderStore::exec(const char* sql) const {
  char* error = nullptr;
  if (sqlite3_exec(db_, sql, nullptr, nullptr, &error) != SQLITE_OK) {
    const std::string why = error ? error : "unknown error";
    sqlite3_free(error);
    throw StoreError(path_ + ": " + why);
  }
}

void OrderStore::save(const orders::Order& o) {
  exec("BEGIN IMMEDIATE");
  try {
    auto step = [&](sqlite3_stmt* stmt) {
      const int rc = sqlite3_step(stmt);
      sqlite3_reset(stmt);
      if (rc != SQLITE_DONE && rc != SQLITE_ROW) throw StoreError(path_ + ": " + sqlite3_errmsg(db_));
    };
    sqlite3_bind_int64(upsert_, 1, o.id);
    sqlite3_bind_text(upsert_, 2, o.request_id.c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_bind_text(upsert_, 3, o.pick_area.c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_bind_text(upsert_, 4, o.drop_area.c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_bind_text(upsert_, 5, o.fleet_id.c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_bind_text(upsert_, 6, o.robot_id.c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_bind_int(upsert_, 7, o.robot_requested ? 1 : 0);
    sqlite3_bind_int(upsert_, 8, o.priority);
    sqlite3_bind_text(upsert_, 9, std::string(orders::to_string(o.status)).c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_bind_text(upsert_, 10, std::string(orders::to_string(o.phase)).c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_bind_text(upsert_, 11, o.reason.c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_bind_int64(upsert_, 12, o.update_id);
    sqlite3_bind_double(upsert_, 13, o.created_sim);
    sqlite3_bind_double(upsert_, 14, o.updated_sim);
    sqlite3_bind_double(upsert_, 15, o.assigned_sim);
    sqlite3_bind_double(upsert_, 16, o.finished_sim);
    sqlite3_bind_text(upsert_, 17, std::string(orders::to_string(o.kind)).c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_bind_text(upsert_, 18, o.lines.c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_bind_text(upsert_, 19, o.cause.c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_bind_text(upsert_, 20, model::ids_text(o.caused_by).c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_bind_int(upsert_, 21, o.loader ? 1 : 0);
    step(upsert_);

    sqlite3_bind_int64(count_events_, 1, o.id);
    std::size_t stored = 0;
    if (sqlite3_step(count_events_) == SQLITE_ROW)
      stored = static_cast<std::size_t>(sqlite3_column_int64(count_events_, 0));
    sqlite3_reset(count_events_);
    for (std::size_t i = stored; i < o.history.size(); ++i) {
      const auto& e = o.history[i];
      sqlite3_bind_int64(insert_event_, 1, o.id);
      sqlite3_bind_int64(insert_event_, 2, static_cast<sqlite3_int64>(i));
      sqlite3_bind_double(insert_event_, 3, e.sim_time);
      sqlite3_bind_text(insert_event_, 4, std::string(orders::to_string(e.status)).c_str(), -1, SQLITE_TRANSIENT);
      sqlite3_bind_text(insert_event_, 5, std::string(orders::to_string(e.phase)).c_str(), -1, SQLITE_TRANSIENT);
      sqlite3_bind_text(insert_event_, 6, e.robot_id.c_str(), -1, SQLITE_TRANSIENT);
      sqlite3_bind_text(insert_event_, 7, e.reason.c_str(), -1, SQLITE_TRANSIENT);
      sqlite3_bind_double(insert_event_, 8, e.robot_x);
      sqlite3_bind_double(insert_event_, 9, e.robot_y);
      step(insert_event_);
    }
    exec("COMMIT");
  } catch (...) {
    sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr);
    throw;
  }
}

std::vector<orders::Order> OrderStore::load_all() const {
  std::vector<orders::Order> out;
  sqlite3_stmt* stmt = nullptr;
  sqlite3_prepare_v2(
      db_,
      "SELECT id, request_id, pick_area, drop_area, fleet_id, robot_id, robot_requested, priority, "
      "status, phase, reason, update_id, created_sim, updated_sim, assigned_sim, finished_sim, kind, lines, "
      "cause, caused_by, loader FROM orders ORDER BY id",
      -1, &stmt, nullptr);
  while (sqlite3_step(stmt) == SQLITE_ROW) {
    orders::Order o;
    o.id = sqlite3_column_int64(stmt, 0);
    o.request_id = text_column(stmt, 1);
    o.pick_area = text_column(stmt, 2);
    o.drop_area = text_column(stmt, 3);
    o.fleet_id = text_column(stmt, 4);
    o.robot_id = text_column(stmt, 5);
    o.robot_requested = sqlite3_column_int(stmt, 6) != 0;
    o.priority = sqlite3_column_int(stmt, 7);
    const auto status = orders::parse_status(text_column(stmt, 8));
    if (!status)
      throw StoreError(path_ + ": order " + std::to_string(o.id) + " has unknown status '" + text_column(stmt, 8) +
                       "'");
    o.status = *status;
    o.phase = orders::parse_phase(text_column(stmt, 9)).value_or(orders::OrderPhase::kNone);
    o.reason = text_column(stmt, 10);
    o.update_id = static_cast<std::uint32_t>(sqlite3_column_int64(stmt, 11));
    o.created_sim = sqlite3_column_double(stmt, 12);
    o.updated_sim = sqlite3_column_double(stmt, 13);
    o.assigned_sim = sqlite3_column_double(stmt, 14);
    o.finished_sim = sqlite3_column_double(stmt, 15);
    const auto kind = orders::parse_kind(text_column(stmt, 16));
    if (!kind) {
      throw StoreError(path_ + ": order " + std::to_string(o.id) + " has unknown kind '" + text_column(stmt, 16) + "'");
    }
    o.kind = *kind;
    o.lines = text_column(stmt, 17);
    o.cause = text_column(stmt, 18);
    const auto caused_by = model::parse_ids(text_column(stmt, 19));
    if (!caused_by) {
      throw StoreError(path_ + ": order " + std::to_string(o.id) + " has caused_by '" + text_column(stmt, 19) +
                       "', not order ids");
    }
    o.caused_by = *caused_by;
    o.loader = sqlite3_column_int(stmt, 20) != 0;
    out.push_back(std::move(o));
  }
  sqlite3_finalize(stmt);
  sqlite3_prepare_v2(db_,
                     "SELECT order_id, sim_time, status, phase, robot_id, reason, robot_x, robot_y FROM order_events "
                     "ORDER BY order_id, seq",
                     -1, &stmt, nullptr);
  std::size_t cursor = 0;
  while (sqlite3_step(stmt) == SQLITE_ROW) {
    const std::int64_t id = sqlite3_column_int64(stmt, 0);
    while (cursor < out.size() && out[cursor].id < id) ++cursor;
    if (cursor >= out.size() || out[cursor].id != id) continue;
    orders::OrderEvent e;
    e.sim_time = sqlite3_column_double(stmt, 1);
    e.status = orders::parse_status(text_column(stmt, 2)).value_or(orders::OrderStatus::kQueued);
    e.phase = orders::parse_phase(text_column(stmt, 3)).value_or(orders::OrderPhase::kNone);
    e.robot_id = text_column(stmt, 4);
    e.reason = text_column(stmt, 5);
    e.robot_x = sqlite3_column_double(stmt, 6);
    e.robot_y = sqlite3_column_double(stmt, 7);
    out[cursor].history.push_back(std::move(e));
  }
  sqlite3_finalize(stmt);
  return out;
}

void OrderStore::save_site_state(const std::string& json) {
  sqlite3_bind_text(upsert_site_state_, 1, json.c_str(), static_cast<int>(json.size()), SQLITE_TRANSIENT);
  const int rc = sqlite3_step(upsert_site_state_);
  sqlite3_reset(upsert_site_state_);
  if (rc != SQLITE_DONE) throw StoreError(path_ + ": " + sqlite3_errmsg(db_));
}

std::optional<std::string> OrderStore::load_site_state() const {
  std::optional<std::string> out;
  sqlite3_stmt* stmt = nullptr;
  sqlite3_prepare_v2(db_, "SELECT json FROM site_state WHERE id = 1", -1, &stmt, nullptr);
  if (sqlite3_step(stmt) == SQLITE_ROW) out = text_column(stmt, 0);
  sqlite3_finalize(stmt);
  return out;
}

void OrderStore::save_term(std::int64_t term) {
  exec(("INSERT OR REPLACE INTO server_term (id, term) VALUES (1, " + std::to_string(term) + ")").c_str());
}

std::int64_t OrderStore::term() const {
  std::int64_t term = 0;
  sqlite3_stmt* stmt = nullptr;
  sqlite3_prepare_v2(db_, "SELECT term FROM server_term WHERE id = 1", -1, &stmt, nullptr);
  if (sqlite3_step(stmt) == SQLITE_ROW) term = sqlite3_column_int64(stmt, 0);
  sqlite3_finalize(stmt);
  return term;
}

void OrderStore::save_robot_poses(const std::map<std::string, geometry::Pose2>& poses) {
  if (poses.empty()) return;
  exec("BEGIN IMMEDIATE");
  sqlite3_stmt* stmt = nullptr;
  try {
    if (sqlite3_prepare_v2(db_, "INSERT OR REPLACE INTO robot_bodies (robot_id, x, y, yaw) VALUES (?, ?, ?, ?)", -1,
                           &stmt, nullptr) != SQLITE_OK) {
      throw StoreError(path_ + ": " + sqlite3_errmsg(db_));
    }
    for (const auto& [id, pose] : poses) {
      sqlite3_bind_text(stmt, 1, id.c_str(), -1, SQLITE_TRANSIENT);
      sqlite3_bind_double(stmt, 2, pose.x);
      sqlite3_bind_double(stmt, 3, pose.y);
      sqlite3_bind_double(stmt, 4, pose.yaw);
      const int rc = sqlite3_step(stmt);
      sqlite3_reset(stmt);
      if (rc != SQLITE_DONE) throw StoreError(path_ + ": " + sqlite3_errmsg(db_));
    }
    sqlite3_finalize(stmt);
    exec("COMMIT");
  } catch (const StoreError&) {
    sqlite3_finalize(stmt);
    sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr);
    throw;
  }
}

std::map<std::string, geometry::Pose2> OrderStore::load_robot_poses() const {
  std::map<std::string, geometry::Pose2> out;
  sqlite3_stmt* stmt = nullptr;
  sqlite3_prepare_v2(db_, "SELECT robot_id, x, y, yaw FROM robot_bodies", -1, &stmt, nullptr);
  while (sqlite3_step(stmt) == SQLITE_ROW) {
    out[text_column(stmt, 0)] = {sqlite3_column_double(stmt, 1), sqlite3_column_double(stmt, 2),
                                 sqlite3_column_double(stmt, 3)};
  }
  sqlite3_finalize(stmt);
  return out;
}

std::int64_t OrderStore::next_id() const {
  sqlite3_stmt* stmt = nullptr;
  sqlite3_prepare_v2(db_, "SELECT COALESCE(MAX(id), 0) + 1 FROM orders", -1, &stmt, nullptr);
  std::int64_t next = 1;
  if (sqlite3_step(stmt) == SQLITE_ROW) next = sqlite3_column_int64(stmt, 0);
  sqlite3_finalize(stmt);
  return next;
}

}  // namespace fleet::server
