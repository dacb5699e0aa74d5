#include "orders/server_term.hpp"

#include <gtest/gtest.h>

namespace fleet::orders {
namespace {

TEST(ServerTerm, TheHigherTermOutranksWhateverTheRest) {
  EXPECT_TRUE(outranks({.term = 3, .since_unix_ms = 900, .server_id = "a"},
                       {.term = 2, .since_unix_ms = 100, .server_id = "z"}));
  EXPECT_FALSE(outranks({.term = 2, .since_unix_ms = 100, .server_id = "z"},
                        {.term = 3, .since_unix_ms = 900, .server_id = "a"}));
}

// A standby took over from server a in term 2; a, restarted on its old database, comes back in
// term 2 as well: the takeover outranks it, and its writers are the weaker ones.
TEST(ServerTerm, AServerRestartedAfterATakeoverStepsDownForTheOneThatTookOver) {
  const ServerTerm took_over{.term = next_term(0, 1), .took_over = true, .since_unix_ms = 1000, .server_id = "b"};
  const ServerTerm restarted{.term = next_term(1, 0), .took_over = false, .since_unix_ms = 2000, .server_id = "z"};
  EXPECT_EQ(took_over.term, restarted.term);
  EXPECT_TRUE(outranks(took_over, restarted));
  EXPECT_FALSE(outranks(restarted, took_over));
  EXPECT_GT(strength(took_over), strength(restarted));
}

TEST(ServerTerm, OfTwoEqualServersTheOneActiveLongerStaysThenTheGreaterIdAndExactlyOneStepsDown) {
  const ServerTerm a{.term = 4, .since_unix_ms = 100, .server_id = "host-a"};
  const ServerTerm b{.term = 4, .since_unix_ms = 200, .server_id = "host-b"};
  EXPECT_TRUE(outranks(a, b));
  EXPECT_FALSE(outranks(b, a));
  const ServerTerm c{.term = 4, .since_unix_ms = 100, .server_id = "host-c"};
  EXPECT_TRUE(outranks(c, a));
  EXPECT_FALSE(outranks(a, c));
  EXPECT_FALSE(outranks(a, a)) << "a server never steps down for itself";
}

TEST(ServerTerm, ANewTermIsAboveEveryTermHeldOrHeard) {
  EXPECT_EQ(next_term(0, 0), 1);
  EXPECT_EQ(next_term(5, 2), 6);
  EXPECT_EQ(next_term(2, 7), 8);
  EXPECT_EQ(next_term(-3, -1), 1) << "a damaged store never gives a term below the first";
}

}  // namespace
}  // namespace fleet::orders
