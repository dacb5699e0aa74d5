// Bad OpenDRIVE input is refused with the file, line, element and attribute named.

#include <gtest/gtest.h>

#include <string>

#include "map/opendrive.hpp"
#include "map/site.hpp"

using namespace fleet::map;

namespace {

// A valid one-road file; each test breaks one thing in it. Line numbers below count from 1.
std::string road_xml(const std::string& geometry_attrs = R"(s="0" x="0" y="0" hdg="0" length="10")",
                     const std::string& shape = "<line/>", const std::string& link = "",
                     const std::string& road_attrs = R"(id="1" length="10" junction="-1")",
                     const std::string& width = R"(sOffset="0" a="3" b="0" c="0" d="0")") {
  return "<?xml version=\"1.0\"?>\n"                    // 1
         "<OpenDRIVE>\n"                                // 2
         "  <header revMajor=\"1\" revMinor=\"6\"/>\n"  // 3
         "  <road " +
         road_attrs +
         ">\n"  // 4
         "    <link>" +
         link +
         "</link>\n"         // 5
         "    <planView>\n"  // 6
         "      <geometry " +
         geometry_attrs +
         ">\n"  // 7
         "        " +
         shape +
         "\n"                                                         // 8
         "      </geometry>\n"                                        // 9
         "    </planView>\n"                                          // 10
         "    <lanes>\n"                                              // 11
         "      <laneSection s=\"0\">\n"                              // 12
         "        <center><lane id=\"0\" type=\"none\"/></center>\n"  // 13
         "        <right>\n"                                          // 14
         "          <lane id=\"-1\" type=\"driving\">\n"              // 15
         "            <width " +
         width +
         "/>\n"  // 16
         "          </lane>\n"
         "        </right>\n"
         "      </laneSection>\n"
         "    </lanes>\n"
         "  </road>\n"
         "</OpenDRIVE>\n";
}

std::string error_of(const std::string& xml) {
  try {
    parse_opendrive(xml, "maps/bad.xodr");
  } catch (const MapError& e) {
    return e.what();
  }
  return "";
}

#define EXPECT_HAS(msg, part) EXPECT_NE((msg).find(part), std::string::npos) << (msg)

}  // namespace

TEST(OpenDriveErrors, ValidFixtureParses) {
  const RoadNetwork net = parse_opendrive(road_xml(), "ok.xodr");
  ASSERT_EQ(net.roads.size(), 1u);
  EXPECT_EQ(net.header.rev_minor, 6);
  EXPECT_EQ(net.roads[0].sections[0].right.size(), 1u);
}

TEST(OpenDriveErrors, MalformedXmlNamesFileAndLine) {
  std::string xml = road_xml();
  xml.replace(xml.find("</planView>"), 11, "</planVieww>");
  const std::string msg = error_of(xml);
  EXPECT_HAS(msg, "maps/bad.xodr:10:");
  EXPECT_HAS(msg, "malformed XML");
}

TEST(OpenDriveErrors, MissingAttributeIsNamed) {
  const std::string msg = error_of(road_xml(R"(s="0" x="0" y="0" length="10")"));
  EXPECT_HAS(msg, "maps/bad.xodr:7: <geometry> attribute 'hdg': is missing");
}

TEST(OpenDriveErrors, NonNumericAndNaNAreRefused) {
  EXPECT_HAS(error_of(road_xml(R"(s="0" x="abc" y="0" hdg="0" length="10")")),
             "maps/bad.xodr:7: <geometry> attribute 'x': 'abc' is not a number");
  EXPECT_HAS(error_of(road_xml(R"(s="0" x="1.5m" y="0" hdg="0" length="10")")), "'1.5m' is not a number");
  EXPECT_HAS(error_of(road_xml(R"(s="0" x="0" y="nan" hdg="0" length="10")")),
             "maps/bad.xodr:7: <geometry> attribute 'y': 'nan' is not finite");
  EXPECT_HAS(error_of(road_xml(R"(s="0" x="0" y="0" hdg="0" length="10")", "<arc curvature=\"inf\"/>")),
             "maps/bad.xodr:8: <arc> attribute 'curvature': 'inf' is not finite");
  EXPECT_HAS(error_of(road_xml(R"(s="0" x="0" y="0" hdg="0" length="10")", "<line/>", "",
                               R"(id="1" length="10" junction="-1")", R"(sOffset="0" a="" b="0" c="0" d="0")")),
             "maps/bad.xodr:16: <width> attribute 'a': '' is not a number");
}

TEST(OpenDriveErrors, NegativeLengthsAreRefused) {
  EXPECT_HAS(error_of(road_xml(R"(s="0" x="0" y="0" hdg="0" length="-1")")),
             "maps/bad.xodr:7: <geometry> attribute 'length': length -1 is negative");
  EXPECT_HAS(error_of(road_xml(R"(s="0" x="0" y="0" hdg="0" length="10")", "<line/>", "",
                               R"(id="1" length="-10" junction="-1")")),
             "maps/bad.xodr:4: <road> attribute 'length'");
}

TEST(OpenDriveErrors, UnknownGeometryElementIsNamed) {
  EXPECT_HAS(error_of(road_xml(R"(s="0" x="0" y="0" hdg="0" length="10")", "<clothoid k=\"1\"/>")),
             "maps/bad.xodr:8: <clothoid>: unknown geometry element");
  EXPECT_HAS(error_of(road_xml(R"(s="0" x="0" y="0" hdg="0" length="10")", "")), "has no shape element");
  EXPECT_HAS(
      error_of(road_xml(R"(s="0" x="0" y="0" hdg="0" length="10")",
                        R"(<paramPoly3 aU="0" bU="1" cU="0" dU="0" aV="0" bV="0" cV="0" dV="0" pRange="degrees"/>)")),
      "attribute 'pRange': 'degrees' is neither normalized nor arcLength");
}

// A spiral costs a numerical integral that grows with its turn; one turning more than forty full
// circles is a broken file (the fuzzer's was 1e9 m long) and is refused instead of taking minutes.
TEST(OpenDriveErrors, ASpiralTurningFortyCirclesIsRefused) {
  EXPECT_HAS(error_of(road_xml(R"(s="0" x="0" y="0" hdg="0" length="1071390801")",
                               R"(<spiral curvStart="0.008" curvEnd="0.0"/>)", "",
                               R"(id="1" length="1071390801" junction="-1")")),
             "maps/bad.xodr:8: <spiral> attribute 'curvEnd': the spiral turns up to 8571126");
  EXPECT_EQ(error_of(road_xml(R"(s="0" x="0" y="0" hdg="0" length="10")", R"(<spiral curvStart="0" curvEnd="0.2"/>)")),
            "");
}

/// The warnings of a file that parses.
std::string warnings_of(const std::string& xml) {
  std::string all;
  for (const auto& w : parse_opendrive(xml, "maps/bad.xodr").warnings) all += w + "\n";
  return all;
}

// Real files have links to roads that are not in them; other tools load such files and drop the
// link, and so does this parser, saying so with the file, line and id.
TEST(OpenDriveErrors, LinksToMissingRoadsAndJunctionsAreDroppedWithAWarning) {
  const std::string dangling = road_xml(R"(s="0" x="0" y="0" hdg="0" length="10")", "<line/>",
                                        R"(<successor elementType="road" elementId="42" contactPoint="start"/>)");
  EXPECT_HAS(warnings_of(dangling),
             "maps/bad.xodr:5: <successor> attribute 'elementId': road '42' does not exist: the successor link of "
             "road '1' is dropped");
  EXPECT_FALSE(parse_opendrive(dangling, "maps/bad.xodr").roads[0].successor.has_value());
  EXPECT_HAS(warnings_of(road_xml(R"(s="0" x="0" y="0" hdg="0" length="10")", "<line/>",
                                  R"(<predecessor elementType="junction" elementId="7"/>)")),
             "<predecessor> attribute 'elementId': junction '7' does not exist");
  EXPECT_HAS(error_of(road_xml(R"(s="0" x="0" y="0" hdg="0" length="10")", "<line/>",
                               R"(<successor elementType="road" elementId="1" contactPoint="middle"/>)")),
             "attribute 'contactPoint': 'middle' is neither start nor end");
  std::string with_junction = road_xml();
  with_junction.replace(with_junction.find("</OpenDRIVE>"), 12,
                        "<junction id=\"9\"><connection id=\"0\" incomingRoad=\"1\" connectingRoad=\"5\" "
                        "contactPoint=\"start\"/></junction></OpenDRIVE>");
  EXPECT_HAS(warnings_of(with_junction),
             "<connection> attribute 'connectingRoad': road '5' does not exist: the connection is dropped from "
             "junction '9'");
  EXPECT_TRUE(parse_opendrive(with_junction, "maps/bad.xodr").junctions[0].connections.empty());
  EXPECT_EQ(warnings_of(road_xml()), "") << "a sound file has no warning";
}

/// The one-road file with its planView in two lines, the second starting at `second_s`.
std::string two_geometries(const std::string& second_s, const std::string& road_length = "10") {
  std::string xml = road_xml(R"(s="0" x="0" y="0" hdg="0" length="5")", "<line/>", "",
                             R"(id="1" length=")" + road_length + R"(" junction="-1")");
  const std::string second = "      <geometry s=\"" + second_s +
                             "\" x=\"5\" y=\"0\" hdg=\"0\" length=\"5\">\n"  // 10
                             "        <line/>\n"                             // 11
                             "      </geometry>\n";                          // 12
  xml.insert(xml.find("    </planView>"), second);
  return xml;
}

TEST(OpenDriveErrors, AGapOrOverlapBetweenGeometriesIsRefusedNamingRoadAndS) {
  EXPECT_NO_THROW(parse_opendrive(two_geometries("5.0005"), "maps/bad.xodr")) << "within the 1 mm tolerance";
  EXPECT_HAS(error_of(two_geometries("5.5")),
             "maps/bad.xodr:10: <geometry> attribute 's': road '1': the geometry at s=5.500000 starts 0.500000 m "
             "after the end of the one at s=0.000000 (length 5.000000): a gap beyond the tolerance of 0.001000 m");
  EXPECT_HAS(error_of(two_geometries("4.9")), "starts 0.100000 m before the end of the one at s=0.000000");
  EXPECT_HAS(error_of(two_geometries("4.9")), "an overlap beyond the tolerance");
  // The tolerance is the caller's.
  EXPECT_NO_THROW(parse_opendrive(two_geometries("5.5"), "maps/bad.xodr", 1.0));
}

TEST(OpenDriveErrors, ARoadLongerThanItsGeometryEndsWhereItsGeometryEndsWithAWarning) {
  const RoadNetwork net = parse_opendrive(two_geometries("5", "2000"), "maps/bad.xodr");
  EXPECT_DOUBLE_EQ(net.roads[0].length, 10.0);
  ASSERT_EQ(net.warnings.size(), 1u);
  EXPECT_HAS(net.warnings[0],
             "maps/bad.xodr:4: <road> attribute 'length': road '1' is 2000.000000 m long, but its planView ends at "
             "s=10.000000: the road ends there");
}

TEST(OpenDriveErrors, PRangeInAnotherCaseIsReadAsTheStandardsValueWithAWarning) {
  const std::string xml =
      road_xml(R"(s="0" x="0" y="0" hdg="0" length="10")",
               R"(<paramPoly3 aU="0" bU="1" cU="0" dU="0" aV="0" bV="0" cV="0" dV="0" pRange="arclength"/>)");
  EXPECT_HAS(warnings_of(xml), "maps/bad.xodr:8: <paramPoly3> attribute 'pRange': 'arclength' read as 'arcLength'");
  EXPECT_FALSE(parse_opendrive(xml, "maps/bad.xodr").roads[0].plan_view[0].normalized);
}

TEST(OpenDriveErrors, StructuralProblemsAreRefused) {
  EXPECT_HAS(error_of("<?xml version=\"1.0\"?>\n<Road/>\n"), "maps/bad.xodr:1: <OpenDRIVE> root element is missing");
  EXPECT_HAS(error_of("<OpenDRIVE><header/></OpenDRIVE>"), "holds no <road>");
  EXPECT_HAS(error_of(""), "malformed XML");
  std::string twice = road_xml();
  const std::size_t a = twice.find("  <road ");
  const std::size_t b = twice.find("</OpenDRIVE>");
  twice.insert(b, twice.substr(a, b - a));
  EXPECT_HAS(error_of(twice), "duplicate road id '1'");
  std::string wrong_side = road_xml();
  wrong_side.replace(wrong_side.find("id=\"-1\""), 7, "id=\"2\"");
  EXPECT_HAS(error_of(wrong_side), "maps/bad.xodr:15: <lane> attribute 'id': lane 2 is on the wrong side (right)");
  std::string border = road_xml();
  border.replace(border.find("<width "), 7, "<border ");
  EXPECT_HAS(error_of(border), "lane borders are not supported");
}

TEST(OpenDriveErrors, TruncatedFilesNeverCrash) {
  const std::string xml = road_xml();
  for (std::size_t n = 0; n < xml.size(); n += 7) {
    try {
      const RoadNetwork net = parse_opendrive(xml.substr(0, n), "cut.xodr");
      EXPECT_FALSE(net.roads.empty());
    } catch (const MapError& e) {
      EXPECT_HAS(std::string(e.what()), "cut.xodr:");
    }
  }
}
