#pragma once

#include <chrono>
#include <string>
#include <utility>
#include <vector>

#include "common/latency_histogram.hpp"
#include "dds/topics.hpp"
#include "orders/server_term.hpp"

namespace fleet::server {

/// What the server's own work costs: the time of each traffic cycle (the requests taken since
/// the previous update, then the update) and of each dispatch round that had orders and free
/// robots to match, as histograms since the start, published as ServerLoad once a second (wall).
class ServerLoadMeter {
 public:
  /// Published under `term`'s server id, as the active server of that term.
  ServerLoadMeter(dds::Participant& participant, orders::ServerTerm term);

  using Clock = std::chrono::steady_clock;
  /// Time spent taking traffic requests, counted into the next cycle.
  void requests_taken(Clock::duration spent) { requests_since_cycle_ += spent; }
  void traffic_updated(Clock::duration spent);
  void dispatched(Clock::duration spent);
  /// Publishes when a second has passed since the last time.
  void publish_when_due(double now_wall, double now_sim, int robots);

 private:
  dds::Writer<model::ServerLoad> writer_;
  orders::ServerTerm term_;
  LatencyHistogram traffic_cycle_;
  LatencyHistogram traffic_update_;
  LatencyHistogram dispatch_;
  Clock::duration requests_since_cycle_{};
  double last_publish_wall_ = 0.0;
};

/// Wall time of the stages of one server loop, lap by lap.
class LoopStages {
 public:
  void start() {
    laps_.clear();
    started_ = last_ = ServerLoadMeter::Clock::now();
  }
  void lap(const char* stage) {
    const auto now = ServerLoadMeter::Clock::now();
    laps_.emplace_back(stage, std::chrono::duration<double>(now - last_).count());
    last_ = now;
  }
  double total_s() const { return std::chrono::duration<double>(last_ - started_).count(); }
  /// "requests 0 ms, states 3 ms, ...".
  std::string describe() const;

 private:
  std::vector<std::pair<const char*, double>> laps_;
  ServerLoadMeter::Clock::time_point started_;
  ServerLoadMeter::Clock::time_point last_;
};

}  // namespace fleet::server
