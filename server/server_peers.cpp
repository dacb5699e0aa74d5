#include "server/server_peers.hpp"

#include <utility>

namespace fleet::server {

ServerPeers::ServerPeers(dds::Participant& participant, orders::ServerTerm self)
    : reader_(participant, dds::qos::live_state()), self_(std::move(self)) {}

std::optional<model::ServerLoad> ServerPeers::outranking_active() {
  std::optional<model::ServerLoad> outranking;
  reader_.take_data([&](model::ServerLoad&& load) {
    if (!load.active || load.server_id == self_.server_id) return;
    const orders::ServerTerm other{.term = load.term,
                                   .took_over = load.took_over,
                                   .since_unix_ms = load.since_unix_ms,
                                   .server_id = load.server_id};
    if (orders::outranks(other, self_)) outranking = std::move(load);
  });
  return outranking;
}

}  // namespace fleet::server
