#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "control/pallet_pick.hpp"
#include "control/pallet_place.hpp"
#include "control/pallet_search.hpp"
#include "perception/marker_camera.hpp"
#include "perception/pallet_world.hpp"

namespace fleet::control {
namespace {

using geometry::Pose2;
using perception::MarkerDetection;

constexpr double kDt = 1.0 / 70.0;
// A loading area on table_a's lower edge: the pallet's marker faces +y, towards the road.
const Pose2 kArea{0.90, 0.12, std::numbers::pi / 2};

perception::PalletWorldParams world_params(const ForkliftGeometry& g) {
  perception::PalletWorldParams p;
  p.carry_x = g.carry_x;
  p.marker_offset = g.marker_offset;
  return p;
}

perception::MarkerCameraParams camera_params(const ForkliftGeometry& g) {
  perception::MarkerCameraParams p;
  p.camera_x = g.camera_x;
  return p;
}

/// Steps a kinematic forklift with the camera on until `done` or `max_time`.
template <typename StepFn, typename DoneFn>
Pose2 drive(Pose2 pose, perception::PalletWorld& world, perception::MarkerCamera& cam, double max_time, StepFn step,
            DoneFn done) {
  for (int i = 0; i < static_cast<int>(max_time / kDt) && !done(); ++i) {
    const double t = i * kDt;
    std::vector<MarkerDetection> dets;
    if (cam.frame_due(t)) {
      const auto markers = world.markers();
      dets = cam.capture(t, pose, markers);
    }
    const ForkCommand fc = step(t, pose, dets);
    world.update(0, pose, fc.fork_up);
    pose = integrate_twist(pose, fc.twist, kDt);
  }
  return pose;
}

/// Searches kArea, arriving on the road beside it heading along the road (+x), short of the
/// search pose.
void search_from_the_road(PalletSearch& search, perception::PalletWorld& world, perception::MarkerCamera& cam,
                          double max_time) {
  search.start(kArea);
  drive(
      {0.6, 0.43, 0.0}, world, cam, max_time,
      [&](double, const Pose2& pose, const std::vector<MarkerDetection>& dets) {
        return ForkCommand{search.step(pose, dets, kDt), false};
      },
      [&] { return search.done(); });
}

TEST(PalletSearch, FindsThePalletInFrontOfTheArea) {
  ForkliftGeometry g;
  perception::PalletWorld world(world_params(g));
  world.add(kArea);
  perception::MarkerCamera cam(camera_params(g), 5);
  PalletSearch search({}, g);
  search_from_the_road(search, world, cam, 30.0);
  EXPECT_EQ(search.status(), SearchStatus::kFound);
  EXPECT_EQ(search.marker_id(), 1);
}

TEST(PalletSearch, ReportsAnEmptyArea) {
  ForkliftGeometry g;
  perception::PalletWorld world(world_params(g));
  // A pallet on the neighbouring area only: visible during the sweep, but not the one ordered.
  world.add({1.25, 0.12, std::numbers::pi / 2});
  perception::MarkerCamera cam(camera_params(g), 5);
  PalletSearch search({}, g);
  search.start(kArea);
  int sweeping_steps = 0;
  drive(
      {0.6, 0.43, 0.0}, world, cam, 60.0,
      [&](double, const Pose2& pose, const std::vector<MarkerDetection>& dets) {
        if (search.status() == SearchStatus::kSweeping) ++sweeping_steps;
        return ForkCommand{search.step(pose, dets, kDt), false};
      },
      [&] { return search.done(); });
  EXPECT_EQ(search.status(), SearchStatus::kEmpty);
  EXPECT_GT(sweeping_steps, 0) << "it turned looking for the marker before giving up";
  // The operator learns what the camera saw: the neighbour's marker, 35 cm from where it looked.
  EXPECT_TRUE(search.empty_reason().starts_with("nearest marker 1 seen 0.3")) << search.empty_reason();
  EXPECT_TRUE(search.empty_reason().ends_with("(accepted within 0.10 m)")) << search.empty_reason();

  perception::PalletWorld bare(world_params(g));
  search_from_the_road(search, bare, cam, 60.0);
  EXPECT_EQ(search.status(), SearchStatus::kEmpty);
  EXPECT_EQ(search.empty_reason(), "no marker in view");
}

TEST(PalletPick, ServoCommandFollowsFig67Order) {
  PickParams p;
  bool aligned = false;
  MarkerDetection det;
  det.d = 0.30;
  det.alpha = 0.1;
  det.gamma = 0.2;
  BodyTwist c = PalletPick::servo_command(det, p, aligned);
  EXPECT_DOUBLE_EQ(c.vy, p.v_miny);  // alpha first, constant speed towards it
  EXPECT_DOUBLE_EQ(c.omega, 0.0);
  EXPECT_DOUBLE_EQ(c.vx, 0.0);
  det.alpha = -0.1;
  EXPECT_DOUBLE_EQ(PalletPick::servo_command(det, p, aligned).vy, -p.v_miny);
  det.alpha = 0.0;
  det.gamma = 0.05;
  c = PalletPick::servo_command(det, p, aligned);
  EXPECT_DOUBLE_EQ(c.vy, 0.0);
  EXPECT_NEAR(c.omega, p.omega_min * 0.05 / p.gamma_min, 1e-12);  // eq. 6.4, proportional
  det.gamma = 0.0;
  c = PalletPick::servo_command(det, p, aligned);
  EXPECT_DOUBLE_EQ(c.vx, p.v_minx);
  det.d = 0.10;
  c = PalletPick::servo_command(det, p, aligned);
  EXPECT_DOUBLE_EQ(c.vx, -p.v_minx) << "too close: back off to d_min";
  EXPECT_FALSE(aligned);
  det.d = p.d_min;
  c = PalletPick::servo_command(det, p, aligned);
  EXPECT_TRUE(aligned);
  EXPECT_EQ(c, BodyTwist{});
}

TEST(PalletPick, ConvergesFromPerturbedStartsAndLifts) {
  ForkliftGeometry g;
  const Pose2 look = PalletSearch::search_pose(kArea, 0.30);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> lat(-0.04, 0.04);
  std::uniform_real_distribution<double> yaw(-0.25, 0.25);
  std::uniform_real_distribution<double> lon(-0.03, 0.05);
  int lifted = 0;
  const int runs = 20;
  for (int run = 0; run < runs; ++run) {
    perception::PalletWorld world(world_params(g));
    world.add(kArea);
    perception::MarkerCamera cam(camera_params(g), 100 + run);
    PalletPick pick({}, g);
    pick.start(1, 0.0);
    // Perturb the start: sideways along the road, out along the approach, turned. The pick
    // begins where the search stopped, i.e. with the marker in view: draw until it is.
    Pose2 start;
    perception::MarkerDetection in_view;
    do {
      start = {look.x + lat(rng), look.y + lon(rng), look.yaw + yaw(rng)};
    } while (!cam.ideal_measurement(start, world.markers().front(), in_view));
    perception::ForkEvent lift;
    drive(
        start, world, cam, 90.0,
        [&](double t, const Pose2& pose, const std::vector<MarkerDetection>& dets) {
          const ForkCommand fc = pick.step(t, dets, kDt);
          const auto ev = world.update(1, pose, fc.fork_up);  // robot 1: observe the lift
          if (ev.kind != perception::ForkEvent::Kind::kNone) lift = ev;
          return fc;
        },
        [&] { return pick.done(); });
    ASSERT_EQ(pick.status(), PickStatus::kDone) << "run " << run << ": " << pick.failure();
    if (lift.kind == perception::ForkEvent::Kind::kLifted) {
      ++lifted;
      EXPECT_LT(std::abs(lift.offset.y), 0.012) << "run " << run;
      EXPECT_LT(std::abs(lift.offset.x - g.carry_x), 0.012) << "run " << run;
      EXPECT_LT(std::abs(geometry::angle_diff(lift.offset.yaw, std::numbers::pi)), 0.05) << "run " << run;
    }
  }
  EXPECT_EQ(lifted, runs);
}

TEST(PalletPick, FailsWhenTheMarkerIsNeverSeen) {
  PickParams p;
  PalletPick pick(p);
  pick.start(4, 0.0);
  double t = 0.0;
  while (!pick.done() && t < 10.0) {
    pick.step(t, {}, kDt);
    t += kDt;
  }
  EXPECT_EQ(pick.status(), PickStatus::kFailed);
  EXPECT_NEAR(t, p.lost_timeout, 0.05);
}

TEST(PalletPlace, ConvergesFromPerturbedStartsHeadingFirst) {
  ForkliftGeometry g;
  PlaceParams p;
  const Pose2 road_end{0.90, 0.42, 0.0};  // on the road beside the area, heading along it
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> off(-0.04, 0.04);
  std::uniform_real_distribution<double> yaw(-0.3, 0.3);
  for (int run = 0; run < 20; ++run) {
    PalletPlace place(p, g);
    place.start(kArea, 0.0);
    Pose2 pose{road_end.x + off(rng), road_end.y + off(rng), road_end.yaw + yaw(rng)};
    const Pose2 target = place.target();
    Pose2 at_lowering;
    bool lowered = false;
    double t = 0.0;
    bool translated_before_heading = false;
    while (!place.done() && t < 90.0) {
      const ForkCommand fc = place.step(t, pose, kDt);
      if (place.status() == PlaceStatus::kHeading && (fc.twist.vx != 0.0 || fc.twist.vy != 0.0)) {
        translated_before_heading = true;
      }
      if (!fc.fork_up && !lowered) {
        lowered = true;
        at_lowering = pose;
      }
      pose = integrate_twist(pose, fc.twist, kDt);
      t += kDt;
    }
    ASSERT_EQ(place.status(), PlaceStatus::kDone) << "run " << run;
    EXPECT_FALSE(translated_before_heading) << "eq. 6.5: heading first";
    ASSERT_TRUE(lowered);
    EXPECT_LT(geometry::distance(at_lowering.position(), target.position()), 0.005) << "run " << run;
    EXPECT_LT(std::abs(geometry::angle_diff(at_lowering.yaw, target.yaw)), p.heading_tol + 1e-9);
    // Backed out along the approach, away from the area.
    EXPECT_NEAR(geometry::distance(pose.position(), at_lowering.position()), p.back_out_distance, 0.005);
  }
}

TEST(PalletPlace, PlacePoseSeatsThePalletOnTheArea) {
  ForkliftGeometry g;
  const Pose2 robot = PalletPlace::place_pose(kArea, g.carry_x);
  const geometry::Vec2 seat = geometry::body_to_map(robot, {g.carry_x, 0.0});
  EXPECT_NEAR(seat.x, kArea.x, 1e-12);
  EXPECT_NEAR(seat.y, kArea.y, 1e-12);
  EXPECT_NEAR(geometry::angle_diff(robot.yaw, kArea.yaw + std::numbers::pi), 0.0, 1e-12);
}

}  // namespace
}  // namespace fleet::control

namespace {
using fleet::geometry::Pose2;
using fleet::perception::PalletWorld;
}  // namespace

TEST(PalletWorldMirror, PlaceAddsOrMovesAndRemoveKeepsCarriedPalletsOnTheForks) {
  PalletWorld world;
  EXPECT_TRUE(world.place(7, {1.0, 1.0, 0.0}));
  EXPECT_TRUE(world.place(3, {2.0, 1.0, 0.0}));
  EXPECT_TRUE(world.place(7, {1.5, 1.0, 0.0}));  // moved, not duplicated
  ASSERT_EQ(world.pallets().size(), 2u);
  EXPECT_DOUBLE_EQ(world.find(7)->pose.x, 1.5);
  EXPECT_EQ(world.add({0.5, 0.5, 0.0}), 8);  // fresh ids never collide with mirrored ones

  // Robot 0 stands so that pallet 3 sits on its forks (pallet yaw = robot yaw + pi).
  const double carry_x = world.params().carry_x;
  const Pose2 robot{2.0 + carry_x, 1.0, 3.14159265358979};
  world.update(0, robot, false);
  const auto lifted = world.update(0, robot, true);
  ASSERT_EQ(lifted.kind, fleet::perception::ForkEvent::Kind::kLifted);
  EXPECT_EQ(lifted.pallet_id, 3);
  EXPECT_FALSE(world.place(3, {0.0, 0.0, 0.0}));  // on the forks: the mirror leaves it alone
  EXPECT_FALSE(world.remove(3));
  EXPECT_TRUE(world.remove(7));  // erasing a pallet before it keeps the forks' hold valid
  const Pose2 moved{robot.x + 0.5, robot.y, robot.yaw};
  world.update(0, moved, true);
  EXPECT_NEAR(world.find(3)->pose.x, moved.x - carry_x, 1e-9);
  EXPECT_EQ(world.update(0, moved, false).kind, fleet::perception::ForkEvent::Kind::kPutDown);
}
