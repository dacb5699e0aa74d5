#include "model/traffic_requests.hpp"

namespace fleet::model {

namespace {

bool same_route(const TrafficRequest& request, std::uint64_t version, const std::string& map_id) {
  return request.version == version && request.map_id == map_id;
}

}  // namespace

TrafficRequest TrafficRequestJoin::route(TrafficRequest request) {
  TrafficRequest& last = last_[request.robot_id];
  if (same_route(last, request.version, request.map_id) && !last.robot_id.empty() && last.sim_time > request.sim_time) {
    // A request that was on its way while later progress on the same route arrived.
    request.progress = last.progress;
    request.stopped_for = last.stopped_for;
    request.sim_time = last.sim_time;
  }
  last = request;
  return request;
}

std::optional<TrafficRequest> TrafficRequestJoin::progress(const TrafficProgress& progress) {
  const auto found = last_.find(progress.robot_id);
  if (found == last_.end()) return std::nullopt;
  TrafficRequest& last = found->second;
  if (!same_route(last, progress.version, progress.map_id) || progress.sim_time < last.sim_time) return std::nullopt;
  last.progress = progress.progress;
  last.stopped_for = progress.stopped_for;
  last.sim_time = progress.sim_time;
  return last;
}

}  // namespace fleet::model
