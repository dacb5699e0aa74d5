#include "server/server_load.hpp"

#include <fmt/format.h>

#include "dds/qos.hpp"

namespace fleet::server {

namespace {

double seconds(ServerLoadMeter::Clock::duration d) {
  return std::chrono::duration<double>(d).count();
}

}  // namespace

ServerLoadMeter::ServerLoadMeter(dds::Participant& participant) : writer_(participant, dds::qos::live_state()) {}

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
  writer_.write({"fleet-server", now_sim, robots, traffic.count, traffic.p50_s * 1e3, traffic.p99_s * 1e3,
                 traffic.max_s * 1e3, update.p50_s * 1e3, update.p99_s * 1e3, update.max_s * 1e3, dispatch.count,
                 dispatch.p50_s * 1e3, dispatch.p99_s * 1e3, dispatch.max_s * 1e3});
}

std::string LoopStages::describe() const {
  std::string out;
  for (const auto& [stage, seconds] : laps_) {
    out += fmt::format("{}{} {:.0f} ms", out.empty() ? "" : ", ", stage, seconds * 1e3);
  }
  return out;
}

}  // namespace fleet::server
