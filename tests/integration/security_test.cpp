// DDS Security end to end: real fleet-server, fleet-agent and fleetctl processes, each with its own
// credentials from a folder made by `fleetctl security init`, and processes without them or with
// credentials of another authority or another role.

#include "dds/security.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <thread>

#include "common/clock.hpp"
#include "dds/topics.hpp"
#include "fleet_harness.hpp"
#include "model/messages.hpp"

using namespace fleet::testing;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

/// A security folder for the default configuration's robots, made by fleetctl, removed at the end.
class Credentials {
 public:
  explicit Credentials(const std::string& name)
      : dir_((fs::temp_directory_path() / ("fleet-security-" + std::to_string(::getpid()) + "-" + name)).string()) {
    fs::remove_all(dir_);
    const auto r = run_command({bin("fleetctl"), "security", "init", dir_, "--days", "2", "--json"}, 60);
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  }
  ~Credentials() { fs::remove_all(dir_); }
  const std::string& dir() const { return dir_; }

 private:
  std::string dir_;
};

/// The robots a secured fleetctl sees, once `robot` is among them or `timeout_s` has passed.
json robots_seen(const FleetHarness& fleet, const std::string& security, const std::string& robot, double timeout_s) {
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  json robots = json::array();
  while (std::chrono::steady_clock::now() < give_up) {
    const auto r = fleet.fleetctl({"--security", security, "robots", "--json"}, 30);
    if (r.exit_code == 0) {
      robots = last_json_line(r.out);
      for (const auto& seen : robots) {
        if (seen["robot_id"] == robot) return robots;
      }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
  }
  return robots;
}

/// Writes RobotStates naming each of `names` at 20 Hz for `seconds` from one writer in `partition`
/// (empty: the default one), each at `x`, `y`.
void write_states(int domain, const std::string& partition, const std::vector<std::string>& names, double x, double y,
                  double seconds) {
  fleet::dds::Participant participant(static_cast<std::uint32_t>(domain));
  fleet::dds::Writer<fleet::model::RobotState> writer =
      partition.empty()
          ? fleet::dds::Writer<fleet::model::RobotState>(participant, fleet::dds::qos::robot_state())
          : fleet::dds::Writer<fleet::model::RobotState>(participant, fleet::dds::qos::robot_state(), partition);
  const fleet::SimClock clock(10.0);
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    for (const std::string& name : names) {
      fleet::model::RobotState state;
      state.robot_id = name;
      state.pose = {x, y, 0.0};
      state.task_state = "IDLE";
      state.sim_time = clock.now();
      writer.write(state);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
}

int lines_with(const std::string& text, const std::string& needle) {
  int count = 0;
  for (std::size_t at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1)) ++count;
  return count;
}

bool lists(const json& robots, const std::string& id) {
  for (const auto& r : robots) {
    if (r["robot_id"] == id) return true;
  }
  return false;
}

}  // namespace

TEST(Security, ASecuredFleetDoesItsOrderAndAStrangerWithoutCredentialsFindsNoServer) {
  const Credentials credentials("fleet");
  FleetHarness fleet(131, 10.0);
  fleet.start_server({"--security", credentials.dir()});
  fleet.start_agent("fl1", {"--security", credentials.dir()});
  ASSERT_TRUE(lists(robots_seen(fleet, credentials.dir(), "fl1", 40), "fl1"))
      << fleet.log_of("fleet-server") << fleet.log_of("fleet-agent-fl1");

  // Without credentials: no server to be found, so no order placed (exit 3).
  const auto stranger = fleet.fleetctl({"--timeout", "3", "order", "add", "--from", "A1", "--to", "A2"}, 30);
  EXPECT_EQ(stranger.exit_code, 3) << stranger.out << stranger.err;

  const auto r = fleet.fleetctl(
      {"--security", credentials.dir(), "order", "add", "--from", "A1", "--to", "A2", "--wait", "--json"}, 120);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err << fleet.log_of("fleet-server");
  EXPECT_EQ(last_json_line(r.out)["state"], "DONE");
  const auto list = fleet.fleetctl({"--security", credentials.dir(), "order", "list", "--json"}, 30);
  ASSERT_EQ(list.exit_code, 0) << list.err;
  EXPECT_EQ(last_json_line(list.out).size(), 1u) << list.out;
}

TEST(Security, ARobotsCredentialsCannotPlaceOrdersAndAnotherAuthoritysRobotIsNotHeard) {
  const Credentials credentials("roles");
  const Credentials foreign("foreign");
  // A folder whose operator is robot fl1: its certificate and permissions under the operator's name.
  const std::string as_robot = credentials.dir() + "-as-robot";
  fs::remove_all(as_robot);
  fs::copy(credentials.dir(), as_robot, fs::copy_options::recursive);
  fs::remove_all(as_robot + "/identities/operator");
  fs::copy(credentials.dir() + "/identities/fl1", as_robot + "/identities/operator", fs::copy_options::recursive);

  FleetHarness fleet(132, 10.0);
  fleet.start_server({"--security", credentials.dir()});
  fleet.start_agent("fl1", {"--security", credentials.dir()});
  fleet.start_agent("fl2", {"--security", foreign.dir()});
  const json robots = robots_seen(fleet, credentials.dir(), "fl1", 40);
  ASSERT_TRUE(lists(robots, "fl1")) << fleet.log_of("fleet-server");
  // fl2 presents a certificate of another authority: the server's participant refuses it.
  std::this_thread::sleep_for(std::chrono::seconds(3));
  EXPECT_FALSE(lists(robots_seen(fleet, credentials.dir(), "fl2", 2), "fl2")) << fleet.log_of("fleet-agent-fl2");

  const auto r = fleet.fleetctl({"--security", as_robot, "order", "add", "--from", "A1", "--to", "A2"}, 30);
  EXPECT_NE(r.exit_code, 0) << r.out;
  EXPECT_NE(r.err.find("security"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(as_robot + "/identities/operator/permissions.p7s"), std::string::npos) << r.err;
  const auto list = fleet.fleetctl({"--security", credentials.dir(), "order", "list", "--json"}, 30);
  ASSERT_EQ(list.exit_code, 0) << list.err;
  EXPECT_TRUE(last_json_line(list.out).empty()) << list.out;
  fs::remove_all(as_robot);
}

TEST(Security, AProcessWithAMissingOrForeignFileStopsAtStartNamingIt) {
  const Credentials credentials("broken");
  const Credentials foreign("broken-foreign");
  fs::remove(credentials.dir() + "/identities/fl1/key.pem");
  const auto agent =
      run_command({bin("fleet-agent"), "--id", "fl1", "--domain", "133", "--security", credentials.dir()}, 30);
  EXPECT_EQ(agent.exit_code, 2) << agent.err;
  EXPECT_NE(agent.err.find(credentials.dir() + "/identities/fl1/key.pem: missing"), std::string::npos) << agent.err;

  fs::copy_file(foreign.dir() + "/identities/server/certificate.pem",
                credentials.dir() + "/identities/server/certificate.pem", fs::copy_options::overwrite_existing);
  const auto server = run_command({bin("fleet-server"), "--domain", "133", "--http-port", "0", "--db",
                                   credentials.dir() + "/fleet.db", "--security", credentials.dir()},
                                  30);
  EXPECT_EQ(server.exit_code, 2) << server.err;
  EXPECT_NE(server.err.find("certificate.pem: not issued by the identity authority"), std::string::npos) << server.err;
}

TEST(Security, ARobotWritingInAnotherRobotsNameIsRefusedAndCounted) {
  const Credentials credentials("impostor");
  FleetHarness fleet(134, 10.0);
  fleet.start_server({"--security", credentials.dir()});
  fleet.start_agent("fl1", {"--security", credentials.dir()});
  ASSERT_TRUE(lists(robots_seen(fleet, credentials.dir(), "fl1", 40), "fl1")) << fleet.log_of("fleet-server");
  // This process presents fl2's credentials and writes in fl2's own partition, naming fl1 at a
  // pose fl1 is not at; a robot's permissions let it write nowhere else.
  fleet::dds::use_security(credentials.dir(), "fl2");
  write_states(134, fleet::model::robot_partition("fl2"), {"fl1"}, 0.77, 0.33, 3.0);
  fleet::dds::use_security("", "");
  const auto stats = fleet.fleetctl({"--security", credentials.dir(), "stats", "--json"}, 30);
  ASSERT_EQ(stats.exit_code, 0) << stats.err;
  const json figures = last_json_line(stats.out);
  EXPECT_GT(figures["refused_samples"].get<long>(), 20) << stats.out;
  ASSERT_EQ(figures["refused_senders"].size(), 1u) << stats.out;
  EXPECT_NE(figures["refused_senders"][0].get<std::string>().find("naming 'fl1'"), std::string::npos) << stats.out;
  EXPECT_EQ(lines_with(fleet.log_of("fleet-server"), "refused fleet/RobotState"), 1) << fleet.log_of("fleet-server");
  for (const auto& robot : robots_seen(fleet, credentials.dir(), "fl1", 10)) {
    if (robot["robot_id"] == "fl1") {
      EXPECT_GT(std::hypot(robot["x"].get<double>() - 0.77, robot["y"].get<double>() - 0.33), 0.05);
    }
  }
}

TEST(Security, AWriterOfPosesThatAreNotNumbersGivesAFewLinesAMinute) {
  FleetHarness fleet(135, 10.0);
  fleet.start_server();
  fleet.start_agent("fl1");
  ASSERT_TRUE(fleet.wait_for_robots({"fl1"}));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  // 20 s at 20 Hz, in a live robot's name and a ghost's, from the default partition.
  std::thread writer([&] { write_states(135, "", {"fl1", "ghost"}, nan, 1e308, 20.0); });
  writer.join();
  const std::string log = fleet.log_of("fleet-server");
  const int pose_lines = lines_with(log, "non-finite pose");
  EXPECT_GE(pose_lines, 1);
  EXPECT_LE(pose_lines, 3) << log;  // the first, then one every ten seconds
  const auto robots = fleet.fleetctl({"robots", "--json"}, 30);
  EXPECT_EQ(robots.exit_code, 0) << robots.err;
  EXPECT_FALSE(lists(last_json_line(robots.out), "ghost"));
}
