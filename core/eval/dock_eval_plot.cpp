// The SVG of `fleetctl dock-eval --plot`: every run's path of the rear-axle midpoint over the
// corridor, the pallet row and the limiter, the stacker drawn where each run ended.

#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>
#include <string>

#include "eval/dock_eval.hpp"
#include "sim/tricycle.hpp"

namespace fleet::eval {

namespace {

std::string fmt(double v, int digits) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

}  // namespace

std::string dock_eval_svg(const DockEvalResult& r) {
  // Corridor frame to pixels: y up in the corridor, down in SVG.
  const double min_x = 3.0, max_x = 20.0, min_y = -1.6, max_y = 3.3;
  const double scale = 80.0;  // px per metre
  const double header = 60.0;
  const double w = (max_x - min_x) * scale;
  const double h = (max_y - min_y) * scale + header;
  auto px = [&](double x) { return fmt((x - min_x) * scale, 1); };
  auto py = [&](double y) { return fmt(header + (max_y - y) * scale, 1); };
  auto polygon = [&](const geometry::Polygon& poly, const std::string& fill, const std::string& stroke) {
    std::ostringstream os;
    os << "<polygon fill=\"" << fill << "\" stroke=\"" << stroke << "\" points=\"";
    for (const auto& p : poly) os << px(p.x) << ',' << py(p.y) << ' ';
    os << "\"/>\n";
    return os.str();
  };

  std::ostringstream os;
  os << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << fmt(w, 0) << "\" height=\"" << fmt(h, 0)
     << "\" viewBox=\"0 0 " << fmt(w, 0) << ' ' << fmt(h, 0) << "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  os << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  const DockSummary& s = r.summary;
  os << "<text x=\"8\" y=\"18\" font-size=\"14\">dock-eval: " << s.successes << " of " << s.runs << " docked, seed "
     << r.params.seed << ", pose noise " << fmt(r.params.pose_noise.position_sigma * 100.0, 1) << " cm / "
     << fmt(r.params.pose_noise.yaw_sigma * 180.0 / std::numbers::pi, 1) << " deg</text>\n";
  os << "<text x=\"8\" y=\"36\">fork tips off the pockets p95 " << fmt(s.lateral_p95 * 100.0, 2) << " cm, yaw p95 "
     << fmt(s.yaw_p95 * 180.0 / std::numbers::pi, 2) << " deg, time median " << fmt(s.time_median, 1)
     << " s; paths of the rear-axle midpoint (green docked, red not)</text>\n";
  // The corridor's walls and the limiter's edge.
  os << "<rect x=\"" << px(min_x) << "\" y=\"" << py(2.98) << "\" width=\"" << fmt(w, 0) << "\" height=\""
     << fmt(2.98 * scale, 1) << "\" fill=\"#f4f4f4\"/>\n";
  os << "<rect x=\"" << px(min_x) << "\" y=\"" << py(0.0) << "\" width=\"" << fmt(w, 0) << "\" height=\""
     << fmt(1.2 * scale, 1) << "\" fill=\"#d9d9d9\"/>\n";
  // The pallet row, the target crossed.
  const geometry::Vec2 along{-std::sin(r.pallet.yaw), std::cos(r.pallet.yaw)};
  for (int k = -3; k <= 3; ++k) {
    const geometry::Vec2 c = r.pallet.position() + (k * 1.5) * along;
    const geometry::Pose2 at{c.x, c.y, r.pallet.yaw};
    const geometry::Polygon outline =
        sim::polygon_in_map(at, geometry::Polygon{{-0.6, -0.4}, {0.6, -0.4}, {0.6, 0.4}, {-0.6, 0.4}});
    os << polygon(outline, k == 0 ? "#c8a165" : "#e6d3b3", "#8c6d3f");
    if (k == 0) {
      os << "<line x1=\"" << px(outline[0].x) << "\" y1=\"" << py(outline[0].y) << "\" x2=\"" << px(outline[2].x)
         << "\" y2=\"" << py(outline[2].y) << "\" stroke=\"#8c6d3f\"/>\n";
      os << "<line x1=\"" << px(outline[1].x) << "\" y1=\"" << py(outline[1].y) << "\" x2=\"" << px(outline[3].x)
         << "\" y2=\"" << py(outline[3].y) << "\" stroke=\"#8c6d3f\"/>\n";
    }
  }
  const sim::TricycleGeometry g;
  for (const DockRun& run : r.runs) {
    const auto& traj = run.result.trajectory;
    if (traj.empty()) continue;
    const std::string colour = run.result.success ? "#2ca02c" : "#d62728";
    os << "<polyline fill=\"none\" stroke=\"" << colour << "\" stroke-opacity=\"0.5\" stroke-width=\"1.2\" points=\"";
    for (const auto& sample : traj) os << px(sample.pose.x) << ',' << py(sample.pose.y) << ' ';
    os << px(run.result.final_pose.x) << ',' << py(run.result.final_pose.y) << "\"/>\n";
    os << "<circle cx=\"" << px(traj.front().pose.x) << "\" cy=\"" << py(traj.front().pose.y)
       << "\" r=\"3\" fill=\"#1f77b4\"/>\n";
  }
  // The stacker where the first run ended, forks in the pallet.
  for (const DockRun& run : r.runs) {
    if (!run.result.completed) continue;
    os << polygon(sim::polygon_in_map(run.result.final_pose, sim::tricycle_footprint(g)), "none", "#333333");
    break;
  }
  os << "</svg>\n";
  return os.str();
}

}  // namespace fleet::eval
