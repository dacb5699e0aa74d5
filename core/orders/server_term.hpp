#pragma once

#include <cstdint>
#include <string>

namespace fleet::orders {

/// Where a server stands among the servers of one fleet. A server takes a new term each time it
/// becomes active, one above every term it has held or heard: a standby that takes over serves in
/// the term above the one it mirrored. Its DDS writers of the server's topics carry its strength
/// (below) as ownership strength, and readers take the samples of the strongest live writer.
struct ServerTerm {
  std::int64_t term = 0;
  bool took_over = false;          ///< became active by taking over from another (a standby's takeover)
  std::int64_t since_unix_ms = 0;  ///< active since
  std::string server_id;
};

/// The ownership strength of its writers: twice its term, one more for a takeover. A server
/// restarted on its old database after a standby took over from it comes back in the standby's
/// term at best, and then with the lesser strength: robots go on following the one that took over.
std::int64_t strength(const ServerTerm& server);

/// Whether `other`, heard serving as active, outranks `self`: the greater strength, then the
/// server active longer, then the greater id. Both servers apply the same rule, so of two active
/// servers exactly one steps down.
bool outranks(const ServerTerm& other, const ServerTerm& self);

/// The term of a server becoming active: one above the last it held (`stored`) and the highest it
/// heard another server hold (`heard`).
std::int64_t next_term(std::int64_t stored, std::int64_t heard);

/// Order ids come in blocks of this many, one block per term.
inline constexpr std::int64_t kOrderIdsPerTerm = 1'000'000;

/// The first order id of a server that takes over in `term`: the start of the term's block, so
/// that the server that took over and one cut off from it (which goes on in the block of an
/// earlier term) never hand out the same id; (term - 1) x kOrderIdsPerTerm + 1. A server that
/// becomes active without taking over goes on from the ids it has.
std::int64_t first_order_id(std::int64_t term);

}  // namespace fleet::orders
