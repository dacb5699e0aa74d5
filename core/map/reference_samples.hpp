#pragma once

#include <cstddef>
#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

#include "map/opendrive.hpp"

namespace fleet::map {

struct ReferenceSample {
  std::string road_id;
  double s = 0.0;
  double x = 0.0;
  double y = 0.0;
  double hdg = 0.0;
};

/// Rows at most, unless the caller asks for more: ten million rows of CSV are about 600 MB.
inline constexpr std::size_t kDefaultMaxSamples = 10'000'000;

/// How many samples sample_reference_lines makes at `step`. Throws MapError when step is not
/// positive.
std::size_t count_reference_samples(const RoadNetwork& network, double step);

/// Samples every road's reference line from s = 0 to its length inclusive, `step` apart (the last
/// step may be shorter), handing each to `emit` as it is made, so that memory does not grow with
/// the roads' length. Throws MapError, before emitting anything, when step is not positive or
/// the samples would be more than `max_samples`.
void for_each_reference_sample(const RoadNetwork& network, double step, std::size_t max_samples,
                               const std::function<void(const ReferenceSample&)>& emit);

/// The same, collected (capped at kDefaultMaxSamples).
std::vector<ReferenceSample> sample_reference_lines(const RoadNetwork& network, double step);

/// The CSV header `road_id,s,x,y,hdg` and one row.
void write_samples_csv_header(std::ostream& out);
void write_sample_csv(const ReferenceSample& sample, std::ostream& out);

/// Writes samples as CSV with the header `road_id,s,x,y,hdg`.
void write_samples_csv(const std::vector<ReferenceSample>& samples, std::ostream& out);

}  // namespace fleet::map
