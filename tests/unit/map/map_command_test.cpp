// fleetctl map check|sample|render, driven through the same entry point fleetctl calls.

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "commands.hpp"
#include "test_data.hpp"
#include "test_paths.hpp"

using namespace fleet::cli;

namespace {

struct CommandRun {
  int code = -1;
  std::string out, err;
};

CommandRun run(std::vector<std::string> args, bool json = false) {
  CommandArgs a;
  a.args = std::move(args);
  a.json = json;
  a.source_dir = fleet::test::source_dir();
  std::ostringstream out, err;
  CommandRun r;
  r.code = map_command(a, out, err);
  r.out = out.str();
  r.err = err.str();
  return r;
}

}  // namespace

TEST(MapCommand, CheckShippedMapsExitsZero) {
  for (const char* name : {"table_a", "table_b", "warehouse", "plant"}) {
    const CommandRun r = run({"check", std::string(fleet::test::source_path("/maps/")) + name + ".yaml"});
    EXPECT_EQ(r.code, kExitOk) << r.out << r.err;
    EXPECT_NE(r.out.find("usable: yes"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("graph edges: "), std::string::npos);
    EXPECT_TRUE(r.err.empty()) << r.err;
  }
  // By name, all at once, with --json.
  const CommandRun all = run({"check", "table_a", "table_b", "warehouse", "plant"}, true);
  EXPECT_EQ(all.code, kExitOk) << all.err;
  EXPECT_NE(all.out.find("\"usable\":true"), std::string::npos);
  EXPECT_EQ(all.out.find("\"usable\":false"), std::string::npos);
}

TEST(MapCommand, CheckOfABrokenSiteExitsTwoWithTheReason) {
  const auto dir = std::filesystem::temp_directory_path() / "fleet_map_command_test";
  std::filesystem::create_directories(dir);
  const auto path = (dir / "broken.yaml").string();
  std::ofstream(path) << "opendrive: " << fleet::test::source_path("/maps/table_a.xodr")
                      << "\n"
                         "bounds: {min_x: 0, min_y: 0, max_x: 3, max_y: 3}\n"
                         "loading_areas:\n  - {id: A1, x: 0.15, y: 0.975, yaw: 3.1415927}\n";
  const CommandRun r = run({"check", path});
  EXPECT_EQ(r.code, kExitBadInput);
  EXPECT_NE(r.out.find("A1: NOT reachable"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find(path + ":4: key 'loading_areas[0]' (A1)"), std::string::npos) << r.err;
  EXPECT_EQ(run({"check", (dir / "absent.yaml").string()}).code, kExitBadInput);
}

TEST(MapCommand, SamplePrintsCsv) {
  FLEET_SKIP_WITHOUT_OPENDRIVE_DATA();
  const CommandRun r = run({"sample", fleet::test::opendrive_test_file("curves.xodr"), "--step", "0.5"});
  ASSERT_EQ(r.code, kExitOk) << r.err;
  EXPECT_EQ(r.out.rfind("road_id,s,x,y,hdg\n1,0.000000,0.000000,0.000000,0.000000\n", 0), 0u) << r.out.substr(0, 200);
  std::istringstream lines(r.out);
  std::string line;
  std::size_t n = 0;
  while (std::getline(lines, line)) ++n;
  EXPECT_GT(n, 2000u);                                           // 1154 m at 0.5 m
  EXPECT_NE(r.out.find("\n1,1154.399475,"), std::string::npos);  // the road's end, inclusive
}

TEST(MapCommand, SampleOfAMalformedFileExitsTwoWithFileAndLine) {
  const auto path = (std::filesystem::temp_directory_path() / "fleet_bad.xodr").string();
  std::ofstream(path) << "<OpenDRIVE>\n<road id=\"1\" length=\"x\">\n</OpenDRIVE>\n";
  const CommandRun r = run({"sample", path});
  EXPECT_EQ(r.code, kExitBadInput);
  EXPECT_NE(r.err.find(path + ":3: malformed XML"), std::string::npos) << r.err;
  EXPECT_EQ(run({"sample", path, "--step", "fast"}).code, kExitBadInput);
  EXPECT_EQ(run({"sample"}).code, kExitBadInput);
}

TEST(MapCommand, RenderWritesAnSvg) {
  const auto out = (std::filesystem::temp_directory_path() / "fleet_table_a.svg").string();
  std::filesystem::remove(out);
  const CommandRun r = run({"render", "table_a", "-o", out});
  ASSERT_EQ(r.code, kExitOk) << r.err;
  std::ifstream in(out);
  std::stringstream svg;
  svg << in.rdbuf();
  EXPECT_NE(svg.str().find("<svg"), std::string::npos);
  EXPECT_EQ(run({"render", "table_a"}).code, kExitBadInput);  // no -o
  EXPECT_EQ(run({"frobnicate"}).code, kExitBadInput);
}

TEST(MapCommand, RenderDrawsTheTracksASoakWroteFromTheGivenTimeOn) {
  const auto dir = std::filesystem::temp_directory_path() / ("fleet_tracks_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto csv = (dir / "deadlock-1-fl7.csv").string();
  const auto svg_file = (dir / "jam.svg").string();
  std::ofstream(csv) << "robot,sim_s,x,y,yaw\nfl7,10.00,2.0,0.45,3.14\nfl7,20.00,1.9,0.45,3.14\n"
                        "fl5,10.00,1.2,0.46,-1.57\nfl5,20.00,1.17,0.46,-1.57\nfl1,5.00,2.4,0.46,3.1\n";
  const CommandRun r = run({"render", "table_a", "-o", svg_file, "--tracks", csv, "--since", "8"});
  ASSERT_EQ(r.code, kExitOk) << r.err;
  std::ifstream in(svg_file);
  std::stringstream svg;
  svg << in.rdbuf();
  EXPECT_NE(svg.str().find(">fl7</text>"), std::string::npos);
  EXPECT_NE(svg.str().find(">fl5</text>"), std::string::npos);
  EXPECT_EQ(svg.str().find(">fl1</text>"), std::string::npos) << "fl1's only pose is before --since";

  std::ofstream(csv, std::ios::app) << "fl7,21.00,oops,0.45,3.14\n";
  const CommandRun bad = run({"render", "table_a", "-o", svg_file, "--tracks", csv});
  EXPECT_EQ(bad.code, kExitBadInput);
  EXPECT_NE(bad.err.find("deadlock-1-fl7.csv:7"), std::string::npos) << bad.err;
  EXPECT_EQ(run({"render", "table_a", "-o", svg_file, "--tracks", (dir / "none.csv").string()}).code, kExitBadInput);
  EXPECT_EQ(run({"render", "table_a", "-o", svg_file, "--tracks", csv, "--since", "soon"}).code, kExitBadInput);
  std::filesystem::remove_all(dir);
}

namespace {

/// A file of `roads` straight roads, each `length` metres, one with a link to road 99, which is
/// not in the file.
std::string write_long_roads(const std::filesystem::path& dir, int roads, double length) {
  std::ostringstream xml;
  xml << "<?xml version=\"1.0\"?>\n<OpenDRIVE>\n  <header revMajor=\"1\" revMinor=\"6\"/>\n";
  for (int i = 1; i <= roads; ++i) {
    xml << "  <road id=\"" << i << "\" length=\"" << length << "\" junction=\"-1\">\n"
        << (i == 1 ? "    <link><successor elementType=\"road\" elementId=\"99\" contactPoint=\"start\"/></link>\n"
                   : "")
        << "    <planView><geometry s=\"0\" x=\"0\" y=\"" << 10 * i << "\" hdg=\"0\" length=\"" << length
        << "\"><line/></geometry></planView>\n"
        << "    <lanes><laneSection s=\"0\"><center><lane id=\"0\" type=\"none\"/></center>"
        << "<right><lane id=\"-1\" type=\"driving\"><width sOffset=\"0\" a=\"3\" b=\"0\" c=\"0\" "
           "d=\"0\"/></lane></right>"
        << "</laneSection></lanes>\n  </road>\n";
  }
  xml << "</OpenDRIVE>\n";
  const std::string path = (dir / "long_roads.xodr").string();
  std::ofstream(path) << xml.str();
  return path;
}

}  // namespace

// Regression: map sample held every row before printing; four roads 5,000 km long needed tens of
// GB. The rows stream, and their count is capped before anything is printed.
TEST(MapCommand, SampleOfVeryLongRoadsIsCappedBeforePrintingAndStreamsWithMaxRows) {
  const auto dir = std::filesystem::temp_directory_path() / ("fleet_map_long_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string file = write_long_roads(dir, 4, 5.0e6);
  const CommandRun capped = run({"sample", file, "--step", "1"});
  EXPECT_EQ(capped.code, kExitBadInput);
  EXPECT_TRUE(capped.out.empty()) << capped.out.substr(0, 200);
  EXPECT_NE(capped.err.find("makes about 20000008 rows, more than the limit of 10000000 (--max-rows N raises it"),
            std::string::npos)
      << capped.err;
  // A step that keeps it small streams every row.
  const CommandRun coarse = run({"sample", file, "--step", "100000", "--max-rows", "500"});
  EXPECT_EQ(coarse.code, kExitOk) << coarse.err;
  EXPECT_EQ(std::count(coarse.out.begin(), coarse.out.end(), '\n'), 1 + 4 * 51);
  std::filesystem::remove_all(dir);
}

TEST(MapCommand, WarningsAreToldAndStrictMakesThemErrors) {
  const auto dir = std::filesystem::temp_directory_path() / ("fleet_map_warn_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string file = write_long_roads(dir, 2, 20.0);
  const CommandRun loose = run({"sample", file, "--step", "10"});
  EXPECT_EQ(loose.code, kExitOk) << loose.err;
  EXPECT_NE(loose.err.find("warning: " + file + ":5: <successor> attribute 'elementId': road '99' does not exist"),
            std::string::npos)
      << loose.err;
  const CommandRun strict = run({"sample", file, "--step", "10", "--strict"});
  EXPECT_EQ(strict.code, kExitBadInput);
  EXPECT_NE(strict.err.find("error (--strict): " + file + ":5:"), std::string::npos) << strict.err;
  EXPECT_TRUE(strict.out.empty());
  std::filesystem::remove_all(dir);
}

TEST(MapCommand, CheckGivenARoadNetworkSaysItWantsASiteFile) {
  const CommandRun r = run({"check", fleet::test::source_path("/maps/table_a.xodr")});
  EXPECT_EQ(r.code, kExitBadInput);
  EXPECT_NE(r.err.find("is an OpenDRIVE road network; map check reads a site file"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("fleetctl map sample"), std::string::npos) << r.err;
}

TEST(MapCommand, AGridSiteIsReportedWithItsComponentsAndDeadEnds) {
  const auto dir = std::filesystem::temp_directory_path() / ("fleet_map_check_grid_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "room.map") << "type octile\nheight 3\nwidth 5\nmap\n.....\n.@.@.\n.....\n";
  std::ofstream(dir / "split.map") << "type octile\nheight 2\nwidth 4\nmap\n.@..\n.@.@\n";
  const CommandRun r = run({"check", (dir / "room.map").string(), (dir / "split.map").string()}, true);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("room.map: grid site, 3 x 5 cells, 13 free, 1 component"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("split.map: grid site, 2 x 4 cells, 5 free, 2 components (largest 3 cells), 4 dead ends"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("2 free cells cannot be reached from the largest component"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"kind\":\"grid\""), std::string::npos) << r.out;
  std::ofstream(dir / "bad.map") << "type octile\nheight 2\nwidth 2\nmap\n..\n";
  const CommandRun bad = run({"check", (dir / "bad.map").string()});
  EXPECT_EQ(bad.code, kExitBadInput);
  EXPECT_NE(bad.err.find("bad.map: has 1 rows of cells, its height says 2"), std::string::npos) << bad.err;
  std::filesystem::remove_all(dir);
}
