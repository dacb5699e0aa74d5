#pragma once
// tests/vda5050/check_messages.js beside a test's fleet: every VDA 5050 message of the topics
// named checked against vda-5050-lib's validators, the official schemas of ../shared/data/vda5050
// (when present) and, for orders, the order rules.

#include <signal.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "fleet_harness.hpp"
#include "test_paths.hpp"

namespace fleet::testing {

/// Starts the check on the broker at `mqtt_url` (mqtt://HOST:PORT) for `topics` (comma-separated
/// last topic parts) and waits a second for it to subscribe; its process index.
inline std::size_t start_message_check(FleetHarness& fleet, const std::string& mqtt_url,
                                       const std::string& topics = "order,instantActions") {
  std::vector<std::string> argv{
      "node", fleet::test::source_dir() + "/tests/vda5050/check_messages.js", "--broker", mqtt_url, "--topics", topics};
  const std::string schemas = fleet::test::source_dir() + "/../shared/data/vda5050";
  if (std::filesystem::exists(schemas)) argv.insert(argv.end(), {"--schemas", schemas});
  argv.insert(argv.end(), {"--out", fleet.log_dir() + "/message-check.json"});
  const std::size_t index = fleet.processes().start("message check", argv, fleet.log_dir() + "/message-check.log");
  std::this_thread::sleep_for(std::chrono::seconds(1));
  return index;
}

/// Stops the check and gives its summary, an empty object when it wrote none.
inline nlohmann::json message_check_result(FleetHarness& fleet, std::size_t index) {
  fleet.processes().signal(index, SIGTERM);
  const std::string out = fleet.log_dir() + "/message-check.json";
  for (int i = 0; i < 100 && !std::filesystem::exists(out); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  std::ifstream in(out);
  const nlohmann::json result = nlohmann::json::parse(in, nullptr, false);
  return result.is_object() ? result : nlohmann::json::object();
}

/// mqtt://HOST:PORT of a broker at tcp://HOST:PORT.
inline std::string mqtt_url_of(const std::string& broker) {
  return "mqtt://" + broker.substr(broker.find("://") + 3);
}

}  // namespace fleet::testing
