#include "coordination/lorr_instance.hpp"

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <unordered_set>

#include "common/args.hpp"
#include "common/errors.hpp"

namespace fleet::coordination {

namespace {

bool next_data_line(std::istream& in, std::string& line, int& line_no) {
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (!line.empty() && line[0] != '#') return true;
  }
  return false;
}

long whole_number(const std::string& text, const std::string& where) {
  // The competition's files may carry more fields after a comma; the location is the first.
  const auto value = parse_long(text.substr(0, text.find(',')));
  if (!value) throw InputError(where + ": '" + text + "' is not an integer");
  return *value;
}

template <typename T>
T required(const nlohmann::json& doc, const std::string& key, const std::string& path) {
  if (!doc.contains(key)) throw InputError(path + ": the key '" + key + "' is missing");
  try {
    return doc.at(key).get<T>();
  } catch (const nlohmann::json::exception&) {
    throw InputError(path + ": the key '" + key + "' has the wrong type (" + doc.at(key).dump() + ")");
  }
}

void check_cells(const std::vector<int>& cells, const GridMap& map, const std::string& what, const std::string& file) {
  for (std::size_t i = 0; i < cells.size(); ++i) {
    if (!map.is_free(cells[i])) {
      throw InputError(file + ": " + what + " " + std::to_string(i) + " at location " + std::to_string(cells[i]) +
                       (cells[i] >= 0 && cells[i] < map.cells()
                            ? " " + map.describe(cells[i]) + " is a blocked cell"
                            : " is off the " + std::to_string(map.rows) + " x " + std::to_string(map.cols) + " map"));
    }
  }
}

}  // namespace

std::vector<int> read_location_file(const std::string& path, const std::string& key, int limit) {
  std::ifstream in(path);
  if (!in) throw InputError(path + " (" + key + "): cannot read the file");
  std::string line;
  int line_no = 0;
  if (!next_data_line(in, line, line_no)) throw InputError(path + " (" + key + "): empty, no count on its first line");
  const long count = whole_number(line, path + ":" + std::to_string(line_no));
  if (count <= 0) throw InputError(path + ":" + std::to_string(line_no) + ": a count of " + line + ", not positive");
  const long wanted = limit >= 0 ? std::min<long>(count, limit) : count;
  std::vector<int> values;
  values.reserve(static_cast<std::size_t>(wanted));
  while (static_cast<long>(values.size()) < wanted) {
    if (!next_data_line(in, line, line_no)) {
      throw InputError(path + ": says " + std::to_string(count) + " locations and ends after " +
                       std::to_string(values.size()));
    }
    values.push_back(static_cast<int>(whole_number(line, path + ":" + std::to_string(line_no))));
  }
  return values;
}

LorrInstance load_lorr_instance(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot read the instance file");
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(in);
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(path + ": not JSON (" + e.what() + ")");
  }
  if (!doc.is_object()) throw InputError(path + ": not a JSON object");
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  auto file_of = [&](const std::string& key) { return (folder / required<std::string>(doc, key, path)).string(); };

  LorrInstance instance;
  instance.path = path;
  const int team = required<int>(doc, "teamSize", path);
  if (team <= 0) throw InputError(path + ": teamSize " + std::to_string(team) + " is not positive");
  const std::string strategy = doc.value("taskAssignmentStrategy", std::string("roundrobin"));
  if (strategy != "roundrobin") {
    throw InputError(path + ": taskAssignmentStrategy '" + strategy + "' is not supported (roundrobin is)");
  }
  instance.tasks_revealed = doc.contains("numTasksReveal") ? required<int>(doc, "numTasksReveal", path) : 1;
  if (instance.tasks_revealed < 1) throw InputError(path + ": numTasksReveal must be at least 1");
  instance.map = load_grid_map(file_of("mapFile"));
  const std::string agent_file = file_of("agentFile");
  instance.starts = read_location_file(agent_file, "agentFile", team);
  if (static_cast<int>(instance.starts.size()) < team) {
    throw InputError(agent_file + ": has " + std::to_string(instance.starts.size()) +
                     " start locations for a teamSize of " + std::to_string(team) + " in " + path);
  }
  const std::string task_file = file_of("taskFile");
  instance.tasks = read_location_file(task_file, "taskFile", -1);
  check_cells(instance.starts, instance.map, "robot", agent_file);
  check_cells(instance.tasks, instance.map, "errand", task_file);
  std::unordered_set<int> taken;
  for (std::size_t i = 0; i < instance.starts.size(); ++i) {
    if (!taken.insert(instance.starts[i]).second) {
      throw InputError(agent_file + ": robot " + std::to_string(i) + " starts on location " +
                       std::to_string(instance.starts[i]) + ", where an earlier robot starts");
    }
  }
  return instance;
}

}  // namespace fleet::coordination
