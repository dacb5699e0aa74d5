#pragma once

#include <optional>

#include "dds/topics.hpp"
#include "orders/server_term.hpp"

namespace fleet::server {

/// The other servers of the fleet as an active server hears them (their ServerLoad, once a second
/// each): whether one that is active too outranks it (orders::outranks). Two active servers
/// happen when a server cut off from the others comes back after a standby took over; the one
/// outranked steps down.
class ServerPeers {
 public:
  ServerPeers(dds::Participant& participant, orders::ServerTerm self);

  /// The active server heard since the last call that outranks this one, if any.
  std::optional<model::ServerLoad> outranking_active();

  /// When this server last heard another before its latest silence of more than two ServerLoad
  /// periods (wall seconds; 0 when it never heard one): what changed since may be news to the
  /// others.
  double silence_began_wall() const { return silence_began_wall_; }

 private:
  dds::Reader<model::ServerLoad> reader_;
  orders::ServerTerm self_;
  double last_heard_wall_ = 0.0;
  double silence_began_wall_ = 0.0;
};

}  // namespace fleet::server
