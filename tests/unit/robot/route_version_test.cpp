// Route versions come from wall time (robot::first_route_version) and must keep growing for as
// long as the fleet runs: the traffic manager refuses a route whose version is not above the last
// one it knows of the robot. In 32 bits, sixteen versions a second since 2023 wrap on 2032-05-17.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <limits>

#include "robot/forklift/forklift.hpp"

namespace fleet::robot {
namespace {

using Clock = std::chrono::system_clock;

Clock::time_point at_unix(std::int64_t seconds) {
  return Clock::time_point(std::chrono::seconds(seconds));
}

constexpr std::int64_t k2030 = 1'893'456'000;       // 2030-01-01T00:00:00Z
constexpr std::int64_t k32BitWrap = 1'968'435'456;  // 2032-05-17T19:37:36Z: 1.7e9 + 2^32 / 16
constexpr std::int64_t k2040 = 2'208'988'800;       // 2040-01-01T00:00:00Z

TEST(RouteVersionOverflow, AClockIn2040StillGivesIncreasingVersions) {
  const std::uint64_t v2030 = first_route_version(at_unix(k2030));
  const std::uint64_t v2040 = first_route_version(at_unix(k2040));
  EXPECT_GT(v2040, v2030);
  EXPECT_GT(v2040, std::numeric_limits<std::uint32_t>::max());
  EXPECT_GT(first_route_version(at_unix(k2040 + 1)), v2040);
}

TEST(RouteVersionOverflow, VersionsKeepGrowingWhereThirtyTwoBitsWrap) {
  std::uint64_t previous = first_route_version(at_unix(k32BitWrap - 2));
  for (std::int64_t t = k32BitWrap - 1; t <= k32BitWrap + 2; ++t) {
    const std::uint64_t v = first_route_version(at_unix(t));
    EXPECT_GT(v, previous) << "unix time " << t;
    previous = v;
  }
}

TEST(RouteVersionOverflow, ARestartedAgentStartsAboveItsPreviousRun) {
  // Seven own routes in a second, the last re-routed by the manager (its version + 1), then a
  // restart: the new agent's first route is still newer than anything the manager knows.
  std::uint64_t v = first_route_version(at_unix(k2040));
  for (int i = 0; i < 7; ++i) v = next_own_route_version(v);
  const std::uint64_t rerouted = v + 1;
  EXPECT_GT(first_route_version(at_unix(k2040 + 1)), rerouted);
}

TEST(RouteVersionOverflow, OwnRoutesTakeEvenVersionsAboveTheManagersReroutes) {
  const std::uint64_t v = first_route_version(at_unix(k2040));
  EXPECT_EQ(v % 2, 0u);
  EXPECT_EQ(next_own_route_version(v), v + 2);
  EXPECT_EQ(next_own_route_version(v + 1), v + 2);  // after a re-route of the manager
  EXPECT_GT(next_own_route_version(v + 1), v + 1);
}

}  // namespace
}  // namespace fleet::robot
