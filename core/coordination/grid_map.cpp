#include "coordination/grid_map.hpp"

#include <algorithm>
#include <fstream>
#include <sstream>

#include "common/errors.hpp"

namespace fleet::coordination {

namespace {

bool free_symbol(char c) {
  return c == '.' || c == 'E' || c == 'S' || c == 'G';
}
bool blocked_symbol(char c) {
  return c == '@' || c == 'T' || c == 'O' || c == 'W';
}

int header_value(std::istream& in, const std::string& key, const std::string& source, int& line_no) {
  std::string line;
  if (!std::getline(in, line)) throw InputError(source + ": ends before the '" + key + "' line");
  ++line_no;
  std::istringstream words(line);
  std::string word;
  int value = 0;
  if (!(words >> word) || word != key || !(words >> value) || value <= 0 || value > 100000) {
    throw InputError(source + ":" + std::to_string(line_no) + ": expected '" + key + " N' (N > 0), got '" + line + "'");
  }
  return value;
}

}  // namespace

char heading_letter(int heading) {
  static constexpr char kLetters[] = {'E', 'S', 'W', 'N'};
  return heading >= 0 && heading < kHeadings ? kLetters[heading] : '?';
}

int GridMap::free_cells() const {
  int n = 0;
  for (auto f : free) n += f != 0 ? 1 : 0;
  return n;
}

int GridMap::step(int cell, int heading) const {
  const int row = cell / cols;
  const int col = cell % cols;
  int next = -1;
  switch (heading) {
    case 0:
      next = col + 1 < cols ? cell + 1 : -1;
      break;
    case 1:
      next = row + 1 < rows ? cell + cols : -1;
      break;
    case 2:
      next = col > 0 ? cell - 1 : -1;
      break;
    case 3:
      next = row > 0 ? cell - cols : -1;
      break;
    default:
      break;
  }
  return next >= 0 && free[next] != 0 ? next : -1;
}

int GridMap::heading_between(int from, int to) const {
  for (int h = 0; h < kHeadings; ++h) {
    if (step(from, h) == to && to >= 0) return h;
  }
  return -1;
}

std::string GridMap::describe(int cell) const {
  return "(row " + std::to_string(cell / cols) + ", column " + std::to_string(cell % cols) + ")";
}

GridReport check_grid_map(const GridMap& map) {
  GridReport report{map.rows, map.cols, map.free_cells(), 0, 0, 0};
  std::vector<int> component(static_cast<std::size_t>(map.cells()), -1);
  std::vector<int> stack;
  for (int start = 0; start < map.cells(); ++start) {
    if (!map.is_free(start)) continue;
    int exits = 0;
    for (int h = 0; h < kHeadings; ++h) exits += map.step(start, h) >= 0 ? 1 : 0;
    report.dead_ends += exits == 1 ? 1 : 0;
    if (component[start] >= 0) continue;
    int size = 0;
    component[start] = report.components;
    stack.assign(1, start);
    while (!stack.empty()) {
      const int cell = stack.back();
      stack.pop_back();
      ++size;
      for (int h = 0; h < kHeadings; ++h) {
        const int next = map.step(cell, h);
        if (next >= 0 && component[next] < 0) {
          component[next] = report.components;
          stack.push_back(next);
        }
      }
    }
    report.largest_component = std::max(report.largest_component, size);
    ++report.components;
  }
  return report;
}

std::string format_grid_report(const GridReport& report, const std::string& name) {
  std::ostringstream out;
  out << name << ": grid site, " << report.rows << " x " << report.cols << " cells, " << report.free_cells << " free, "
      << report.components << (report.components == 1 ? " component" : " components") << " (largest "
      << report.largest_component << " cells), " << report.dead_ends << " dead ends\n";
  if (report.components > 1) {
    out << "  " << report.free_cells - report.largest_component
        << " free cells cannot be reached from the largest component: a robot or errand there stays apart\n";
  }
  return out.str();
}

GridMap parse_grid_map(std::istream& in, const std::string& source) {
  GridMap map;
  map.source = source;
  std::string line;
  int line_no = 1;
  if (!std::getline(in, line) || line.rfind("type", 0) != 0) {
    throw InputError(source + ":1: not a MovingAI map: the first line must be 'type octile'");
  }
  map.rows = header_value(in, "height", source, line_no);
  map.cols = header_value(in, "width", source, line_no);
  if (!std::getline(in, line) || line.rfind("map", 0) != 0) {
    throw InputError(source + ":" + std::to_string(line_no + 1) + ": expected the 'map' line");
  }
  ++line_no;
  map.free.assign(static_cast<std::size_t>(map.rows) * map.cols, 0);
  for (int row = 0; row < map.rows; ++row) {
    if (!std::getline(in, line)) {
      throw InputError(source + ": has " + std::to_string(row) + " rows of cells, its height says " +
                       std::to_string(map.rows));
    }
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (static_cast<int>(line.size()) != map.cols) {
      throw InputError(source + ":" + std::to_string(line_no) + ": a row of " + std::to_string(line.size()) +
                       " cells, the width says " + std::to_string(map.cols));
    }
    for (int col = 0; col < map.cols; ++col) {
      const char c = line[col];
      if (!free_symbol(c) && !blocked_symbol(c)) {
        throw InputError(source + ":" + std::to_string(line_no) + ": unknown cell symbol '" + std::string(1, c) +
                         "' in column " + std::to_string(col) + " (free: . E S G, blocked: @ T O W)");
      }
      map.free[static_cast<std::size_t>(row) * map.cols + col] = free_symbol(c) ? 1 : 0;
    }
  }
  if (map.free_cells() == 0) throw InputError(source + ": has no free cell");
  return map;
}

GridMap load_grid_map(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot read the map file");
  return parse_grid_map(in, path);
}

}  // namespace fleet::coordination
