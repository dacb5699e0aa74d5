#include "orders/server_term.hpp"

#include <algorithm>

namespace fleet::orders {

std::int64_t strength(const ServerTerm& server) {
  return 2 * server.term + (server.took_over ? 1 : 0);
}

bool outranks(const ServerTerm& other, const ServerTerm& self) {
  if (strength(other) != strength(self)) return strength(other) > strength(self);
  if (other.since_unix_ms != self.since_unix_ms) return other.since_unix_ms < self.since_unix_ms;
  return other.server_id > self.server_id;
}

std::int64_t next_term(std::int64_t stored, std::int64_t heard) {
  return std::max<std::int64_t>({stored, heard, 0}) + 1;
}

std::int64_t first_order_id(std::int64_t term) {
  return (std::max<std::int64_t>(term, 1) - 1) * kOrderIdsPerTerm + 1;
}

}  // namespace fleet::orders
