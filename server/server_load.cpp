#include "server/server_load.hpp"

#include <fmt/format.h>

#include "dds/qos.hpp"

namespace fleet::server {

namespace {

double seconds(ServerLoadMeter::Clock::duration d) {
  return std::chrono::duration<double>(d).count();
}

}  // namespace

ServerLoadMeter::ServerLoadMeter(dds::Participant& participant, orders::ServerTerm term)
    : writer_(participant, dds::qos::live_state()), term_(std::move(term)) {}

void ServerLoadMeter::traffic_updated(Clock::duration spent) {
  traffic_cycle_.add(seconds(requests_since_cycle_ + spent));
  traffic_update_.add(seconds(spent));
  requests_since_cycle_ = {};
}

void ServerLoadMeter::dispatched(Clock::duration spent) {
  dispatch_.add(seconds(spent));
}

void ServerLoadMeter::publish_when_due(double now_wall, double now_sim, int robots) {
  if (now_wall - last_publish_wall_ < 1.0) return;
  last_publish_wall_ = now_wall;
  const auto traffic = traffic_cycle_.figures();
  const auto update = traffic_update_.figures();
  const auto dispatch = dispatch_.figures();
  writer_.write({.server_id = term_.server_id,
                 .sim_time = now_sim,
                 .robots = robots,
                 .traffic_cycles = traffic.count,
                 .traffic_cycle_p50_ms = traffic.p50_s * 1e3,
                 .traffic_cycle_p99_ms = traffic.p99_s * 1e3,
                 .traffic_cycle_max_ms = traffic.max_s * 1e3,
                 .traffic_update_p50_ms = update.p50_s * 1e3,
                 .traffic_update_p99_ms = update.p99_s * 1e3,
                 .traffic_update_max_ms = update.max_s * 1e3,
                 .dispatches = dispatch.count,
                 .dispatch_p50_ms = dispatch.p50_s * 1e3,
                 .dispatch_p99_ms = dispatch.p99_s * 1e3,
                 .dispatch_max_ms = dispatch.max_s * 1e3,
                 .term = term_.term,
                 .active = true,
                 .took_over = term_.took_over,
                 .since_unix_ms = term_.since_unix_ms,
                 .active_heard_s_ago = 0.0});
}

std::string LoopStages::describe() const {
  std::string out;
  for (const auto& [stage, seconds] : laps_) {
    out += fmt::format("{}{} {:.0f} ms", out.empty() ? "" : ", ", stage, seconds * 1e3);
  }
  return out;
}

}  // namespace fleet::server
