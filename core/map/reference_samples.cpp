#include "map/reference_samples.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ostream>

#include "map/site.hpp"

namespace fleet::map {

namespace {

void check_step(const RoadNetwork& network, double step) {
  if (!(step > 0.0) || !std::isfinite(step)) {
    throw MapError(network.file + ": sample step " + std::to_string(step) + " must be a positive number of metres");
  }
}

/// Whole steps on `road` (the samples are these plus s = 0, plus the end when it falls between).
double whole_steps(const Road& road, double step) {
  return std::floor(road.length / step + 1e-9);
}

}  // namespace

std::size_t count_reference_samples(const RoadNetwork& network, double step) {
  check_step(network, step);
  double total = 0.0;
  for (const Road& road : network.roads) total += whole_steps(road, step) + 2.0;
  return total >= 1e18 ? static_cast<std::size_t>(1e18) : static_cast<std::size_t>(total);
}

void for_each_reference_sample(const RoadNetwork& network, double step, std::size_t max_samples,
                               const std::function<void(const ReferenceSample&)>& emit) {
  const std::size_t rows = count_reference_samples(network, step);
  if (rows > max_samples) {
    throw MapError(network.file + ": sampling every " + std::to_string(step) + " m makes about " +
                   std::to_string(rows) + " rows, more than the limit of " + std::to_string(max_samples) +
                   " (--max-rows N raises it; a longer --step lowers the count)");
  }
  for (const Road& road : network.roads) {
    // Integer multiples rather than repeated addition, so s does not drift on long roads.
    const auto n = static_cast<std::size_t>(whole_steps(road, step));
    for (std::size_t i = 0; i <= n; ++i) {
      const double s = std::min(road.length, static_cast<double>(i) * step);
      const RefPoint p = evaluate_reference(road, s);
      emit({road.id, s, p.x, p.y, p.hdg});
    }
    if (road.length - static_cast<double>(n) * step > 1e-9) {
      const RefPoint p = evaluate_reference(road, road.length);
      emit({road.id, road.length, p.x, p.y, p.hdg});
    }
  }
}

std::vector<ReferenceSample> sample_reference_lines(const RoadNetwork& network, double step) {
  std::vector<ReferenceSample> out;
  for_each_reference_sample(network, step, kDefaultMaxSamples, [&](const ReferenceSample& r) { out.push_back(r); });
  return out;
}

void write_samples_csv_header(std::ostream& out) {
  out << "road_id,s,x,y,hdg\n";
}

void write_sample_csv(const ReferenceSample& r, std::ostream& out) {
  char buf[160];
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

void write_samples_csv(const std::vector<ReferenceSample>& samples, std::ostream& out) {
  write_samples_csv_header(out);
  for (const ReferenceSample& r : samples) write_sample_csv(r, out);
}

}  // namespace fleet::map
