#pragma once

#include <chrono>

namespace fleet {

/// The one clock every Fleet process reads (ARCHITECTURE.md, "Time"):
/// sim_time = time_scale x wall_time, wall time counted from the Unix epoch. Because every
/// process derives it from the same wall clock, sim times in messages compare across processes
/// with no handshake, and a paused or killed process simply falls behind.
class SimClock {
 public:
  explicit SimClock(double time_scale = 1.0) : time_scale_(time_scale) {}

  double time_scale() const { return time_scale_; }

  /// Sim seconds now.
  double now() const { return time_scale_ * wall_now(); }

  /// Wall seconds since the Unix epoch.
  static double wall_now() {
    using namespace std::chrono;
    return duration<double>(system_clock::now().time_since_epoch()).count();
  }

  /// Wall seconds that `sim_seconds` of sim time take.
  double to_wall(double sim_seconds) const { return sim_seconds / time_scale_; }

 private:
  double time_scale_;
};

}  // namespace fleet
