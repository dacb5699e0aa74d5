#include "server/web_json.hpp"

#include <cmath>

namespace fleet::server::web_json {

using nlohmann::json;

// Rounding keeps frames small and stable: a robot standing still produces no diff from
// floating-point noise in its pose. 0.1 mm and 0.1 mrad are below anything the page can show.
// Dividing the rounded integer by an exact power of ten yields the double nearest the decimal
// value, which prints short ("0.7", not "0.7000000000000001").
double round_places(double v, int places) {
  const double k = std::pow(10.0, places);
  return std::round(v * k) / k;
}
double r4(double v) {
  return round_places(v, 4);
}
double r3(double v) {
  return round_places(v, 3);
}
double sig3(double v) {
  if (v == 0.0 || !std::isfinite(v)) return 0.0;
  const int places = 2 - static_cast<int>(std::floor(std::log10(std::fabs(v))));
  return places >= 0 ? round_places(v, places) : std::round(v / std::pow(10.0, -places)) * std::pow(10.0, -places);
}

json point(double x, double y) {
  return json::array({r3(x), r3(y)});
}

json pose_json(const std::string& id, const geometry::Pose2& p) {
  return json{{"id", id}, {"x", r4(p.x)}, {"y", r4(p.y)}, {"yaw", r4(p.yaw)}};
}

json polygon_json(const geometry::Polygon& polygon) {
  json out = json::array();
  for (const auto& p : polygon) out.push_back(point(p.x, p.y));
  return out;
}

}  // namespace fleet::server::web_json
