#include "model/traffic_requests.hpp"

#include <gtest/gtest.h>

namespace fleet::model {
namespace {

TrafficRequest request_of(std::uint64_t version, double progress, double sim_time, const std::string& map = "m") {
  TrafficRequest request;
  request.robot_id = "fl1";
  request.version = version;
  request.points = {4, 5, 6, 7};
  request.progress = progress;
  request.sim_time = sim_time;
  request.map_id = map;
  return request;
}

TrafficProgress progress_sample(std::uint64_t version, double progress, double sim_time, const std::string& map = "m") {
  return {"fl1", version, progress, {}, sim_time, map};
}

TEST(TrafficRequestJoin, ProgressAppliesToTheLastRequestOfTheSameRouteWithItsPoints) {
  TrafficRequestJoin join;
  join.route(request_of(3, 0.1, 10.0));
  TrafficProgress progress = progress_sample(3, 0.45, 10.2);
  progress.stopped_for = {"fl2"};
  const auto joined = join.progress(progress);
  ASSERT_TRUE(joined.has_value());
  EXPECT_EQ(joined->points, (std::vector<int>{4, 5, 6, 7}));
  EXPECT_DOUBLE_EQ(joined->progress, 0.45);
  EXPECT_DOUBLE_EQ(joined->sim_time, 10.2);
  EXPECT_EQ(joined->stopped_for, std::vector<std::string>{"fl2"});
}

TEST(TrafficRequestJoin, ProgressBeforeItsRequestOrOnAnotherMapIsDropped) {
  TrafficRequestJoin join;
  EXPECT_FALSE(join.progress(progress_sample(3, 0.2, 10.0)).has_value());  // nothing heard of the robot
  join.route(request_of(3, 0.1, 10.0));
  EXPECT_FALSE(join.progress(progress_sample(4, 0.0, 10.5)).has_value());       // the new route is on its way
  EXPECT_FALSE(join.progress(progress_sample(3, 0.3, 10.5, "n")).has_value());  // another map's route
  join.forget("fl1");
  EXPECT_FALSE(join.progress(progress_sample(3, 0.3, 10.6)).has_value());
}

TEST(TrafficRequestJoin, ProgressOlderThanWhatWasAppliedIsDropped) {
  TrafficRequestJoin join;
  join.route(request_of(3, 0.1, 10.0));
  ASSERT_TRUE(join.progress(progress_sample(3, 0.5, 10.4)).has_value());
  EXPECT_FALSE(join.progress(progress_sample(3, 0.4, 10.3)).has_value());
}

TEST(TrafficRequestJoin, ALateRequestOfTheSameRouteKeepsTheLaterProgress) {
  TrafficRequestJoin join;
  join.route(request_of(3, 0.1, 10.0));
  ASSERT_TRUE(join.progress(progress_sample(3, 0.5, 10.4)).has_value());
  // The once-a-second repeat of the request, written before that progress, arrives after it.
  const TrafficRequest late = join.route(request_of(3, 0.3, 10.2));
  EXPECT_DOUBLE_EQ(late.progress, 0.5);
  EXPECT_DOUBLE_EQ(late.sim_time, 10.4);
  // A new route is taken as it comes, whatever was applied before.
  const TrafficRequest next = join.route(request_of(4, 0.0, 10.1));
  EXPECT_EQ(next.version, 4u);
  EXPECT_DOUBLE_EQ(next.progress, 0.0);
}

}  // namespace
}  // namespace fleet::model
