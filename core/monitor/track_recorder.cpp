#include "monitor/track_recorder.hpp"

#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>
#include <stdexcept>

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

std::vector<Track> read_tracks_csv(std::istream& in, const std::string& source) {
  std::map<std::string, Track> by_robot;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (number == 1 && line == "robot,sim_s,x,y,yaw") continue;
    if (line.empty()) continue;
    std::istringstream row(line);
    std::string field;
    std::vector<std::string> fields;
    while (std::getline(row, field, ',')) fields.push_back(field);
    double v[4] = {};
    bool ok = fields.size() == 5 && !fields[0].empty();
    for (std::size_t i = 0; ok && i < 4; ++i) {
      std::size_t used = 0;
      try {
        v[i] = std::stod(fields[i + 1], &used);
      } catch (const std::exception&) {
        used = 0;
      }
      ok = used == fields[i + 1].size() && used > 0 && std::isfinite(v[i]);
    }
    if (!ok) {
      throw std::runtime_error(source + ":" + std::to_string(number) + ": expected robot,sim_s,x,y,yaw, got '" + line +
                               "'");
    }
    Track& t = by_robot[fields[0]];
    t.robot_id = fields[0];
    t.sim_s.push_back(v[0]);
    t.poses.push_back({v[1], v[2], v[3]});
  }
  std::vector<Track> tracks;
  for (auto& [id, t] : by_robot) tracks.push_back(std::move(t));
  return tracks;
}

}  // namespace fleet::monitor
