// The stacker's docking: the docking law's cost per control step, and one depth frame rendered
// and searched for the pallet. They measure; they never assert a time.
#include <benchmark/benchmark.h>

#include <memory>
#include <numbers>

#include "control/docking_law.hpp"
#include "perception/pallet_detector.hpp"
#include "sim/depth_camera.hpp"
#include "sim/tricycle.hpp"

namespace {

using fleet::geometry::Pose2;

const Pose2 kPallet{11.6, -0.6, std::numbers::pi / 2};

// The law driving the tricycle through a whole docking with a perfect detection each step: the
// mean over every phase of the docking, as the controller runs it at 20 Hz.
void BM_DockingLawStep(benchmark::State& state) {
  const Pose2 start{7.6, 0.745, 0.0};
  fleet::sim::TricycleParams vehicle;
  fleet::control::DockingParams params;
  params.vehicle = vehicle.geometry;
  fleet::sim::Tricycle body(vehicle, start);
  auto law = std::make_unique<fleet::control::DockingLaw>(params, kPallet, start);
  for (auto _ : state) {
    fleet::control::DockingInput in;
    in.vehicle = body.pose();
    in.steer_angle = body.state().theta_steer;
    in.pallet_detection = kPallet;
    const auto out = law->update(in);
    benchmark::DoNotOptimize(out.command);
    if (out.phase == fleet::control::DockingPhase::kDone || out.phase == fleet::control::DockingPhase::kFailed) {
      state.PauseTiming();
      body.reset(start);
      law = std::make_unique<fleet::control::DockingLaw>(params, kPallet, start);
      state.ResumeTiming();
      continue;
    }
    state.PauseTiming();
    body.step(out.command, in.dt);
    state.ResumeTiming();
  }
}
BENCHMARK(BM_DockingLawStep);

fleet::sim::DepthScene row() {
  fleet::sim::DepthScene scene;
  scene.add_limiter({11.6, -0.6, std::numbers::pi}, 20.0, 1.2, 0.30);
  for (int k = -2; k <= 2; ++k) scene.add_pallet({11.6 + 1.5 * k, -0.6, std::numbers::pi / 2}, 0.30);
  return scene;
}

// The rear RealSense (640 x 480; the preset's mount is 0.85 m behind the pose) 1.75 m from the
// pallet face, as at the start of the final law.
const Pose2 kRearView{11.6, 1.75 + 0.85, std::numbers::pi / 2};

void BM_RealSenseFrame(benchmark::State& state) {
  const auto scene = row();
  fleet::sim::DepthCamera camera(fleet::sim::realsense_r200(), 1);
  for (auto _ : state) benchmark::DoNotOptimize(camera.render(scene, kRearView).depth.data());
}
BENCHMARK(BM_RealSenseFrame)->Unit(benchmark::kMillisecond);

// The same frame rendered only inside the detector's region of interest, as the stacker's
// cameras render it while docking.
void BM_RealSenseFrameWindow(benchmark::State& state) {
  const auto scene = row();
  fleet::sim::DepthCamera camera(fleet::sim::realsense_r200(), 1);
  fleet::perception::PalletExpectation expected;
  expected.pallet = fleet::geometry::map_pose_to_body(kRearView, kPallet);
  expected.base_height = 0.30;
  const auto window = fleet::perception::detection_window(camera.model(), expected);
  for (auto _ : state) benchmark::DoNotOptimize(camera.render(scene, kRearView, window).depth.data());
}
BENCHMARK(BM_RealSenseFrameWindow)->Unit(benchmark::kMillisecond);

void BM_DetectPalletRealSense(benchmark::State& state) {
  const auto scene = row();
  fleet::sim::DepthCamera camera(fleet::sim::realsense_r200(), 1);
  const auto image = camera.render(scene, kRearView);
  fleet::perception::PalletExpectation expected;
  expected.pallet = fleet::geometry::map_pose_to_body(kRearView, kPallet);
  expected.base_height = 0.30;
  for (auto _ : state) {
    const auto d = fleet::perception::detect_pallet(image, camera.model(), expected);
    if (!d.found) state.SkipWithError(d.reason.c_str());
    benchmark::DoNotOptimize(d.midpoint);
  }
}
BENCHMARK(BM_DetectPalletRealSense)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
