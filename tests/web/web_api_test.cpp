// The web view's JSON API against a real fleet-server and fleet-agent over DDS, through HTTP:
// every endpoint, its bad input and a missing or wrong token.

#include <gtest/gtest.h>
#include <httplib.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <functional>
#include <iterator>
#include <memory>
#include <nlohmann/json.hpp>
#include <thread>

#include "../integration/fleet_harness.hpp"
#include "test_paths.hpp"

using namespace fleet::testing;
using nlohmann::json;

namespace {

constexpr int kDomain = 190;
constexpr int kPort = 18190;  // unique to this test program
const std::string kToken = "api-test-token";
const std::string kViewerToken = "viewer-test-token";
const httplib::Headers kViewer{{"Authorization", "Bearer " + kViewerToken}};

json parse(const httplib::Result& r) {
  if (!r) return json();
  return json::parse(r->body, nullptr, false);
}

/// Waits (up to `timeout_s`) until `ready` holds for /api/state.
json wait_state(httplib::Client& http, const std::function<bool(const json&)>& ready, double timeout_s = 30.0) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  json state;
  while (std::chrono::steady_clock::now() < end) {
    if (auto r = http.Get("/api/state", kViewer); r && r->status == 200) {
      state = json::parse(r->body, nullptr, false);
      if (!state.is_discarded() && ready(state)) return state;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return state;
}

const json* robot_in(const json& state, const std::string& id) {
  for (const auto& r : state["robots"]) {
    if (r["id"] == id) return &r;
  }
  return nullptr;
}

const json* order_in(const json& state, std::int64_t id) {
  for (const auto& o : state["orders"]) {
    if (o["id"] == id) return &o;
  }
  return nullptr;
}

class WebApi : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    fleet_ = std::make_unique<FleetHarness>(kDomain, 10.0);
    fleet_->start_server({"--http-port", std::to_string(kPort), "--api-token", kToken, "--viewer-token", kViewerToken});
    fleet_->start_agent("fl1");
    httplib::Client http("127.0.0.1", kPort);
    const json state = wait_state(http, [](const json& s) { return robot_in(s, "fl1") != nullptr; });
    ready_ = robot_in(state, "fl1") != nullptr;
    ASSERT_TRUE(ready_) << state.dump() << fleet_->log_of("fleet-server");
  }
  static void TearDownTestSuite() { fleet_.reset(); }

  void SetUp() override {
    // A failed SetUpTestSuite would only skip the tests; make every test fail instead.
    ASSERT_TRUE(ready_) << "the server and agent of this suite did not come up";
    http_ = std::make_unique<httplib::Client>("127.0.0.1", kPort);
    http_->set_read_timeout(10, 0);
  }

  httplib::Result post(const std::string& path, const std::string& body, const std::string& token = kToken) {
    httplib::Headers headers;
    if (!token.empty()) headers.emplace("Authorization", "Bearer " + token);
    return http_->Post(path.c_str(), headers, body, "application/json");
  }
  httplib::Result del(const std::string& path, const std::string& token = kToken) {
    httplib::Headers headers;
    if (!token.empty()) headers.emplace("Authorization", "Bearer " + token);
    return http_->Delete(path.c_str(), headers);
  }

  static std::unique_ptr<FleetHarness> fleet_;
  static bool ready_;
  std::unique_ptr<httplib::Client> http_;
};

std::unique_ptr<FleetHarness> WebApi::fleet_;
bool WebApi::ready_ = false;

/// Expects a 4xx JSON error with this status whose message names `needle`.
void expect_error(const httplib::Result& r, int status, const std::string& needle, const std::string& field = "") {
  ASSERT_TRUE(r) << "no answer";
  EXPECT_EQ(r->status, status) << r->body;
  const json body = json::parse(r->body, nullptr, false);
  ASSERT_TRUE(body.is_object()) << r->body;
  ASSERT_TRUE(body.contains("error")) << r->body;
  EXPECT_NE(body["error"].get<std::string>().find(needle), std::string::npos) << r->body;
  if (!field.empty()) {
    EXPECT_EQ(body.value("field", ""), field) << r->body;
  }
  EXPECT_EQ(r->get_header_value("Content-Type"), "application/json");
}

}  // namespace

TEST_F(WebApi, ServesThePageAndItsFilesWithNothingFromElsewhere) {
  auto r = http_->Get("/");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
  EXPECT_NE(r->body.find("<canvas"), std::string::npos);
  EXPECT_EQ(r->body.find("http://"), std::string::npos) << "the page must not load anything from outside";
  EXPECT_EQ(r->body.find("https://"), std::string::npos);
  EXPECT_NE(r->get_header_value("Content-Security-Policy").find("default-src 'self'"), std::string::npos);
  // Each file whole, as it lies in server/web.
  for (const char* file : {"/app.js", "/robots.js", "/tables.js", "/shapes.js", "/text.js", "/style.css"}) {
    auto f = http_->Get(file);
    ASSERT_TRUE(f) << file;
    EXPECT_EQ(f->status, 200) << file;
    std::ifstream source(fleet::test::source_path(std::string("/server/web") + file), std::ios::binary);
    const std::string expected((std::istreambuf_iterator<char>(source)), std::istreambuf_iterator<char>());
    EXPECT_GT(expected.size(), 500u) << file;
    EXPECT_EQ(f->body, expected) << file;
  }
  expect_error(http_->Get("/nothing.js"), 404, "no such");
  expect_error(http_->Get("/api/nothing"), 404, "no such");
}

TEST_F(WebApi, SiteHasRoadsGraphAreasObstaclesAnchorsAndHomes) {
  const json site = parse(http_->Get("/api/site", kViewer));
  ASSERT_TRUE(site.is_object());
  EXPECT_EQ(site["site"], "table_a");
  EXPECT_DOUBLE_EQ(site["road_width"].get<double>(), 0.30);
  ASSERT_FALSE(site["lanes"].empty());
  EXPECT_GE(site["lanes"][0]["outline"].size(), 4u);
  EXPECT_FALSE(site["references"].empty());
  EXPECT_FALSE(site["graph"]["points"].empty());
  EXPECT_FALSE(site["graph"]["edges"].empty());
  EXPECT_EQ(site["areas"].size(), 8u);
  EXPECT_EQ(site["obstacles"].size(), 4u);
  EXPECT_GE(site["obstacles"][0]["polygon"].size(), 3u);
  EXPECT_FALSE(site["anchors"].empty());
  EXPECT_FALSE(site["homes"].empty());
  EXPECT_EQ(site["robots"][0]["id"], "fl1");
  EXPECT_NE(std::find(site["maps"].begin(), site["maps"].end(), "table_a"), site["maps"].end());
}

TEST_F(WebApi, StateListsTheRobotWithItsPoseAndHealth) {
  const json state = wait_state(*http_, [](const json& s) {
    const json* r = robot_in(s, "fl1");
    return r && (*r)["health"] == "alive";
  });
  const json* fl1 = robot_in(state, "fl1");
  ASSERT_NE(fl1, nullptr) << state.dump();
  EXPECT_TRUE((*fl1)["x"].is_number());
  EXPECT_TRUE((*fl1)["y"].is_number());
  EXPECT_TRUE((*fl1)["yaw"].is_number());
  EXPECT_EQ((*fl1)["fleet"], "forklifts");
  EXPECT_FALSE(fl1->contains("dock_targets")) << "a forklift shows no docking";
  EXPECT_FALSE(fl1->contains("detected_pallet"));
  EXPECT_EQ(state["obstacles"].size(), 4u);
  EXPECT_EQ(state["pallets"].size(), 8u);
}

TEST_F(WebApi, MutatingCallsNeedTheRightToken) {
  expect_error(post("/api/auto-orders", R"({"enabled": false})", ""), 401, "token", "token");
  expect_error(post("/api/auto-orders", R"({"enabled": false})", "wrong"), 403, "token", "token");
  expect_error(post("/api/orders", R"({"from": "A1", "to": "A2"})", ""), 401, "token");
  expect_error(del("/api/orders/1", ""), 401, "token");
  expect_error(post("/api/obstacles/O1", R"({"enabled": true})", ""), 401, "token");
  expect_error(post("/api/map", R"({"map": "table_a"})", ""), 401, "token");
  expect_error(post("/api/robots/fl1/pause", "", ""), 401, "token");
  // The page's way: ?token= in the query.
  auto r = http_->Post(("/api/auto-orders?token=" + kToken).c_str(), R"({"enabled": false})", "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200) << r->body;
}

TEST_F(WebApi, TheViewerReadsButChangesNothingAndStrangersReadNothing) {
  for (const char* path : {"/api/site", "/api/state", "/api/fleets"}) {
    expect_error(http_->Get(path), 401, "missing", "token");
    expect_error(http_->Get(path, {{"Authorization", "Bearer guess"}}), 403, "wrong token", "token");
    auto viewer = http_->Get(path, kViewer);
    ASSERT_TRUE(viewer);
    EXPECT_EQ(viewer->status, 200) << path;
    auto op = http_->Get(path, {{"Authorization", "Bearer " + kToken}});
    ASSERT_TRUE(op);
    EXPECT_EQ(op->status, 200) << path << ": the operator may read too";
  }
  // The page's event stream sends the token in the query.
  expect_error(http_->Get("/api/stream"), 401, "missing", "token");
  expect_error(post("/api/auto-orders", R"({"enabled": false})", kViewerToken), 403,
               "the viewer's token does not allow POST /api/auto-orders", "token");
  expect_error(del("/api/orders/1", kViewerToken), 403, "the operator's does", "token");
}

TEST_F(WebApi, EachFailedAuthenticationInARowWaitsLonger) {
  const auto timed = [&] {
    const auto start = std::chrono::steady_clock::now();
    expect_error(http_->Get("/api/state", {{"Authorization", "Bearer guess"}}), 403, "wrong token", "token");
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  const auto failures = [&] { return parse(http_->Get("/api/state", kViewer))["failed_authentications"].get<int>(); };
  const int before = failures();  // a success clears the address
  const double first = timed();
  const double second = timed();
  const double third = timed();
  EXPECT_GE(first, 0.1);
  EXPECT_GE(second, 0.2);
  EXPECT_GE(third, 0.4);
  EXPECT_EQ(failures(), before + 3);
}

TEST_F(WebApi, NoCorsHeadersForOtherOrigins) {
  httplib::Headers headers{{"Origin", "http://evil.example"}, {"Authorization", "Bearer " + kViewerToken}};
  auto r = http_->Get("/api/state", headers);
  ASSERT_TRUE(r);
  EXPECT_FALSE(r->has_header("Access-Control-Allow-Origin"));
  auto o = http_->Options("/api/orders", headers);
  ASSERT_TRUE(o);
  EXPECT_FALSE(o->has_header("Access-Control-Allow-Origin"));
}

TEST_F(WebApi, OrderBadInputNamesTheField) {
  expect_error(post("/api/orders", "not json"), 400, "body", "body");
  expect_error(post("/api/orders", R"({"to": "A2"})"), 400, "missing", "from");
  expect_error(post("/api/orders", R"({"from": 3, "to": "A2"})"), 400, "string", "from");
  expect_error(post("/api/orders", R"({"from": "NOPE", "to": "A2"})"), 400, "'NOPE'", "from");
  expect_error(post("/api/orders", R"({"from": "A1", "to": "ZZ"})"), 400, "'ZZ'", "to");
  expect_error(post("/api/orders", R"({"from": "A1", "to": "A2", "robot": "fl99"})"), 400, "'fl99'", "robot");
  expect_error(post("/api/orders", R"({"from": "A1", "to": "A2", "fleet": "boats"})"), 400, "'boats'", "fleet");
  expect_error(post("/api/orders", R"({"from": "A1", "to": "A2", "priority": "high"})"), 400, "integer", "priority");
  // A pick list: read before anything else; table_a has no fleet that picks items.
  expect_error(post("/api/orders", R"({"from": "A1", "to": "A2", "lines": "A1,X,1"})"), 400, "kind pick", "lines");
  expect_error(post("/api/orders", R"({"kind": "pick", "to": "A2", "lines": "A1,X"})"), 400,
               "lines:1: expected place,item,quantity", "lines");
  expect_error(post("/api/orders", R"({"kind": "pick", "to": "A2", "lines": "A1,X,1"})"), 400, "pickItem", "kind");
  // Valid names the server refuses (the same check as fleetctl's): A3 holds a pallet already.
  expect_error(post("/api/orders", R"({"from": "A1", "to": "A3"})"), 409, "A3");
}

TEST_F(WebApi, OrderIsCreatedAndCancelled) {
  // A5 -> A6 (A5 holds a pallet at the start, A6 is free); queued behind nothing, but cancelled
  // at once, before the robot gets far.
  auto r = post("/api/orders", R"({"from": "A5", "to": "A6"})");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 201) << r->body;
  const std::int64_t id = parse(r)["order_id"].get<std::int64_t>();
  EXPECT_GT(id, 0);
  const json seen = wait_state(*http_, [&](const json& s) { return order_in(s, id) != nullptr; });
  ASSERT_NE(order_in(seen, id), nullptr) << seen.dump();
  EXPECT_EQ((*order_in(seen, id))["from"], "A5");

  auto c = del("/api/orders/" + std::to_string(id));
  ASSERT_TRUE(c);
  EXPECT_EQ(c->status, 200) << c->body;
  const json after = wait_state(*http_, [&](const json& s) {
    const json* o = order_in(s, id);
    return o && (*o)["state"] == "CANCELLED";
  });
  ASSERT_NE(order_in(after, id), nullptr);
  EXPECT_EQ((*order_in(after, id))["state"], "CANCELLED");
  expect_error(del("/api/orders/" + std::to_string(id)), 409, "CANCELLED");
}

TEST_F(WebApi, CancelBadInput) {
  expect_error(del("/api/orders/abc"), 400, "'abc'", "id");
  expect_error(del("/api/orders/987654"), 404, "987654");
}

TEST_F(WebApi, ObstacleIsSwitchedAndBadInputIsNamed) {
  expect_error(post("/api/obstacles/O9", R"({"enabled": true})"), 404, "'O9'", "id");
  expect_error(post("/api/obstacles/O1", "{}"), 400, "missing", "enabled");
  expect_error(post("/api/obstacles/O1", R"({"enabled": "yes"})"), 400, "true or false", "enabled");
  auto r = post("/api/obstacles/O1", R"({"enabled": true})");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200) << r->body;
  json state = wait_state(*http_, [](const json& s) { return s["obstacles"]["O1"] == true; });
  EXPECT_EQ(state["obstacles"]["O1"], true) << state.dump();
  r = post("/api/obstacles/O1", R"({"enabled": false})");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200) << r->body;
  state = wait_state(*http_, [](const json& s) { return s["obstacles"]["O1"] == false; });
  EXPECT_EQ(state["obstacles"]["O1"], false);
  // The agent heard it over DDS.
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (fleet_->log_of("fleet-agent-fl1").find("static obstacle O1 enabled") == std::string::npos &&
         std::chrono::steady_clock::now() < end) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  EXPECT_NE(fleet_->log_of("fleet-agent-fl1").find("static obstacle O1 enabled"), std::string::npos);
}

TEST_F(WebApi, MapRequestIsValidatedAndForwarded) {
  expect_error(post("/api/map", "{}"), 400, "missing", "map");
  expect_error(post("/api/map", R"({"map": "atlantis"})"), 400, "'atlantis'", "map");
  expect_error(post("/api/map", R"({"map": "table_a", "robot": "fl99"})"), 400, "'fl99'", "robot");
  // A valid request reaches the server loop, which answers it: accepted, or refused with a reason.
  auto r = post("/api/map", R"({"map": "table_a", "robot": "fl1"})");
  ASSERT_TRUE(r);
  const json body = parse(r);
  if (r->status == 200) {
    EXPECT_EQ(body["accepted"], true) << r->body;
  } else {
    EXPECT_EQ(r->status, 409) << r->body;
    EXPECT_FALSE(body.value("error", "").empty()) << r->body;
  }
}

TEST_F(WebApi, RobotIsPausedAndResumed) {
  expect_error(post("/api/robots/fl99/pause", ""), 404, "'fl99'", "id");
  auto r = post("/api/robots/fl1/pause", "");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200) << r->body;
  json state = wait_state(*http_, [](const json& s) {
    const json* fl1 = robot_in(s, "fl1");
    return fl1 && (*fl1)["state"] == "PAUSED";
  });
  ASSERT_NE(robot_in(state, "fl1"), nullptr);
  EXPECT_EQ((*robot_in(state, "fl1"))["state"], "PAUSED") << state.dump();
  r = post("/api/robots/fl1/resume", "");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200) << r->body;
  state = wait_state(*http_, [](const json& s) {
    const json* fl1 = robot_in(s, "fl1");
    return fl1 && (*fl1)["state"] != "PAUSED";
  });
  EXPECT_NE((*robot_in(state, "fl1"))["state"], "PAUSED");
}

TEST_F(WebApi, AutoOrdersSwitchAndBadInput) {
  expect_error(post("/api/auto-orders", "[]"), 400, "JSON object", "body");
  expect_error(post("/api/auto-orders", R"({"enabled": 1})"), 400, "true or false", "enabled");
  auto r = post("/api/auto-orders", R"({"enabled": true})");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200) << r->body;
  json state = wait_state(*http_, [](const json& s) { return s["auto_orders"] == true; });
  EXPECT_EQ(state["auto_orders"], true);
  r = post("/api/auto-orders", R"({"enabled": false})");
  ASSERT_TRUE(r);
  state = wait_state(*http_, [](const json& s) { return s["auto_orders"] == false; });
  EXPECT_EQ(state["auto_orders"], false);
}

TEST_F(WebApi, StreamStartsWithAFullFrameThenSendsDiffs) {
  std::string text;
  int events = 0;
  auto r = http_->Get("/api/stream", kViewer, [&](const char* data, std::size_t length) {
    text.append(data, length);
    events = 0;
    for (std::size_t at = text.find("\n\n"); at != std::string::npos; at = text.find("\n\n", at + 2)) ++events;
    return events < 4;
  });
  ASSERT_GE(events, 4) << text;
  ASSERT_EQ(text.rfind("event: full\n", 0), 0u) << text.substr(0, 200);
  const auto data_at = text.find("data: ");
  const json full = json::parse(text.substr(data_at + 6, text.find('\n', data_at) - data_at - 6), nullptr, false);
  ASSERT_TRUE(full.is_object());
  // The first full frame may be built from a snapshot taken just before fl1 registered; fl1 is
  // then in one of the diffs after it.
  EXPECT_TRUE(full["robots"].contains("fl1") || text.find("\"fl1\"", data_at + 6) != std::string::npos) << text;
  EXPECT_TRUE(full["globals"].contains("sim_time"));
  EXPECT_NE(text.find("event: diff\n"), std::string::npos) << text;
}

// A stacker on the plant: the site gives its fork tines, and while it docks its robot carries
// the docking's two targets and the pallet its cameras detect; absent again once it is docked.
TEST(WebApiStacker, ADockingStackerShowsItsTargetsAndTheDetectedPallet) {
  constexpr int kStackerDomain = 192;
  constexpr int kStackerPort = 18192;
  FleetHarness fleet(kStackerDomain, 5.0, "plant");
  fleet.use_config(fleet::test::source_dir() + "/config/sites/plant.yaml");
  fleet.start_server(
      {"--http-port", std::to_string(kStackerPort), "--api-token", kToken, "--viewer-token", kViewerToken});
  fleet.start_agent("st2");
  httplib::Client http("127.0.0.1", kStackerPort);
  http.set_read_timeout(10, 0);
  const auto st2_in = [](const json& s) { return robot_in(s, "st2"); };
  json state = wait_state(http, [&](const json& s) { return st2_in(s) && (*st2_in(s))["health"] == "alive"; });
  ASSERT_NE(st2_in(state), nullptr) << state.dump() << fleet.log_of("fleet-server");
  EXPECT_FALSE(st2_in(state)->contains("dock_targets")) << "parked in its bay";

  // The site: the stackers' tines run from the footprint's back end (x -0.85) to the chassis.
  const json site = parse(http.Get("/api/site", kViewer));
  json fg5;
  for (const auto& a : site["areas"]) {
    if (a["id"] == "FG5") fg5 = a;
  }
  ASSERT_FALSE(fg5.is_null()) << "no area FG5 on the plant";
  for (const auto& spec : site["robots"]) {
    if (spec["type"] != "stacker") {
      EXPECT_FALSE(spec.contains("forks")) << spec.dump();
      continue;
    }
    ASSERT_EQ(spec["forks"].size(), 2u) << spec.dump();
    for (const auto& tine : spec["forks"]) {
      ASSERT_EQ(tine.size(), 4u) << spec.dump();
      double back = 1e9, front = -1e9;
      for (const auto& p : tine) {
        back = std::min(back, p[0].get<double>());
        front = std::max(front, p[0].get<double>());
      }
      EXPECT_NEAR(back, -0.85, 1e-3) << spec.dump();
      EXPECT_NEAR(front, 0.30, 1e-3) << spec.dump();
    }
  }

  httplib::Headers auth{{"Authorization", "Bearer " + kToken}};
  auto r = http.Post("/api/orders", auth, R"({"from": "FG5", "to": "EX3", "robot": "st2"})", "application/json");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 201) << r->body;
  state = wait_state(
      http,
      [&](const json& s) {
        const json* st2 = st2_in(s);
        return st2 && st2->contains("dock_targets") && st2->contains("detected_pallet");
      },
      150.0);
  const json* st2 = st2_in(state);
  ASSERT_TRUE(st2 && st2->contains("detected_pallet")) << state.dump() << fleet.log_of("fleet-agent-st2");
  EXPECT_EQ((*st2)["state"], "DOCKING");
  EXPECT_EQ((*st2)["dock_targets"].size(), 2u);
  const json& seen = (*st2)["detected_pallet"];
  ASSERT_EQ(seen.size(), 3u);
  const double off =
      std::hypot(seen[0].get<double>() - fg5["x"].get<double>(), seen[1].get<double>() - fg5["y"].get<double>());
  EXPECT_LT(off, 0.15) << "the detected pallet is not FG5's: " << seen.dump() << " vs " << fg5.dump();

  // Docked, it lifts and drives on: nothing of the docking is left.
  state = wait_state(
      http,
      [&](const json& s) {
        const json* now = st2_in(s);
        return now && ((*now)["state"] == "LIFTING" || (*now)["state"] == "TO_DROP");
      },
      120.0);
  st2 = st2_in(state);
  ASSERT_TRUE(st2 && ((*st2)["state"] == "LIFTING" || (*st2)["state"] == "TO_DROP")) << state.dump();
  EXPECT_FALSE(st2->contains("dock_targets")) << st2->dump();
  EXPECT_FALSE(st2->contains("detected_pallet")) << st2->dump();
}
