#pragma once

#include <chrono>

#include "common/latency_histogram.hpp"
#include "dds/topics.hpp"

namespace fleet::server {

/// What the server's own work costs: the time of each traffic cycle (the requests taken since
/// the previous update, then the update) and of each dispatch round that had orders and free
/// robots to match, as histograms since the start, published as ServerLoad once a second (wall).
class ServerLoadMeter {
 public:
  explicit ServerLoadMeter(dds::Participant& participant);

  using Clock = std::chrono::steady_clock;
  /// Time spent taking traffic requests, counted into the next cycle.
  void requests_taken(Clock::duration spent) { requests_since_cycle_ += spent; }
  void traffic_updated(Clock::duration spent);
  void dispatched(Clock::duration spent);
  /// Publishes when a second has passed since the last time.
  void publish_when_due(double now_wall, double now_sim, int robots);

 private:
  dds::Writer<model::ServerLoad> writer_;
  LatencyHistogram traffic_cycle_;
  LatencyHistogram traffic_update_;
  LatencyHistogram dispatch_;
  Clock::duration requests_since_cycle_{};
  double last_publish_wall_ = 0.0;
};

}  // namespace fleet::server
