#pragma once

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

/// Samples every road's reference line from s = 0 to its length inclusive, `step` apart (the last
/// step may be shorter). Throws MapError when step is not positive.
std::vector<ReferenceSample> sample_reference_lines(const RoadNetwork& network, double step);

/// Writes samples as CSV with the header `road_id,s,x,y,hdg`.
void write_samples_csv(const std::vector<ReferenceSample>& samples, std::ostream& out);

}  // namespace fleet::map
