#include "monitor/track_recorder.hpp"

#include <cstdio>

namespace fleet::monitor {

void TrackRecorder::add(const std::string& robot_id, const geometry::Pose2& pose, double sim_time) {
  if (!geometry::is_finite(pose)) return;
  auto& track = tracks_[robot_id];
  if (!track.empty() && sim_time < track.back().sim_time + period_s_) return;
  track.push_back({sim_time, pose});
  while (!track.empty() && track.front().sim_time < sim_time - window_s_) track.pop_front();
}

void TrackRecorder::write_csv(std::ostream& out, double since, double origin) const {
  out << "robot,sim_s,x,y,yaw\n";
  char row[128];
  for (const auto& [robot_id, track] : tracks_) {
    for (const auto& s : track) {
      if (s.sim_time < since) continue;
      std::snprintf(row, sizeof row, ",%.2f,%.4f,%.4f,%.4f\n", s.sim_time - origin, s.pose.x, s.pose.y, s.pose.yaw);
      out << robot_id << row;
    }
  }
}

}  // namespace fleet::monitor
