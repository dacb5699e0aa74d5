#pragma once

#include <optional>
#include <string>
#include <vector>

namespace fleet::map {

// OpenDRIVE road networks ([Forklift thesis, section 5.1]; ASAM OpenDRIVE 1.4-1.7). Only what a planar
// planner needs is kept: elevation, superelevation, road marks, objects and signals are skipped.

enum class ContactPoint { kNone, kStart, kEnd };
enum class LinkTarget { kRoad, kJunction };

/// `<predecessor>` / `<successor>` of a road's `<link>`.
struct RoadLink {
  LinkTarget target = LinkTarget::kRoad;
  std::string element_id;
  ContactPoint contact = ContactPoint::kNone;  ///< only for roads; kNone when the file omits it
  int line = 0;                                ///< line in the file, for messages
};

/// a + b*ds + c*ds^2 + d*ds^3 from `s` on (laneOffset, lane width, lane border).
struct CubicPoly {
  double s = 0.0;  ///< start: road s for laneOffset, sOffset from the section start for widths
  double a = 0.0, b = 0.0, c = 0.0, d = 0.0;

  double at(double ds) const { return a + ds * (b + ds * (c + ds * d)); }
};

enum class GeometryKind { kLine, kArc, kSpiral, kPoly3, kParamPoly3 };

/// One `<geometry>` record of a `<planView>`.
struct Geometry {
  GeometryKind kind = GeometryKind::kLine;
  double s = 0.0, x = 0.0, y = 0.0, hdg = 0.0, length = 0.0;
  double curvature = 0.0;                         ///< arc
  double curv_start = 0.0, curv_end = 0.0;        ///< spiral
  double a = 0.0, b = 0.0, c = 0.0, d = 0.0;      ///< poly3: v(u)
  double au = 0.0, bu = 0.0, cu = 0.0, du = 0.0;  ///< paramPoly3 u(p)
  double av = 0.0, bv = 0.0, cv = 0.0, dv = 0.0;  ///< paramPoly3 v(p)
  bool normalized = true;                         ///< paramPoly3 pRange: p in [0, 1] (true) or [0, length] (false)
  /// paramPoly3: the cubic's own arc length over its whole p range, which every evaluation scales
  /// s by. The parser computes it once (paramPoly3_arc_length); 0: computed at each evaluation.
  double curve_arc_length = 0.0;
  int line = 0;
};

struct Lane {
  int id = 0;
  std::string type;                ///< "driving", "sidewalk", "none", ...
  std::vector<CubicPoly> widths;   ///< by sOffset, ascending
  std::optional<int> predecessor;  ///< lane id in the previous section or linked road
  std::optional<int> successor;
  int line = 0;

  /// Types a vehicle may drive on.
  bool drivable() const;
};

struct LaneSection {
  double s = 0.0;
  std::vector<Lane> left;   ///< ids 1, 2, ... (inner to outer)
  std::vector<Lane> right;  ///< ids -1, -2, ... (inner to outer)
  int line = 0;

  const Lane* find(int lane_id) const;
};

struct Road {
  std::string id;
  std::string name;
  std::string junction = "-1";  ///< id of the junction this road belongs to, "-1" for none
  double length = 0.0;
  bool left_hand_traffic = false;  ///< rule="LHT": left lanes drive along the reference line
  std::optional<RoadLink> predecessor;
  std::optional<RoadLink> successor;
  std::vector<Geometry> plan_view;      ///< by s, ascending
  std::vector<CubicPoly> lane_offsets;  ///< by s, ascending
  std::vector<LaneSection> sections;    ///< by s, ascending
  int line = 0;

  bool in_junction() const { return junction != "-1"; }
  /// End s of section i (start of the next one, or the road length).
  double section_end(std::size_t i) const;
};

struct LaneLink {
  int from = 0;  ///< lane of the incoming road
  int to = 0;    ///< lane of the connecting road
};

struct Connection {
  std::string id;
  std::string incoming_road;
  std::string connecting_road;
  ContactPoint contact = ContactPoint::kStart;  ///< end of the connecting road touching the incoming road
  std::vector<LaneLink> lane_links;
  int line = 0;
};

struct Junction {
  std::string id;
  std::string name;
  std::vector<Connection> connections;
  int line = 0;
};

struct Header {
  int rev_major = 1;
  int rev_minor = 4;
  std::string name;
  double north = 0.0, south = 0.0, east = 0.0, west = 0.0;
};

struct RoadNetwork {
  std::string file;
  Header header;
  std::vector<Road> roads;
  std::vector<Junction> junctions;
  /// What was read in spite of the standard ("file:line: <element> attribute: what"): links to
  /// roads or junctions that do not exist (dropped), a road length that disagrees with its
  /// geometry, pRange spelled in another case.
  std::vector<std::string> warnings;

  const Road* find_road(const std::string& id) const;
  const Junction* find_junction(const std::string& id) const;
  std::size_t road_index(const std::string& id) const;  ///< roads.size() when absent
};

/// How far consecutive geometries may miss each other in s, and a road's length its geometry's
/// end, before the file is refused (a gap or an overlap) or warned about (the length).
inline constexpr double kDefaultGeometryTolerance = 1e-3;

/// Parses OpenDRIVE text; `file` names it in messages. Throws MapError ("file:line: <element>
/// attribute 'name': what") on malformed XML, missing or non-numeric attributes, NaN or infinite
/// values, negative lengths, unknown geometry elements, and consecutive geometries whose s leave
/// a gap or an overlap beyond `tolerance_m`. Lane <border> records are refused rather than
/// ignored, because a lane placed without its border would be silently wrong. What it reads in
/// spite of the standard it says in RoadNetwork::warnings: links to roads or junctions that do
/// not exist (dropped), a road length that disagrees with its geometry (the road ends where its
/// geometry ends), pRange in another case.
RoadNetwork parse_opendrive(const std::string& xml_text, const std::string& file,
                            double tolerance_m = kDefaultGeometryTolerance);

/// Reads and parses a .xodr file.
RoadNetwork load_opendrive(const std::string& path, double tolerance_m = kDefaultGeometryTolerance);

// ---- evaluation -------------------------------------------------------------------------------

struct RefPoint {
  double x = 0.0;
  double y = 0.0;
  double hdg = 0.0;
};

/// Point and heading of one geometry record at `ds` metres from its start (clamped to [0, length]).
RefPoint evaluate_geometry(const Geometry& g, double ds);

/// The arc length of a paramPoly3's cubic over its whole p range (Geometry::curve_arc_length).
double paramPoly3_arc_length(const Geometry& g);

/// The reference line of `road` at `s` (clamped to [0, length]).
RefPoint evaluate_reference(const Road& road, double s);

/// Lateral offset of the centre lane (laneOffset) at `s`.
double lane_offset_at(const Road& road, double s);

/// Index of the lane section that holds `s`.
std::size_t section_index_at(const Road& road, double s);

/// Width of lane `lane_id` of section `section` at road position `s`.
double lane_width_at(const Road& road, std::size_t section, int lane_id, double s);

/// Signed lateral offset t of the centre of lane `lane_id` (not 0) at `s`: positive to the left.
double lane_center_t(const Road& road, std::size_t section, int lane_id, double s);

/// The centre of lane `lane_id` of section `section` at `s`, heading along the reference line.
RefPoint lane_center(const Road& road, std::size_t section, int lane_id, double s);

/// Fresnel integrals C(x) = int_0^x cos(pi t^2 / 2) dt and S(x) = int_0^x sin(pi t^2 / 2) dt.
void fresnel(double x, double& c, double& s);

}  // namespace fleet::map
