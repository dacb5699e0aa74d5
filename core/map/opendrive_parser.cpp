// OpenDRIVE reader [Forklift thesis, section 5.1, Fig. 5.3 steps 1-6]: pulls roads, links, junctions,
// plan-view geometry and lanes out of the XML and refuses anything it cannot place exactly.

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <pugixml.hpp>
#include <set>
#include <sstream>
#include <utility>

#include "map/opendrive.hpp"
#include "map/site.hpp"

namespace fleet::map {

namespace {

class Parser {
 public:
  Parser(const std::string& text, std::string file, double tolerance) : file_(std::move(file)), tolerance_(tolerance) {
    line_starts_.push_back(0);
    for (std::size_t i = 0; i < text.size(); ++i) {
      if (text[i] == '\n') line_starts_.push_back(i + 1);
    }
  }

  int line_at(std::ptrdiff_t offset) const {
    if (offset < 0) return 0;
    const auto it = std::upper_bound(line_starts_.begin(), line_starts_.end(), static_cast<std::size_t>(offset));
    return static_cast<int>(it - line_starts_.begin());
  }

  int line_of(const pugi::xml_node& node) const { return line_at(node.offset_debug()); }

  std::string where(int line) const { return file_ + ":" + std::to_string(line); }

  [[noreturn]] void fail_at(int line, const std::string& element, const std::string& attribute,
                            const std::string& what) const {
    std::string msg = where(line) + ": <" + element + ">";
    if (!attribute.empty()) msg += " attribute '" + attribute + "'";
    throw MapError(msg + ": " + what);
  }

  [[noreturn]] void fail(const pugi::xml_node& node, const std::string& attribute, const std::string& what) const {
    fail_at(line_of(node), node.name(), attribute, what);
  }

  /// What the parser reads in spite of the standard, said in the same form as an error.
  void warn_at(int line, const std::string& element, const std::string& attribute, const std::string& what) const {
    std::string msg = where(line) + ": <" + element + ">";
    if (!attribute.empty()) msg += " attribute '" + attribute + "'";
    warnings_.push_back(msg + ": " + what);
  }
  void warn(const pugi::xml_node& node, const std::string& attribute, const std::string& what) const {
    warn_at(line_of(node), node.name(), attribute, what);
  }
  std::vector<std::string> warnings() const { return warnings_; }
  double tolerance() const { return tolerance_; }

  std::string text(const pugi::xml_node& node, const char* name) const {
    const pugi::xml_attribute attr = node.attribute(name);
    if (!attr) fail(node, name, "is missing");
    return attr.value();
  }

  std::string text_or(const pugi::xml_node& node, const char* name, const std::string& fallback) const {
    const pugi::xml_attribute attr = node.attribute(name);
    return attr ? std::string(attr.value()) : fallback;
  }

  double number(const pugi::xml_node& node, const char* name) const {
    const pugi::xml_attribute attr = node.attribute(name);
    if (!attr) fail(node, name, "is missing");
    return to_number(node, name, attr.value());
  }

  double number_or(const pugi::xml_node& node, const char* name, double fallback) const {
    const pugi::xml_attribute attr = node.attribute(name);
    return attr ? to_number(node, name, attr.value()) : fallback;
  }

  double length(const pugi::xml_node& node, const char* name) const {
    const double v = number(node, name);
    if (v < 0.0) fail(node, name, "length " + std::string(node.attribute(name).value()) + " is negative");
    return v;
  }

  int integer(const pugi::xml_node& node, const char* name) const {
    const pugi::xml_attribute attr = node.attribute(name);
    if (!attr) fail(node, name, "is missing");
    const double v = to_number(node, name, attr.value());
    if (v != std::floor(v) || std::abs(v) > 1e6)
      fail(node, name, "'" + std::string(attr.value()) + "' is not an integer");
    return static_cast<int>(v);
  }

  ContactPoint contact(const pugi::xml_node& node, const char* name, bool required) const {
    const pugi::xml_attribute attr = node.attribute(name);
    if (!attr) {
      if (required) fail(node, name, "is missing");
      return ContactPoint::kNone;
    }
    const std::string v = attr.value();
    if (v == "start") return ContactPoint::kStart;
    if (v == "end") return ContactPoint::kEnd;
    fail(node, name, "'" + v + "' is neither start nor end");
  }

  const std::string& file() const { return file_; }

 private:
  double to_number(const pugi::xml_node& node, const char* name, const char* raw) const {
    std::string_view v(raw);
    while (!v.empty() && std::isspace(static_cast<unsigned char>(v.front()))) v.remove_prefix(1);
    while (!v.empty() && std::isspace(static_cast<unsigned char>(v.back()))) v.remove_suffix(1);
    if (!v.empty() && v.front() == '+') v.remove_prefix(1);
    double out = 0.0;
    const auto [ptr, ec] = std::from_chars(v.data(), v.data() + v.size(), out);
    if (v.empty() || ec != std::errc() || ptr != v.data() + v.size()) {
      fail(node, name, "'" + std::string(raw) + "' is not a number");
    }
    if (!std::isfinite(out)) fail(node, name, "'" + std::string(raw) + "' is not finite");
    return out;
  }

  std::string file_;
  std::vector<std::size_t> line_starts_;
  double tolerance_;
  mutable std::vector<std::string> warnings_;
};

CubicPoly cubic(const Parser& p, const pugi::xml_node& node, const char* s_name) {
  return {p.number(node, s_name), p.number(node, "a"), p.number(node, "b"), p.number(node, "c"), p.number(node, "d")};
}

std::optional<RoadLink> road_link(const Parser& p, const pugi::xml_node& node) {
  if (!node) return std::nullopt;
  RoadLink link;
  link.line = p.line_of(node);
  const std::string type = p.text(node, "elementType");
  if (type == "road") {
    link.target = LinkTarget::kRoad;
  } else if (type == "junction") {
    link.target = LinkTarget::kJunction;
  } else {
    p.fail(node, "elementType", "'" + type + "' is neither road nor junction");
  }
  link.element_id = p.text(node, "elementId");
  // A missing contactPoint on a road link is inferred from the geometry by the graph builder.
  link.contact = link.target == LinkTarget::kRoad ? p.contact(node, "contactPoint", false) : ContactPoint::kNone;
  return link;
}

/// Forty full circles: see the spiral case below.
constexpr double kMaxSpiralTurn = 250.0;

Geometry geometry(const Parser& p, const pugi::xml_node& node) {
  Geometry g;
  g.line = p.line_of(node);
  g.s = p.length(node, "s");
  g.x = p.number(node, "x");
  g.y = p.number(node, "y");
  g.hdg = p.number(node, "hdg");
  g.length = p.length(node, "length");
  pugi::xml_node shape;
  for (const pugi::xml_node child : node.children()) {
    if (child.type() != pugi::node_element) continue;
    if (shape) p.fail(child, "", "a <geometry> holds exactly one shape element");
    shape = child;
  }
  if (!shape) p.fail(node, "", "has no shape element (line, arc, spiral, poly3 or paramPoly3)");
  const std::string kind = shape.name();
  if (kind == "line") {
    g.kind = GeometryKind::kLine;
  } else if (kind == "arc") {
    g.kind = GeometryKind::kArc;
    g.curvature = p.number(shape, "curvature");
  } else if (kind == "spiral") {
    g.kind = GeometryKind::kSpiral;
    g.curv_start = p.number(shape, "curvStart");
    g.curv_end = p.number(shape, "curvEnd");
    // A spiral is integrated numerically, at a cost that grows with its turn. No road turns
    // forty full circles in one geometry; such a spiral is a broken file, refused by name.
    const double turn = std::max(std::abs(g.curv_start), std::abs(g.curv_end)) * g.length;
    if (!(turn <= kMaxSpiralTurn)) {
      p.fail(shape, "curvEnd",
             "the spiral turns up to " + std::to_string(turn) + " rad over its length " + std::to_string(g.length) +
                 " m, more than the " + std::to_string(static_cast<int>(kMaxSpiralTurn)) + " rad a road geometry may");
    }
  } else if (kind == "poly3") {
    g.kind = GeometryKind::kPoly3;
    g.a = p.number(shape, "a");
    g.b = p.number(shape, "b");
    g.c = p.number(shape, "c");
    g.d = p.number(shape, "d");
  } else if (kind == "paramPoly3") {
    g.kind = GeometryKind::kParamPoly3;
    g.au = p.number(shape, "aU");
    g.bu = p.number(shape, "bU");
    g.cu = p.number(shape, "cU");
    g.du = p.number(shape, "dU");
    g.av = p.number(shape, "aV");
    g.bv = p.number(shape, "bV");
    g.cv = p.number(shape, "cV");
    g.dv = p.number(shape, "dV");
    // OpenDRIVE 1.4 had no pRange and meant p in [0, 1]; later revisions keep that default.
    const std::string range = p.text_or(shape, "pRange", "normalized");
    const auto lower = [](std::string t) {
      for (char& c : t) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      return t;
    };
    if (range == "normalized") {
      g.normalized = true;
    } else if (range == "arcLength") {
      g.normalized = false;
    } else if (lower(range) == "normalized" || lower(range) == "arclength") {
      // Written by tools that do not mind the case; what they mean is not in doubt.
      g.normalized = lower(range) == "normalized";
      p.warn(shape, "pRange",
             "'" + range + "' read as '" + (g.normalized ? "normalized" : "arcLength") + "' (the standard's spelling)");
    } else {
      p.fail(shape, "pRange", "'" + range + "' is neither normalized nor arcLength");
    }
    // Every point of the geometry scales s by it: integrated once, here.
    g.curve_arc_length = paramPoly3_arc_length(g);
  } else {
    p.fail(shape, "", "unknown geometry element");
  }
  return g;
}

Lane lane(const Parser& p, const pugi::xml_node& node) {
  Lane l;
  l.line = p.line_of(node);
  l.id = p.integer(node, "id");
  l.type = p.text(node, "type");
  if (const pugi::xml_node link = node.child("link")) {
    if (const pugi::xml_node pred = link.child("predecessor")) l.predecessor = p.integer(pred, "id");
    if (const pugi::xml_node succ = link.child("successor")) l.successor = p.integer(succ, "id");
  }
  for (const pugi::xml_node w : node.children("width")) {
    CubicPoly poly = cubic(p, w, "sOffset");
    if (poly.s < 0.0) p.fail(w, "sOffset", "is negative");
    if (!l.widths.empty() && poly.s < l.widths.back().s) p.fail(w, "sOffset", "widths must be ordered by sOffset");
    l.widths.push_back(poly);
  }
  if (l.widths.empty() && node.child("border")) {
    p.fail(node.child("border"), "", "lane borders are not supported; describe the lane with <width>");
  }
  if (l.id != 0 && l.widths.empty()) p.fail(node, "", "lane " + std::to_string(l.id) + " has no <width>");
  return l;
}

void side(const Parser& p, const pugi::xml_node& node, int sign, std::vector<Lane>& out) {
  if (!node) return;
  for (const pugi::xml_node n : node.children("lane")) {
    Lane l = lane(p, n);
    if (l.id * sign <= 0) {
      p.fail(n, "id", "lane " + std::to_string(l.id) + " is on the wrong side (" + std::string(node.name()) + ")");
    }
    out.push_back(std::move(l));
  }
  std::sort(out.begin(), out.end(), [](const Lane& a, const Lane& b) { return std::abs(a.id) < std::abs(b.id); });
  // Lane centres are found by adding the widths of the lanes inside them, so the ids must run
  // 1, 2, ... without gaps or the offsets would be silently wrong.
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (std::abs(out[i].id) != static_cast<int>(i + 1)) {
      p.fail_at(out[i].line, "lane", "id",
                "lane ids on the " + std::string(node.name()) + " must run " + std::to_string(sign) + ", " +
                    std::to_string(2 * sign) + ", ... without gaps or repeats");
    }
  }
}

Road road(const Parser& p, const pugi::xml_node& node) {
  Road r;
  r.line = p.line_of(node);
  r.id = p.text(node, "id");
  if (r.id.empty()) p.fail(node, "id", "is empty");
  r.name = p.text_or(node, "name", "");
  r.length = p.length(node, "length");
  r.junction = p.text_or(node, "junction", "-1");
  if (r.junction.empty()) r.junction = "-1";
  const std::string rule = p.text_or(node, "rule", "RHT");
  if (rule != "RHT" && rule != "LHT") p.fail(node, "rule", "'" + rule + "' is neither RHT nor LHT");
  r.left_hand_traffic = rule == "LHT";

  if (const pugi::xml_node link = node.child("link")) {
    r.predecessor = road_link(p, link.child("predecessor"));
    r.successor = road_link(p, link.child("successor"));
  }

  const pugi::xml_node plan = node.child("planView");
  if (!plan) p.fail(node, "", "road '" + r.id + "' has no <planView>");
  for (const pugi::xml_node g : plan.children("geometry")) {
    Geometry geo = geometry(p, g);
    if (!r.plan_view.empty() && geo.s < r.plan_view.back().s) p.fail(g, "s", "geometries must be ordered by s");
    r.plan_view.push_back(geo);
  }
  if (r.plan_view.empty()) p.fail(plan, "", "road '" + r.id + "' has no <geometry>");
  // Consecutive geometries meet in s. A gap or an overlap beyond the tolerance cannot be placed
  // exactly (which geometry holds the s between?), so it is refused, naming where.
  for (std::size_t i = 1; i < r.plan_view.size(); ++i) {
    const Geometry& before = r.plan_view[i - 1];
    const Geometry& next = r.plan_view[i];
    const double gap = next.s - (before.s + before.length);
    if (std::abs(gap) > p.tolerance()) {
      p.fail_at(next.line, "geometry", "s",
                "road '" + r.id + "': the geometry at s=" + std::to_string(next.s) + " starts " +
                    std::to_string(std::abs(gap)) + " m " + (gap > 0 ? "after" : "before") +
                    " the end of the one at s=" + std::to_string(before.s) + " (length " +
                    std::to_string(before.length) + "): " + (gap > 0 ? "a gap" : "an overlap") +
                    " beyond the tolerance of " + std::to_string(p.tolerance()) + " m");
    }
  }

  const pugi::xml_node lanes = node.child("lanes");
  if (!lanes) p.fail(node, "", "road '" + r.id + "' has no <lanes>");
  for (const pugi::xml_node o : lanes.children("laneOffset")) {
    CubicPoly poly = cubic(p, o, "s");
    if (!r.lane_offsets.empty() && poly.s < r.lane_offsets.back().s) p.fail(o, "s", "laneOffsets must be ordered by s");
    r.lane_offsets.push_back(poly);
  }
  for (const pugi::xml_node sec : lanes.children("laneSection")) {
    LaneSection section;
    section.line = p.line_of(sec);
    section.s = p.length(sec, "s");
    if (section.s > r.length + 1e-6) p.fail(sec, "s", "lies beyond the road length " + std::to_string(r.length));
    if (!r.sections.empty() && section.s < r.sections.back().s) p.fail(sec, "s", "laneSections must be ordered by s");
    side(p, sec.child("left"), +1, section.left);
    side(p, sec.child("right"), -1, section.right);
    r.sections.push_back(std::move(section));
  }
  if (r.sections.empty()) p.fail(lanes, "", "road '" + r.id + "' has no <laneSection>");
  // A road whose length disagrees with its geometry ends where its geometry ends: past that end
  // there is nothing to place points on.
  const double geometry_end = r.plan_view.back().s + r.plan_view.back().length;
  if (std::abs(geometry_end - r.length) > p.tolerance()) {
    p.warn(node, "length",
           "road '" + r.id + "' is " + std::to_string(r.length) +
               " m long, but its planView ends at s=" + std::to_string(geometry_end) + ": the road ends there");
    r.length = geometry_end;
  }
  return r;
}

Junction junction(const Parser& p, const pugi::xml_node& node) {
  Junction j;
  j.line = p.line_of(node);
  j.id = p.text(node, "id");
  j.name = p.text_or(node, "name", "");
  for (const pugi::xml_node c : node.children("connection")) {
    Connection con;
    con.line = p.line_of(c);
    con.id = p.text_or(c, "id", std::to_string(j.connections.size()));
    con.incoming_road = p.text(c, "incomingRoad");
    // Direct junctions (OpenDRIVE 1.7) name the linked road instead of a connecting road.
    con.connecting_road = c.attribute("connectingRoad") || !c.attribute("linkedRoad") ? p.text(c, "connectingRoad")
                                                                                      : p.text(c, "linkedRoad");
    con.contact = p.contact(c, "contactPoint", true);
    for (const pugi::xml_node ll : c.children("laneLink"))
      con.lane_links.push_back({p.integer(ll, "from"), p.integer(ll, "to")});
    j.connections.push_back(std::move(con));
  }
  return j;
}

}  // namespace

bool Lane::drivable() const {
  return type == "driving" || type == "bidirectional" || type == "entry" || type == "exit" || type == "onRamp" ||
         type == "offRamp" || type == "connectingRamp";
}

const Lane* LaneSection::find(int lane_id) const {
  const auto& lanes = lane_id > 0 ? left : right;
  const auto k = static_cast<std::size_t>(std::abs(lane_id));
  if (lane_id == 0 || k > lanes.size()) return nullptr;
  return &lanes[k - 1];
}

double Road::section_end(std::size_t i) const {
  return i + 1 < sections.size() ? sections[i + 1].s : length;
}

const Road* RoadNetwork::find_road(const std::string& id) const {
  const std::size_t i = road_index(id);
  return i < roads.size() ? &roads[i] : nullptr;
}

std::size_t RoadNetwork::road_index(const std::string& id) const {
  for (std::size_t i = 0; i < roads.size(); ++i) {
    if (roads[i].id == id) return i;
  }
  return roads.size();
}

const Junction* RoadNetwork::find_junction(const std::string& id) const {
  for (const auto& j : junctions) {
    if (j.id == id) return &j;
  }
  return nullptr;
}

RoadNetwork parse_opendrive(const std::string& xml_text, const std::string& file, double tolerance_m) {
  if (!(tolerance_m >= 0.0) || !std::isfinite(tolerance_m)) {
    throw MapError(file + ": tolerance " + std::to_string(tolerance_m) + " m must be a non-negative number");
  }
  const Parser p(xml_text, file, tolerance_m);
  pugi::xml_document doc;
  const pugi::xml_parse_result result = doc.load_buffer(xml_text.data(), xml_text.size());
  if (!result) {
    throw MapError(p.where(p.line_at(result.offset)) + ": malformed XML: " + result.description());
  }
  const pugi::xml_node root = doc.child("OpenDRIVE");
  if (!root) throw MapError(file + ":1: <OpenDRIVE> root element is missing");

  RoadNetwork net;
  net.file = file;
  if (const pugi::xml_node h = root.child("header")) {
    net.header.rev_major = h.attribute("revMajor") ? p.integer(h, "revMajor") : 1;
    net.header.rev_minor = h.attribute("revMinor") ? p.integer(h, "revMinor") : 4;
    net.header.name = p.text_or(h, "name", "");
    net.header.north = p.number_or(h, "north", 0.0);
    net.header.south = p.number_or(h, "south", 0.0);
    net.header.east = p.number_or(h, "east", 0.0);
    net.header.west = p.number_or(h, "west", 0.0);
  }

  std::set<std::string> road_ids;
  for (const pugi::xml_node r : root.children("road")) {
    Road rd = road(p, r);
    if (!road_ids.insert(rd.id).second) p.fail(r, "id", "duplicate road id '" + rd.id + "'");
    net.roads.push_back(std::move(rd));
  }
  if (net.roads.empty()) throw MapError(file + ":" + std::to_string(p.line_of(root)) + ": <OpenDRIVE> holds no <road>");

  std::set<std::string> junction_ids;
  for (const pugi::xml_node j : root.children("junction")) {
    Junction jn = junction(p, j);
    if (!junction_ids.insert(jn.id).second) p.fail(j, "id", "duplicate junction id '" + jn.id + "'");
    net.junctions.push_back(std::move(jn));
  }

  // References are checked once everything is read, because links may point forward in the file.
  // A link to a road or junction that does not exist is dropped with a warning: real files have
  // them, other tools load such files, and the rest of the network is sound.
  for (Road& r : net.roads) {
    for (auto* link : {&r.predecessor, &r.successor}) {
      if (!link->has_value()) continue;
      const RoadLink& l = **link;
      const char* element = link == &r.predecessor ? "predecessor" : "successor";
      const bool dangling = (l.target == LinkTarget::kRoad && !road_ids.contains(l.element_id)) ||
                            (l.target == LinkTarget::kJunction && !junction_ids.contains(l.element_id));
      if (dangling) {
        p.warn_at(l.line, element, "elementId",
                  std::string(l.target == LinkTarget::kRoad ? "road '" : "junction '") + l.element_id +
                      "' does not exist: the " + element + " link of road '" + r.id + "' is dropped");
        link->reset();
      }
    }
    if (r.in_junction() && !junction_ids.contains(r.junction)) {
      p.fail_at(r.line, "road", "junction", "junction '" + r.junction + "' does not exist");
    }
  }
  for (Junction& j : net.junctions) {
    std::erase_if(j.connections, [&](const Connection& c) {
      for (const auto& [attribute, id] :
           {std::pair{"incomingRoad", c.incoming_road}, {"connectingRoad", c.connecting_road}}) {
        if (!road_ids.contains(id)) {
          p.warn_at(c.line, "connection", attribute,
                    "road '" + id + "' does not exist: the connection is dropped from junction '" + j.id + "'");
          return true;
        }
      }
      return false;
    });
  }
  net.warnings = p.warnings();
  return net;
}

RoadNetwork load_opendrive(const std::string& path, double tolerance_m) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw MapError(path + ": cannot open the OpenDRIVE file");
  std::stringstream buffer;
  buffer << in.rdbuf();
  return parse_opendrive(buffer.str(), path, tolerance_m);
}

}  // namespace fleet::map
