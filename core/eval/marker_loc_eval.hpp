#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "geometry/polygon.hpp"
#include "geometry/pose.hpp"
#include "localization/marker_localizer.hpp"
#include "map/site.hpp"

namespace fleet::eval {

/// The picker's localization by markers on a rack aisle [Picker thesis, section 4.2.9], on core/ alone: the
/// Summit-XLS base drives laps of an aisle with its waypoint controller on the filter's estimate, one lap
/// along each rack face at `rack_distance` (two pickers share an aisle this way), while both Axis PTZ cameras
/// aim at the nearest rack marker and the EKF fuses their sightings with wheel odometry.
struct MarkerLocEvalParams {
  std::uint64_t seed = 1;
  double duration = 300.0;     ///< simulated seconds
  double speed = 0.3;          ///< the thesis's test speed, m/s
  double rack_distance = 0.8;  ///< from the rack face to the robot's centre, m
  /// The aisle: the two rack faces' y and the x span driven (the plant's rack aisle 1 by default).
  double south_face_y = 10.2;
  double north_face_y = 13.2;
  double x_from = 32.0;
  double x_to = 56.0;
  /// Markers on the site; empty means every marker of the plant's rack aisle 1 (pillars every 3.5 m).
  std::vector<map::Marker> markers;
  /// What the cameras cannot see through (the site's racks); empty means the two rack rows of the aisle
  /// (none for a route).
  std::vector<geometry::Polygon> occluders;
  /// A route to drive in place of the aisle laps: its points in order to the end, then back to the
  /// start, again and again (loc-eval's plant_route). Empty: the aisle laps.
  std::vector<geometry::Vec2> route;
  /// The cameras, encoders and filter, as the picker's agent runs them.
  localization::MarkerLocalizerParams localizer;
};

struct MarkerLocErrors {
  double rmse_cm = 0.0;
  double p95_cm = 0.0;
  double max_cm = 0.0;
  double heading_rmse_deg = 0.0;
  double heading_max_deg = 0.0;
};

struct MarkerLocEvalResult {
  MarkerLocErrors ekf;                    ///< the filter: odometry and markers
  MarkerLocErrors odometry;               ///< wheel odometry alone (Picker thesis, eq. 3.7) from the same start
  int sightings = 0;                      ///< markers detected by either camera
  int sightings_fused = 0;                ///< accepted by the filter
  int sightings_gated = 0;                ///< rejected by the filter's gate
  int markers_seen = 0;                   ///< distinct marker ids
  double longest_gap_s = 0.0;             ///< longest time without an accepted sighting
  double distance_m = 0.0;                ///< driven
  int laps = 0;                           ///< aisle lengths driven
  std::vector<geometry::Pose2> truth;     ///< every 0.5 s
  std::vector<geometry::Pose2> estimate;  ///< every 0.5 s
  geometry::Vec2 worst_at;                ///< where the body truly stood when the filter was farthest off
};

/// The plant's rack-aisle-1 markers: pillars every 3.5 m on both faces, facing into the aisle.
std::vector<map::Marker> rack_aisle_markers(const MarkerLocEvalParams& params);

/// Runs the evaluation. Throws std::invalid_argument for a non-positive duration or speed, an aisle too
/// narrow for the rack distance, or a route of fewer than two points.
MarkerLocEvalResult run_marker_loc_eval(const MarkerLocEvalParams& params);

}  // namespace fleet::eval
