#pragma once

#include <sqlite3.h>

#include <cstdint>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/errors.hpp"
#include "model/messages.hpp"
#include "orders/order.hpp"

namespace fleet::server {

/// The database cannot be opened or written; the message names the file.
class StoreError : public InputError {
 public:
  using InputError::InputError;
};

/// Orders and their events in SQLite (WAL mode). The server writes an order, and each of its
/// events, before it acknowledges or publishes them, so a `kill -9` at any moment loses nothing
/// that anyone was told about. Synchronous=NORMAL in WAL mode survives a process crash; it
/// trades only durability against power loss.
class OrderStore {
 public:
  /// Opens or creates the database at `path` (parent folders are created).
  explicit OrderStore(const std::string& path);
  ~OrderStore();
  OrderStore(const OrderStore&) = delete;
  OrderStore& operator=(const OrderStore&) = delete;

  /// Inserts or updates the order and appends the events not stored yet, in one transaction.
  void save(const orders::Order& order);

  /// Every stored order with its history, by id.
  std::vector<orders::Order> load_all() const;

  /// One past the largest id ever stored (ids are never reused).
  std::int64_t next_id() const;

  /// The site's state (orders::to_json of an orders::SiteState), so a restarted server keeps the
  /// truth of what stands where; nothing before the first save.
  void save_site_state(const std::string& json);
  std::optional<std::string> load_site_state() const;

  /// The last term this database's server served in as active (orders::ServerTerm); 0 before any.
  void save_term(std::int64_t term);
  std::int64_t term() const;

  /// Where robots were last heard standing, so that a restarted server holds the bodies of the
  /// robots it has not heard from yet. One transaction for all.
  void save_robot_poses(const std::map<std::string, geometry::Pose2>& poses);
  std::map<std::string, geometry::Pose2> load_robot_poses() const;

  const std::string& path() const { return path_; }
  /// The database's schema version (PRAGMA user_version) after the migrations on opening.
  int schema_version() const;

 private:
  void exec(const char* sql) const;
  void migrate();
  std::string path_;
  sqlite3* db_ = nullptr;
  sqlite3_stmt* upsert_ = nullptr;
  sqlite3_stmt* count_events_ = nullptr;
  sqlite3_stmt* insert_event_ = nullptr;
  sqlite3_stmt* upsert_site_state_ = nullptr;
};

}  // namespace fleet::server
