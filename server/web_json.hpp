#pragma once
// Numbers and shapes as the web view's JSON writes them, shared by the API and the stream.

#include <nlohmann/json.hpp>
#include <string>

#include "geometry/polygon.hpp"

namespace fleet::server::web_json {

/// `v` rounded to `places` decimals; r3 and r4 round to 3 and 4.
double round_places(double v, int places);
double r3(double v);
double r4(double v);
/// Three significant digits, for covariances that span many orders of magnitude.
double sig3(double v);

nlohmann::json point(double x, double y);
nlohmann::json pose_json(const std::string& id, const geometry::Pose2& p);
nlohmann::json polygon_json(const geometry::Polygon& polygon);

}  // namespace fleet::server::web_json
