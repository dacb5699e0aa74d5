// Localization micro-benchmarks (target: EKF predict + update <= 5 us). They measure;
// they never assert a time.
#include <benchmark/benchmark.h>

#include <random>

#include "eval/loc_eval.hpp"
#include "localization/ekf.hpp"
#include "sim/uwb.hpp"

namespace {

using fleet::localization::Ekf;
using fleet::localization::EkfParams;

// A converged filter on a forklift driving a circle, so that every branch runs as in service.
Ekf warmed_up(const EkfParams& params) {
  Ekf ekf(params);
  ekf.update_uwb({1.05, 1.0});
  for (int i = 0; i < 400; ++i) {
    ekf.predict(0.2, 1.0 / 70.0);
    ekf.update_commanded({0.2, 0.0, 0.2});
    if (i % 4 == 0) ekf.update_uwb({1.05 + 0.0005 * i, 1.0 + 0.0002 * i});
  }
  return ekf;
}

void BM_EkfPredictUpdate(benchmark::State& state) {
  Ekf ekf = warmed_up(EkfParams::tuned());
  std::mt19937_64 rng(1);
  std::normal_distribution<double> n(0.0, 0.03);
  const Eigen::Matrix2d cov = 0.0025 * Eigen::Matrix2d::Identity();
  for (auto _ : state) {
    ekf.predict(0.2 + 0.01 * n(rng), 1.0 / 70.0);
    const auto p = ekf.pose();
    benchmark::DoNotOptimize(
        ekf.update_uwb({p.x + 0.05 * std::cos(p.yaw) + n(rng), p.y + 0.05 * std::sin(p.yaw) + n(rng)}, cov));
  }
}
BENCHMARK(BM_EkfPredictUpdate);

// The same with the thesis's filter (no gating, no velocity update).
void BM_EkfPredictUpdateSeed(benchmark::State& state) {
  Ekf ekf = warmed_up(EkfParams::seed());
  std::mt19937_64 rng(1);
  std::normal_distribution<double> n(0.0, 0.03);
  for (auto _ : state) {
    ekf.predict(0.2, 1.0 / 70.0);
    const auto p = ekf.pose();
    benchmark::DoNotOptimize(ekf.update_uwb({p.x + 0.05 + n(rng), p.y + n(rng)}));
  }
}
BENCHMARK(BM_EkfPredictUpdateSeed);

// One 70 Hz cycle of the tuned filter: predict, commanded-velocity update, UWB update.
void BM_EkfFullCycle(benchmark::State& state) {
  Ekf ekf = warmed_up(EkfParams::tuned());
  std::mt19937_64 rng(1);
  std::normal_distribution<double> n(0.0, 0.03);
  for (auto _ : state) {
    ekf.predict(0.2, 1.0 / 70.0);
    ekf.update_commanded({0.2, 0.0, 0.2});
    const auto p = ekf.pose();
    benchmark::DoNotOptimize(
        ekf.update_uwb({p.x + 0.05 * std::cos(p.yaw) + n(rng), p.y + 0.05 * std::sin(p.yaw) + n(rng)}));
  }
}
BENCHMARK(BM_EkfFullCycle);

void BM_Multilateration(benchmark::State& state) {
  const auto anchors = fleet::eval::default_anchors();
  fleet::sim::UwbTag tag(anchors, {}, std::mt19937_64(1));
  const auto readings = tag.measure_ranges({1.2, 1.7, 0.3});
  std::vector<fleet::sim::AnchorRange> ranges;
  for (const auto& r : readings) ranges.push_back({r.anchor, r.range});
  const fleet::sim::MultilaterationParams params;
  for (auto _ : state) {
    benchmark::DoNotOptimize(
        fleet::sim::solve_multilateration(anchors, ranges, params, fleet::geometry::Vec2{1.2, 1.7}));
  }
}
BENCHMARK(BM_Multilateration);

void BM_LocEvalFigure8_60s(benchmark::State& state) {
  fleet::eval::LocEvalParams p;
  p.variants = false;
  for (auto _ : state) benchmark::DoNotOptimize(fleet::eval::run_loc_eval(p).full.ekf.pos_rmse);
}
BENCHMARK(BM_LocEvalFigure8_60s)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
