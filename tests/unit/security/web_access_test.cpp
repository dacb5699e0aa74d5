// The web view's two roles and the delay that grows with failed authentications.

#include "model/web_access.hpp"

#include <gtest/gtest.h>

using namespace fleet::model;
using namespace std::chrono_literals;

namespace {
const WebTokens kTokens{"viewer-token-1234", "operator-token-99"};
}

TEST(WebAccess, EachTokenOpensItsRoleAndNothingElseOpensAny) {
  EXPECT_EQ(role_of("viewer-token-1234", kTokens), WebRole::kViewer);
  EXPECT_EQ(role_of("operator-token-99", kTokens), WebRole::kOperator);
  EXPECT_EQ(role_of("", kTokens), WebRole::kNone);
  EXPECT_EQ(role_of("viewer-token-123", kTokens), WebRole::kNone);    // a prefix
  EXPECT_EQ(role_of("viewer-token-12345", kTokens), WebRole::kNone);  // longer
  EXPECT_EQ(role_of("operator-token-98", kTokens), WebRole::kNone);
  // An unset token opens nothing, not even to an empty guess.
  EXPECT_EQ(role_of("", WebTokens{"", ""}), WebRole::kNone);
  EXPECT_FALSE(same_token("", ""));
}

TEST(WebAccess, TheOperatorMayDoWhatTheViewerMayAndMore) {
  EXPECT_TRUE(allows(WebRole::kOperator, WebRole::kViewer));
  EXPECT_TRUE(allows(WebRole::kOperator, WebRole::kOperator));
  EXPECT_TRUE(allows(WebRole::kViewer, WebRole::kViewer));
  EXPECT_FALSE(allows(WebRole::kViewer, WebRole::kOperator));
  EXPECT_FALSE(allows(WebRole::kNone, WebRole::kViewer));
}

TEST(WebAccess, TheDelayDoublesWithFailuresInARowUpToTheLongest) {
  FailedLogins logins;
  const auto t0 = FailedLogins::Clock::time_point{} + 1h;
  EXPECT_EQ(logins.failed("10.0.0.1", t0), 100ms);
  EXPECT_EQ(logins.failed("10.0.0.1", t0 + 1s), 200ms);
  EXPECT_EQ(logins.failed("10.0.0.1", t0 + 2s), 400ms);
  for (int i = 0; i < 40; ++i) (void)logins.failed("10.0.0.1", t0 + 3s);
  EXPECT_EQ(logins.failed("10.0.0.1", t0 + 4s), 5000ms);
  // Another address has its own count.
  EXPECT_EQ(logins.failed("10.0.0.2", t0 + 4s), 100ms);
  EXPECT_EQ(logins.total(), 45u);
}

TEST(WebAccess, ASuccessOrAQuietSpellClearsAnAddress) {
  FailedLogins logins({.first_delay = 100ms, .longest_delay = 5000ms, .forget_after = 600s});
  const auto t0 = FailedLogins::Clock::time_point{} + 1h;
  (void)logins.failed("a", t0);
  (void)logins.failed("a", t0);
  EXPECT_EQ(logins.in_a_row("a", t0), 2);
  logins.succeeded("a");
  EXPECT_EQ(logins.in_a_row("a", t0), 0);
  EXPECT_EQ(logins.failed("a", t0), 100ms);
  EXPECT_EQ(logins.failed("b", t0), 100ms);
  EXPECT_EQ(logins.in_a_row("b", t0 + 601s), 0);
  EXPECT_EQ(logins.failed("b", t0 + 601s), 100ms);
  EXPECT_EQ(logins.total(), 5u);  // the count since start is kept
}
