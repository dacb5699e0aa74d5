#include "server/server_peers.hpp"

#include <utility>

#include "common/clock.hpp"

namespace fleet::server {

ServerPeers::ServerPeers(dds::Participant& participant, orders::ServerTerm self)
    : reader_(participant, dds::qos::live_state()), self_(std::move(self)) {}

std::optional<model::ServerLoad> ServerPeers::outranking_active() {
  std::optional<model::ServerLoad> outranking;
  constexpr double kSilenceS = 2.0;
  reader_.take_data([&](model::ServerLoad&& load) {
    if (load.server_id == self_.server_id) return;
    const double now = SimClock::wall_now();
    if (now - last_heard_wall_ > kSilenceS) silence_began_wall_ = last_heard_wall_;
    last_heard_wall_ = now;
    if (!load.active) return;
    const orders::ServerTerm other{.term = load.term,
                                   .took_over = load.took_over,
                                   .since_unix_ms = load.since_unix_ms,
                                   .server_id = load.server_id};
    if (orders::outranks(other, self_)) outranking = std::move(load);
  });
  return outranking;
}

}  // namespace fleet::server
