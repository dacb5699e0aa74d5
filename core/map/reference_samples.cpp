#include "map/reference_samples.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ostream>

#include "map/site.hpp"

namespace fleet::map {

std::vector<ReferenceSample> sample_reference_lines(const RoadNetwork& network, double step) {
  if (!(step > 0.0) || !std::isfinite(step)) {
    throw MapError(network.file + ": sample step " + std::to_string(step) + " must be a positive number of metres");
  }
  std::vector<ReferenceSample> out;
  for (const Road& road : network.roads) {
    // Integer multiples rather than repeated addition, so s does not drift on long roads.
    const double wanted = std::floor(road.length / step + 1e-9);
    if (!(wanted <= 1e7)) {
      throw MapError(network.file + ":" + std::to_string(road.line) + ": road '" + road.id + "' of " +
                     std::to_string(road.length) + " m needs more than 1e7 samples at step " + std::to_string(step));
    }
    const auto n = static_cast<std::size_t>(wanted);
    for (std::size_t i = 0; i <= n; ++i) {
      const double s = std::min(road.length, static_cast<double>(i) * step);
      const RefPoint p = evaluate_reference(road, s);
      out.push_back({road.id, s, p.x, p.y, p.hdg});
    }
    if (road.length - static_cast<double>(n) * step > 1e-9) {
      const RefPoint p = evaluate_reference(road, road.length);
      out.push_back({road.id, road.length, p.x, p.y, p.hdg});
    }
  }
  return out;
}

void write_samples_csv(const std::vector<ReferenceSample>& samples, std::ostream& out) {
  out << "road_id,s,x,y,hdg\n";
  char buf[160];
  for (const ReferenceSample& r : samples) {
    std::snprintf(buf, sizeof buf, ",%.6f,%.6f,%.6f,%.6f\n", r.s, r.x, r.y, r.hdg);
    if (r.road_id.find_first_of(",\"\n\r") == std::string::npos) {
      out << r.road_id << buf;
    } else {
      // RFC 4180 quoting: road ids are free text in OpenDRIVE.
      std::string quoted = "\"";
      for (const char c : r.road_id) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
      out << quoted << '"' << buf;
    }
  }
}

}  // namespace fleet::map
