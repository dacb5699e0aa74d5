#pragma once

#include <string>
#include <vector>

#include "map/site_map.hpp"

namespace fleet::map {

/// A robot's track drawn over the map: its line, its footprint every few seconds and where it
/// ended, labelled.
struct RenderTrack {
  std::string label;
  std::vector<double> times;  ///< sim seconds, one per pose
  std::vector<geometry::Pose2> poses;
};

struct RenderOptions {
  double image_size = 1000.0;   ///< pixels along the longer side of the site bounds
  double margin = 40.0;         ///< pixels around the bounds
  double pallet_size = 0.0;     ///< drawn pallet side, metres; 0: 0.4 x the road width
  bool graph_points = true;     ///< draw graph points (dense on big sites)
  double robot_length = 0.25;   ///< drawn footprint at homes, metres
  double robot_width = 0.16;
  std::vector<RenderTrack> tracks;
  double track_footprint_every = 5.0;  ///< sim seconds between the faint footprints along a track
};

/// An SVG picture a person checks a map with: lanes at their width, the reference lines, graph
/// edges and points, racks, loading areas (pallet, facing arrow, id), static obstacles (solid
/// when enabled at start, dashed when not), AR markers, UWB anchors and home poses; robots' tracks
/// on top.
std::string render_svg(const SiteMap& map, const RenderOptions& options = {});

}  // namespace fleet::map
