// The web API's JSON input, fuzzed against a real fleet-server: bodies broken byte by byte and
// field by field (wrong types, unknown and missing fields, long strings, deep nesting, cut
// text) are each answered with a status the API documents, a 400 naming the field or the body,
// and the server keeps serving. Seeded and bounded in requests and time (ctest -L security).

#include <gtest/gtest.h>
#include <httplib.h>

#include <chrono>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "../integration/fleet_harness.hpp"

using namespace fleet::testing;
using nlohmann::json;

namespace {

constexpr int kDomain = 193;
constexpr int kPort = 18193;  // unique to this test program
const std::string kToken = "fuzz-operator";
constexpr int kRequests = 5000;
constexpr double kLongestSeconds = 30.0;

struct Endpoint {
  std::string method;
  std::string path;
  json seed;  ///< a body that parses but that the server refuses, so that no mutation changes the fleet much
};

/// A value of a random JSON type, sometimes large.
json random_value(std::mt19937& rng) {
  switch (std::uniform_int_distribution<int>(0, 9)(rng)) {
    case 0:
      return nullptr;
    case 1:
      return std::uniform_int_distribution<int>(0, 1)(rng) == 1;
    case 2:
      return std::uniform_int_distribution<std::int64_t>(INT64_MIN, INT64_MAX)(rng);
    case 3:
      return std::uniform_real_distribution<double>(-1e308, 1e308)(rng);
    case 4:
      return std::string(std::uniform_int_distribution<std::size_t>(0, 70000)(rng), 'A');
    case 5:
      return json::array({1, "two", nullptr});
    case 6:
      return json::object({{"nested", json::object({{"deeper", 1}})}});
    case 7:
      return std::string("A1\n\t\"\\\u00e9\xff");  // control characters, an escape, invalid UTF-8
    case 8:
      return "";
    default: {
      std::string area = "A";
      area += std::to_string(std::uniform_int_distribution<int>(0, 99)(rng));
      return area;
    }
  }
}

/// One mutation of `seed`, as the text sent.
std::string mutate(const json& seed, std::mt19937& rng) {
  json body = seed;
  std::string text;
  const int kind = std::uniform_int_distribution<int>(0, 7)(rng);
  if (kind <= 2 && !body.empty()) {
    // A field's value of another type.
    auto it = body.begin();
    std::advance(it, std::uniform_int_distribution<std::size_t>(0, body.size() - 1)(rng));
    *it = random_value(rng);
    text = body.dump(-1, ' ', false, json::error_handler_t::replace);
  } else if (kind == 3) {
    body[std::string(std::uniform_int_distribution<std::size_t>(1, 300)(rng), 'x')] = random_value(rng);
    text = body.dump(-1, ' ', false, json::error_handler_t::replace);
  } else if (kind == 4 && !body.empty()) {
    body.erase(body.begin());
    text = body.dump();
  } else if (kind == 5) {
    // Deep nesting, or another top-level type.
    const std::size_t depth = std::uniform_int_distribution<std::size_t>(1, 20000)(rng);
    text = std::string(depth, '[') + std::string(depth, ']');
  } else {
    // Bytes: cut, flipped or inserted.
    text = seed.dump();
    const int edits = std::uniform_int_distribution<int>(1, 4)(rng);
    for (int e = 0; e < edits && !text.empty(); ++e) {
      const std::size_t at = std::uniform_int_distribution<std::size_t>(0, text.size() - 1)(rng);
      switch (std::uniform_int_distribution<int>(0, 2)(rng)) {
        case 0:
          text.resize(at);
          break;
        case 1:
          text[at] = static_cast<char>(std::uniform_int_distribution<int>(0, 255)(rng));
          break;
        default:
          text.insert(at, 1, "{}[]\",:\\0e-"[std::uniform_int_distribution<int>(0, 11)(rng)]);
      }
    }
  }
  return text;
}

}  // namespace

TEST(WebApiFuzz, BrokenBodiesAreAnsweredWithTheFieldNamedAndTheServerKeepsServing) {
  FleetHarness fleet(kDomain, 10.0);
  fleet.start_server({"--http-port", std::to_string(kPort), "--api-token", kToken, "--viewer-token", "fuzz-viewer"});
  httplib::Client http("127.0.0.1", kPort);
  http.set_read_timeout(10, 0);
  const httplib::Headers auth{{"Authorization", "Bearer " + kToken}};
  // Up once the server's loop has published its first snapshot (the pallets of the site): the web
  // view answers before that, and refuses orders until it knows the site's names.
  bool up = false;
  for (int i = 0; i < 100 && !up; ++i) {
    auto r = http.Get("/api/state", auth);
    up = r && r->status == 200 && !json::parse(r->body, nullptr, false).value("pallets", json::object()).empty();
    if (!up) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ASSERT_TRUE(up) << fleet.log_of("fleet-server");

  const std::vector<Endpoint> endpoints{
      {"POST", "/api/orders", {{"from", "A1"}, {"to", "A1"}, {"priority", 5}, {"fleet", "forklifts"}}},
      {"POST", "/api/orders", {{"kind", "pick"}, {"to", "A1"}, {"lines", "nowhere,box,1\n"}}},
      {"POST", "/api/map", {{"map", "no_such_map"}, {"robot", "fl1"}}},
      {"POST", "/api/obstacles/NO_SUCH_OBSTACLE", {{"enabled", true}}},
      {"POST", "/api/robots/no_such_robot/pause", json::object()},
  };
  const std::set<int> documented{200, 201, 400, 404, 409, 413};
  std::mt19937 rng(20261206);
  const auto start = std::chrono::steady_clock::now();
  int sent = 0, refused_400 = 0;
  for (; sent < kRequests; ++sent) {
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > kLongestSeconds) break;
    const Endpoint& endpoint = endpoints[static_cast<std::size_t>(sent) % endpoints.size()];
    const std::string body = mutate(endpoint.seed, rng);
    auto r = http.Post(endpoint.path, auth, body, "application/json");
    ASSERT_TRUE(r) << "no answer to " << endpoint.path << " with " << body.substr(0, 200) << "\n"
                   << fleet.log_of("fleet-server");
    ASSERT_TRUE(documented.count(r->status))
        << r->status << " for " << endpoint.path << " with " << body.substr(0, 200) << ": " << r->body.substr(0, 300);
    const json answer = json::parse(r->body, nullptr, false);
    ASSERT_TRUE(answer.is_object()) << r->body.substr(0, 300);
    if (r->status == 400) {
      ++refused_400;
      EXPECT_FALSE(answer.value("field", "").empty())
          << "a 400 names the field or the body: " << r->body.substr(0, 300);
      EXPECT_LT(r->body.size(), 2000u) << "an error quotes what it refuses briefly: " << r->body.substr(0, 400);
    }
  }
  EXPECT_GE(sent, 500) << "too few requests within " << kLongestSeconds << " s to call it fuzzed";
  EXPECT_GT(refused_400, sent / 2);
  auto alive = http.Get("/api/state", auth);
  ASSERT_TRUE(alive);
  EXPECT_EQ(alive->status, 200);
  std::cout << "fuzzed the API with " << sent << " bodies, " << refused_400 << " answered 400\n";
}
