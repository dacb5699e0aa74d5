#include "coordination/place_index.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "forklift_places.hpp"
#include "map/site_map.hpp"
#include "test_paths.hpp"

namespace fleet::coordination {
namespace {

// The places near a circle are every place whose region may reach into it, found among the
// buckets round it rather than by a look at every place: on table_a, for circles anywhere on and
// off the table, each place that brute force finds within the circle's radius plus its reach is
// among those found.
TEST(PlaceIndex, FindsEveryPlaceWhoseRegionMayReachACircle) {
  const auto site = map::load_site_map(fleet::test::source_dir() + "/maps/table_a.yaml");
  const traffic::ConflictZones zones(site.graph.graph, testing::forklift_params());
  const PlaceIndex index(zones);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> coordinate(-1.0, 4.0);
  std::uniform_real_distribution<double> size(0.0, 0.5);
  std::size_t found_total = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const geometry::Vec2 centre{coordinate(rng), coordinate(rng)};
    const double radius = size(rng);
    std::vector<int> found = index.near(centre, radius);
    std::sort(found.begin(), found.end());
    found_total += found.size();
    for (int place = 0; place < static_cast<int>(zones.place_count()); ++place) {
      if (geometry::distance(centre, zones.position(place)) > radius + zones.reach(0, place)) continue;
      EXPECT_TRUE(std::binary_search(found.begin(), found.end(), place))
          << "place " << place << " near (" << centre.x << ", " << centre.y << ") radius " << radius;
    }
  }
  EXPECT_LT(found_total, 200 * zones.place_count() / 2) << "a look-up visits a part of the site, not all of it";
  EXPECT_GT(zones.reach(0, 0), 0.0);
}

}  // namespace
}  // namespace fleet::coordination
