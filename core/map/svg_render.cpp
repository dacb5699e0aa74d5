#include "map/svg_render.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace fleet::map {

namespace {

class Canvas {
 public:
  Canvas(const geometry::Bounds& b, const RenderOptions& o) : b_(b), o_(o) {
    const double w = b.max_x - b.min_x;
    const double h = b.max_y - b.min_y;
    k_ = o.image_size / std::max(w, h);
    width_ = w * k_ + 2.0 * o.margin;
    height_ = h * k_ + 2.0 * o.margin;
  }

  // SVG's y runs down; the map's runs up.
  double X(double x) const { return o_.margin + (x - b_.min_x) * k_; }
  double Y(double y) const { return o_.margin + (b_.max_y - y) * k_; }
  double len(double metres) const { return metres * k_; }
  double width() const { return width_; }
  double height() const { return height_; }

  std::string pt(double x, double y) const {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.2f,%.2f", X(x), Y(y));
    return buf;
  }

 private:
  geometry::Bounds b_;
  RenderOptions o_;
  double k_ = 1.0;
  double width_ = 0.0;
  double height_ = 0.0;
};

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", v);
  return buf;
}

std::string escape(const std::string& s) {
  std::string out;
  for (const char c : s) {
    switch (c) {
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '&':
        out += "&amp;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string rotated_rect(const Canvas& cv, const geometry::Pose2& pose, double length, double width) {
  const geometry::Polygon poly = geometry::footprint_polygon(pose, {length, width});
  std::string pts;
  for (const auto& p : poly) pts += cv.pt(p.x, p.y) + " ";
  return pts;
}

/// Lanes as outlines between their borders.
void draw_lanes(std::ostream& svg, const Canvas& cv, const SiteMap& map, const RenderOptions& /*o*/, double /*font*/) {
  const Site& site = map.site;
  // Lanes as filled outlines between their inner and outer borders (exact for any width
  // profile): drivable dark, others light. Sampled at half the graph spacing.
  const double step = std::max(site.graph_spacing * 0.5, 1e-3);
  svg << "<g id=\"lanes\" stroke-linejoin=\"round\">\n";
  for (const Road& road : map.network.roads) {
    for (std::size_t si = 0; si < road.sections.size(); ++si) {
      const double s0 = road.sections[si].s;
      const double s1 = road.section_end(si);
      const int n = std::clamp(static_cast<int>(std::ceil((s1 - s0) / step)), 1, 4000);
      for (const auto* side : {&road.sections[si].left, &road.sections[si].right}) {
        for (const Lane& lane : *side) {
          std::string inner, outer;
          for (int i = 0; i <= n; ++i) {
            const double s = s0 + (s1 - s0) * i / n;
            const RefPoint ref = evaluate_reference(road, s);
            const double t = lane_center_t(road, si, lane.id, s);
            const double half = 0.5 * lane_width_at(road, si, lane.id, s);
            const double nx = -std::sin(ref.hdg), ny = std::cos(ref.hdg);
            inner += cv.pt(ref.x + (t - half) * nx, ref.y + (t - half) * ny) + " ";
            outer = cv.pt(ref.x + (t + half) * nx, ref.y + (t + half) * ny) + " " + outer;
          }
          const char* colour = lane.drivable() ? "#8d8d8d" : "#cfcfcf";
          // A hairline stroke of the same colour closes the seams between adjacent pieces.
          svg << "<polygon points=\"" << inner << outer << "\" fill=\"" << colour << "\" stroke=\"" << colour
              << "\" stroke-width=\"0.8\"/>\n";
        }
      }
    }
  }
  svg << "</g>\n";
}

/// Every road's reference line.
void draw_reference_lines(std::ostream& svg, const Canvas& cv, const SiteMap& map, const RenderOptions& /*o*/,
                          double /*font*/) {
  const double step = std::max(map.site.graph_spacing * 0.5, 1e-3);
  // Reference lines, thin and dashed, so a person sees where each road starts and runs.
  svg << "<g id=\"reference\" fill=\"none\" stroke=\"#ffffff\" stroke-width=\"1\" stroke-dasharray=\"4 4\">\n";
  for (const Road& road : map.network.roads) {
    const int n = std::clamp(static_cast<int>(std::ceil(road.length / step)), 1, 8000);
    std::string pts;
    for (int i = 0; i <= n; ++i) {
      const RefPoint p = evaluate_reference(road, road.length * i / n);
      pts += cv.pt(p.x, p.y) + " ";
    }
    svg << "<polyline points=\"" << pts << "\"/>\n";
  }
  svg << "</g>\n";
}

/// The road graph's edges and, when asked, its points.
void draw_graph(std::ostream& svg, const Canvas& cv, const SiteMap& map, const RenderOptions& o, double /*font*/) {
  const RoadGraph& graph = map.graph.graph;
  svg << "<g id=\"graph-edges\" stroke=\"#2060c0\" stroke-width=\"1\">\n";
  for (std::size_t i = 0; i < graph.points.size(); ++i) {
    const GraphPoint& a = graph.points[i];
    for (const int j : graph.successors[i]) {
      const GraphPoint& b = graph.points[static_cast<std::size_t>(j)];
      svg << "<line x1=\"" << num(cv.X(a.x)) << "\" y1=\"" << num(cv.Y(a.y)) << "\" x2=\"" << num(cv.X(b.x))
          << "\" y2=\"" << num(cv.Y(b.y)) << "\"/>\n";
    }
  }
  svg << "</g>\n";
  if (o.graph_points) {
    svg << "<g id=\"graph-points\" fill=\"#2060c0\">\n";
    for (const GraphPoint& p : graph.points) {
      svg << "<circle cx=\"" << num(cv.X(p.x)) << "\" cy=\"" << num(cv.Y(p.y)) << "\" r=\"1.6\"/>\n";
    }
    svg << "</g>\n";
  }
}

/// Racks.
void draw_racks(std::ostream& svg, const Canvas& cv, const SiteMap& map, const RenderOptions& /*o*/, double /*font*/) {
  const Site& site = map.site;
  svg << "<g id=\"racks\" font-size=\"12\">\n";
  for (const Rack& rack : site.racks) {
    std::string pts;
    for (const auto& p : rack.polygon) pts += cv.pt(p.x, p.y) + " ";
    svg << "<polygon points=\"" << pts << "\" fill=\"#c9b79c\" stroke=\"#7a6648\" stroke-width=\"1.5\"/>\n";
  }
  svg << "</g>\n";
}

/// The designated static obstacles, on or off at the start.
void draw_obstacles(std::ostream& svg, const Canvas& cv, const SiteMap& map, const RenderOptions& /*o*/, double font) {
  const Site& site = map.site;
  svg << "<g id=\"obstacles\" font-size=\"" << num(font) << "\">\n";
  for (const StaticObstacle& ob : site.static_obstacles) {
    std::string pts;
    double cx = 0.0, cy = 0.0;
    for (const auto& p : ob.polygon) {
      pts += cv.pt(p.x, p.y) + " ";
      cx += p.x / static_cast<double>(ob.polygon.size());
      cy += p.y / static_cast<double>(ob.polygon.size());
    }
    svg << "<polygon points=\"" << pts << "\" fill=\"#d03030\" fill-opacity=\"" << (ob.enabled_at_start ? "0.7" : "0.2")
        << "\" stroke=\"#b00000\" stroke-width=\"2\"" << (ob.enabled_at_start ? "" : " stroke-dasharray=\"5 3\"")
        << "/>\n";
    svg << "<text x=\"" << num(cv.X(cx)) << "\" y=\"" << num(cv.Y(cy) + font * 0.35)
        << "\" text-anchor=\"middle\" fill=\"#700000\">" << escape(ob.id) << "</text>\n";
  }
  svg << "</g>\n";
}

/// Loading areas with their pallets and the way they face.
void draw_loading_areas(std::ostream& svg, const Canvas& cv, const SiteMap& map, const RenderOptions& o, double font) {
  const Site& site = map.site;
  svg << "<g id=\"loading-areas\" font-size=\"" << num(font) << "\">\n";
  // Pallets scale with the roads: 0.12 m on the 0.30 m demo tables.
  const double pallet = o.pallet_size > 0.0 ? o.pallet_size : 0.4 * site.road_width;
  for (const LoadingArea& a : site.loading_areas) {
    svg << "<polygon points=\"" << rotated_rect(cv, a.pose, pallet, pallet) << "\" fill=\""
        << (a.pallet_at_start ? "#b07a3a" : "none") << "\" stroke=\"#6b4418\" stroke-width=\"2\""
        << (a.pallet_at_start ? "" : " stroke-dasharray=\"4 3\"") << "/>\n";
    // Arrow along yaw: from the pallet towards the road the forklift comes from.
    const double c = std::cos(a.pose.yaw), s = std::sin(a.pose.yaw);
    const double tip = 0.5 * pallet + 0.3 * site.road_width;
    svg << "<line x1=\"" << num(cv.X(a.pose.x)) << "\" y1=\"" << num(cv.Y(a.pose.y)) << "\" x2=\""
        << num(cv.X(a.pose.x + tip * c)) << "\" y2=\"" << num(cv.Y(a.pose.y + tip * s))
        << "\" stroke=\"#6b4418\" stroke-width=\"2\"/>\n";
    const double hx = a.pose.x + tip * c, hy = a.pose.y + tip * s;
    const double w = 0.1 * site.road_width;
    svg << "<polygon points=\"" << cv.pt(hx + w * c, hy + w * s) << " " << cv.pt(hx - w * s, hy + w * c) << " "
        << cv.pt(hx + w * s, hy - w * c) << "\" fill=\"#6b4418\"/>\n";
    const double lx = a.pose.x - (0.5 * pallet + 0.2 * site.road_width) * c;
    const double ly = a.pose.y - (0.5 * pallet + 0.2 * site.road_width) * s;
    svg << "<text x=\"" << num(cv.X(lx)) << "\" y=\"" << num(cv.Y(ly) + font * 0.35)
        << "\" text-anchor=\"middle\" fill=\"#4a2e0e\" font-weight=\"bold\">" << escape(a.id) << "</text>\n";
  }
  svg << "</g>\n";
}

/// Homes as robot footprints.
void draw_homes(std::ostream& svg, const Canvas& cv, const SiteMap& map, const RenderOptions& o, double font) {
  const Site& site = map.site;
  svg << "<g id=\"homes\" font-size=\"" << num(font) << "\">\n";
  for (const Home& h : site.homes) {
    svg << "<polygon points=\"" << rotated_rect(cv, h.pose, o.robot_length, o.robot_width)
        << "\" fill=\"#40a040\" fill-opacity=\"0.25\" stroke=\"#207020\" stroke-width=\"1.5\"/>\n";
    const double c = std::cos(h.pose.yaw), s = std::sin(h.pose.yaw);
    svg << "<line x1=\"" << num(cv.X(h.pose.x)) << "\" y1=\"" << num(cv.Y(h.pose.y)) << "\" x2=\""
        << num(cv.X(h.pose.x + 0.5 * o.robot_length * c)) << "\" y2=\""
        << num(cv.Y(h.pose.y + 0.5 * o.robot_length * s)) << "\" stroke=\"#207020\" stroke-width=\"2\"/>\n";
    svg << "<text x=\"" << num(cv.X(h.pose.x)) << "\" y=\"" << num(cv.Y(h.pose.y) + font * 0.35)
        << "\" text-anchor=\"middle\" fill=\"#104010\">" << escape(h.id) << "</text>\n";
  }
  svg << "</g>\n";
}

/// AR markers.
void draw_markers(std::ostream& svg, const Canvas& cv, const SiteMap& map, const RenderOptions& /*o*/,
                  double /*font*/) {
  const Site& site = map.site;
  // AR markers: a small square with a tick the way the marker faces; the id shows on hover.
  svg << "<g id=\"markers\" fill=\"#000\" stroke=\"#000\">\n";
  for (const Marker& m : site.markers) {
    const double x = cv.X(m.pose.x), y = cv.Y(m.pose.y);
    svg << "<rect x=\"" << num(x - 3) << "\" y=\"" << num(y - 3) << "\" width=\"6\" height=\"6\"><title>marker " << m.id
        << " z=" << num(m.z) << "</title></rect>\n";
    svg << "<line x1=\"" << num(x) << "\" y1=\"" << num(y) << "\" x2=\"" << num(x + 8 * std::cos(m.pose.yaw))
        << "\" y2=\"" << num(y - 8 * std::sin(m.pose.yaw)) << "\" stroke-width=\"1.5\"/>\n";
  }
  svg << "</g>\n";
}

/// UWB anchors.
void draw_uwb_anchors(std::ostream& svg, const Canvas& cv, const SiteMap& map, const RenderOptions& /*o*/,
                      double font) {
  const Site& site = map.site;
  svg << "<g id=\"uwb-anchors\" font-size=\"" << num(font) << "\" fill=\"#7030a0\">\n";
  for (const UwbAnchor& u : site.uwb_anchors) {
    const double x = cv.X(u.x), y = cv.Y(u.y);
    svg << "<polygon points=\"" << num(x) << "," << num(y - 9) << " " << num(x - 8) << "," << num(y + 6) << " "
        << num(x + 8) << "," << num(y + 6) << "\"/>\n";
    // Labels point inwards so that anchors on the right edge keep theirs inside the picture.
    const bool right = u.x > 0.5 * (site.bounds.min_x + site.bounds.max_x);
    svg << "<text x=\"" << num(right ? x - 10 : x + 10) << "\" y=\"" << num(y - 8) << "\" text-anchor=\""
        << (right ? "end" : "start") << "\">" << escape(u.id) << " z=" << num(u.z) << "</text>\n";
  }
  svg << "</g>\n";
}

/// Recorded tracks.
void draw_tracks(std::ostream& svg, const Canvas& cv, const SiteMap& /*map*/, const RenderOptions& o, double font) {
  if (!o.tracks.empty()) {
    // Colours far apart in hue, so that eight robots stay apart.
    static const char* kColours[] = {"#e6194b", "#3cb44b", "#4363d8", "#f58231", "#911eb4",
                                     "#42d4f4", "#f032e6", "#9a6324", "#000075", "#808000"};
    svg << "<g id=\"tracks\" font-size=\"" << num(font) << "\">\n";
    for (std::size_t i = 0; i < o.tracks.size(); ++i) {
      const RenderTrack& track = o.tracks[i];
      if (track.poses.empty()) continue;
      const char* colour = kColours[i % std::size(kColours)];
      double next_footprint = track.times.empty() ? 0.0 : track.times.front();
      for (std::size_t k = 0; k < track.poses.size() && k < track.times.size(); ++k) {
        if (track.times[k] < next_footprint) continue;
        next_footprint = track.times[k] + o.track_footprint_every;
        svg << "<polygon points=\"" << rotated_rect(cv, track.poses[k], o.robot_length, o.robot_width)
            << "\" fill=\"none\" stroke=\"" << colour << "\" stroke-opacity=\"0.35\" stroke-width=\"1\"/>\n";
      }
      std::string line;
      for (const auto& p : track.poses) line += cv.pt(p.x, p.y) + " ";
      svg << "<polyline points=\"" << line << "\" fill=\"none\" stroke=\"" << colour << "\" stroke-width=\"2\"/>\n";
      const geometry::Pose2& last = track.poses.back();
      svg << "<polygon points=\"" << rotated_rect(cv, last, o.robot_length, o.robot_width) << "\" fill=\"" << colour
          << "\" fill-opacity=\"0.45\" stroke=\"" << colour << "\" stroke-width=\"2\"/>\n";
      svg << "<line x1=\"" << num(cv.X(last.x)) << "\" y1=\"" << num(cv.Y(last.y)) << "\" x2=\""
          << num(cv.X(last.x + 0.5 * o.robot_length * std::cos(last.yaw))) << "\" y2=\""
          << num(cv.Y(last.y + 0.5 * o.robot_length * std::sin(last.yaw)))
          << "\" stroke=\"#000\" stroke-width=\"2\"/>\n";
      svg << "<text x=\"" << num(cv.X(last.x)) << "\" y=\"" << num(cv.Y(last.y) - cv.len(0.5 * o.robot_length) - 4.0)
          << "\" text-anchor=\"middle\" fill=\"" << colour << "\" font-weight=\"bold\">" << escape(track.label)
          << "</text>\n";
    }
    svg << "</g>\n";
  }
}

/// The caption under the picture.
void draw_caption(std::ostream& svg, const Canvas& cv, const SiteMap& map, const RenderOptions& o, double /*font*/) {
  const Site& site = map.site;
  const RoadGraph& graph = map.graph.graph;
  svg << "<text x=\"" << num(o.margin) << "\" y=\"" << num(cv.height() + 16.0) << "\" font-size=\"14\" fill=\"#333\">"
      << escape(site.name) << ": " << num(site.bounds.max_x - site.bounds.min_x) << " m x "
      << num(site.bounds.max_y - site.bounds.min_y) << " m, " << map.network.roads.size() << " roads, "
      << graph.points.size() << " graph points, " << graph.edge_count() << " edges, " << site.loading_areas.size()
      << " loading areas, " << site.static_obstacles.size() << " obstacles, " << site.homes.size() << " homes</text>\n";
}

}  // namespace

std::string render_svg(const SiteMap& map, const RenderOptions& o) {
  const Site& site = map.site;
  const Canvas cv(site.bounds, o);
  std::ostringstream svg;
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << num(cv.width()) << "\" height=\""
      << num(cv.height() + 30.0) << "\" viewBox=\"0 0 " << num(cv.width()) << " " << num(cv.height() + 30.0)
      << "\" font-family=\"sans-serif\">\n";
  svg << "<rect x=\"0\" y=\"0\" width=\"100%\" height=\"100%\" fill=\"#ffffff\"/>\n";
  svg << "<rect x=\"" << num(cv.X(site.bounds.min_x)) << "\" y=\"" << num(cv.Y(site.bounds.max_y)) << "\" width=\""
      << num(cv.len(site.bounds.max_x - site.bounds.min_x)) << "\" height=\""
      << num(cv.len(site.bounds.max_y - site.bounds.min_y))
      << "\" fill=\"#f4f1e8\" stroke=\"#555\" stroke-width=\"2\"/>\n";
  const double font = std::clamp(cv.len(0.07), 9.0, 16.0);
  for (auto* draw : {draw_lanes, draw_reference_lines, draw_graph, draw_racks, draw_obstacles, draw_loading_areas,
                     draw_homes, draw_markers, draw_uwb_anchors, draw_tracks, draw_caption}) {
    draw(svg, cv, map, o, font);
  }
  svg << "</svg>\n";
  return svg.str();
}

}  // namespace fleet::map
