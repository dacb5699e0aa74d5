// The competition's output file, in the order and shape the 2023 Start-Kit's saveResults writes.

#include <nlohmann/json.hpp>

#include "coordination/lifelong_run.hpp"

namespace fleet::coordination {

std::string lorr_output_json(const LorrInstance& instance, const LifelongResult& result) {
  using Json = nlohmann::ordered_json;
  const GridMap& map = instance.map;
  const int team = static_cast<int>(instance.starts.size());
  Json doc;
  doc["actionModel"] = "MAPF_T";
  doc["AllValid"] = result.errors.empty() ? "Yes" : "No";
  doc["teamSize"] = team;
  Json start = Json::array();
  for (int cell : instance.starts) start.push_back(Json::array({cell / map.cols, cell % map.cols, "E"}));
  doc["start"] = start;
  doc["numTaskFinished"] = result.finished;
  // Every robot always has an errand under round robin, so each step costs each robot one.
  doc["sumOfCost"] = static_cast<long>(result.steps) * team;
  doc["makespan"] = result.steps;
  Json paths = Json::array();
  for (const std::string& actions : result.actions) {
    std::string path;
    for (char a : actions) {
      if (!path.empty()) path += ',';
      path += a;
    }
    paths.push_back(path);
  }
  doc["actualPaths"] = paths;
  doc["plannerPaths"] = paths;
  doc["Planner Paths"] = paths;
  doc["plannerTimes"] = result.planning_s;
  Json errors = Json::array();
  for (const std::string& e : result.errors) errors.push_back(Json::array({-1, -1, -1, e}));
  doc["errors"] = errors;
  Json events = Json::array();
  for (const auto& robot_events : result.events) {
    Json list = Json::array();
    for (const ErrandEvent& e : robot_events)
      list.push_back(Json::array({e.errand, e.step, e.finished ? "finished" : "assigned"}));
    events.push_back(list);
  }
  doc["events"] = events;
  Json errands = Json::array();
  for (const ErrandRecord& t : result.errands)
    errands.push_back(Json::array({t.id, t.cell / map.cols, t.cell % map.cols}));
  doc["tasks"] = errands;
  return doc.dump(4);
}

}  // namespace fleet::coordination
