#include "orders/pick_lines.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>

#include "common/errors.hpp"
#include "config/fleet_config.hpp"
#include "model/names.hpp"

namespace fleet::orders {

namespace {

std::string trim(std::string_view s) {
  const auto first = s.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return {};
  const auto last = s.find_last_not_of(" \t\r");
  return std::string(s.substr(first, last - first + 1));
}

std::string one_decimal(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.1f", v);
  return buffer;
}

std::string line_at(const std::string& source, int line) {
  return source + ":" + std::to_string(line);
}

std::vector<std::string> fields_of(std::string_view row) {
  std::vector<std::string> out;
  std::size_t start = 0;
  for (;;) {
    const auto comma = row.find(',', start);
    out.push_back(trim(row.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start)));
    if (comma == std::string_view::npos) return out;
    start = comma + 1;
  }
}

}  // namespace

std::vector<PickLine> parse_pick_lines(std::string_view text, const std::string& source) {
  std::vector<PickLine> lines;
  int number = 0;
  std::size_t start = 0;
  while (start <= text.size()) {
    const auto end = text.find('\n', start);
    const std::string_view row =
        text.substr(start, end == std::string_view::npos ? std::string_view::npos : end - start);
    start = end == std::string_view::npos ? text.size() + 1 : end + 1;
    ++number;
    const std::string content = trim(row);
    if (content.empty() || content.front() == '#') continue;
    const std::vector<std::string> f = fields_of(content);
    const std::string at = line_at(source, number);
    if (lines.empty() && f.size() == 3 && f[0] == "place" && f[1] == "item" && f[2] == "quantity") continue;
    if (f.size() != 3) {
      throw InputError(at + ": expected place,item,quantity, got " + std::to_string(f.size()) + " field" +
                       (f.size() == 1 ? "" : "s") + ": '" + model::excerpt(content) + "'");
    }
    if (f[0].empty()) throw InputError(at + ": the place is empty");
    if (f[1].empty()) throw InputError(at + ": the item is empty");
    int quantity = 0;
    const auto [ptr, ec] = std::from_chars(f[2].data(), f[2].data() + f[2].size(), quantity);
    if (ec != std::errc{} || ptr != f[2].data() + f[2].size() || quantity < 1) {
      throw InputError(at + ": quantity '" + model::excerpt(f[2]) + "' is not a whole number of boxes >= 1");
    }
    lines.push_back({f[0], f[1], quantity, number});
  }
  if (lines.empty()) throw InputError(source + ": no pick lines (expected place,item,quantity per line)");
  return lines;
}

std::string pick_lines_csv(const std::vector<PickLine>& lines) {
  std::string out;
  for (const PickLine& l : lines) out += l.place + "," + l.item + "," + std::to_string(l.quantity) + "\n";
  return out;
}

std::optional<std::string> check_pick_lines(const std::vector<PickLine>& lines, const std::vector<std::string>& places,
                                            const std::map<std::string, map::BoxStock>& stock, double max_box_mass,
                                            const std::string& source) {
  std::map<std::string, int> asked;
  for (const PickLine& l : lines) {
    const std::string at = line_at(source, l.line);
    if (std::find(places.begin(), places.end(), l.place) == places.end()) {
      return at + ": " + model::unknown_name_message("place", l.place, places);
    }
    const auto held = stock.find(l.place);
    if (held == stock.end() || held->second.count == 0) return at + ": place " + l.place + " holds no boxes to pick";
    const map::BoxStock& s = held->second;
    if (s.item != l.item) return at + ": place " + l.place + " holds item " + s.item + ", not " + l.item;
    if (s.mass > max_box_mass) {
      return at + ": a box of " + l.item + " weighs " + one_decimal(s.mass) +
             " kg, more than the pickers' grippers hold (" + one_decimal(max_box_mass) + " kg)";
    }
    const int total = asked[l.place] += l.quantity;
    if (total > s.count) {
      return at + ": place " + l.place + " holds " + std::to_string(s.count) + " box" + (s.count == 1 ? "" : "es") +
             " of " + s.item + ", the lines ask for " + std::to_string(total);
    }
  }
  return std::nullopt;
}

std::map<std::string, map::BoxStock> declared_boxes(const map::Site& site) {
  std::map<std::string, map::BoxStock> out;
  for (const auto& area : site.loading_areas) {
    if (area.boxes) out[area.id] = *area.boxes;
  }
  return out;
}

double max_pickable_mass(const config::FleetConfig& config) {
  double heaviest = 0.0;
  for (const auto& fleet : config.fleets) {
    const auto& actions = fleet.profile.actions;
    if (std::find(actions.begin(), actions.end(), "pickItem") != actions.end()) {
      heaviest = std::max(heaviest, fleet.profile.load.max_mass);
    }
  }
  return heaviest;
}

std::map<std::string, geometry::Pose2> place_poses(const map::Site& site) {
  std::map<std::string, geometry::Pose2> out;
  for (const auto& area : site.loading_areas) out[area.id] = area.pose;
  return out;
}

int PickTour::boxes() const {
  int n = 0;
  for (const PickLine& l : lines) n += l.quantity;
  return n;
}

std::vector<PickTour> plan_tours(const std::vector<PickLine>& lines, int capacity,
                                 const std::map<std::string, geometry::Pose2>& poses) {
  if (capacity < 1) throw std::invalid_argument("plan_tours: capacity must be >= 1");
  std::vector<PickLine> merged;
  for (const PickLine& l : lines) {
    auto same = std::find_if(merged.begin(), merged.end(), [&](const PickLine& m) { return m.place == l.place; });
    if (same == merged.end()) {
      merged.push_back(l);
    } else {
      same->quantity += l.quantity;
    }
  }
  const auto where = [&](const PickLine& l) {
    const auto it = poses.find(l.place);
    return it == poses.end() ? geometry::Pose2{} : it->second;
  };
  std::stable_sort(merged.begin(), merged.end(), [&](const PickLine& a, const PickLine& b) {
    const geometry::Pose2 pa = where(a), pb = where(b);
    // Places on one aisle face share their y to the centimetre.
    if (std::abs(pa.y - pb.y) > 0.01) return pa.y < pb.y;
    return pa.x < pb.x;
  });
  std::vector<PickTour> tours;
  int room = 0;
  for (PickLine l : merged) {
    while (l.quantity > 0) {
      if (room == 0) {
        tours.emplace_back();
        room = capacity;
      }
      PickLine part = l;
      part.quantity = std::min(l.quantity, room);
      tours.back().lines.push_back(part);
      l.quantity -= part.quantity;
      room -= part.quantity;
    }
  }
  return tours;
}

bool same_rack_row(const geometry::Pose2& a, const geometry::Pose2& b) {
  return std::abs(a.y - b.y) < 0.05;
}

std::optional<std::vector<PickLine>> choose_auto_pick_list(const std::map<std::string, map::BoxStock>& stock,
                                                           const std::map<std::string, geometry::Pose2>& poses,
                                                           double max_box_mass, int capacity, std::mt19937_64& rng) {
  std::vector<std::string> places;
  for (const auto& [place, boxes] : stock) {
    if (boxes.count > 0 && boxes.mass <= max_box_mass && poses.contains(place)) places.push_back(place);
  }
  if (places.empty() || capacity < 1) return std::nullopt;
  const auto take = [&](const std::string& place, int room) {
    const auto& boxes = stock.at(place);
    const int most = std::min(room, boxes.count);
    return PickLine{place, boxes.item, 1 + static_cast<int>(rng() % static_cast<std::uint64_t>(most)), 0};
  };
  std::vector<PickLine> lines{take(places[rng() % places.size()], capacity)};
  int room = capacity - lines.front().quantity;
  const geometry::Pose2& first = poses.at(lines.front().place);
  std::vector<std::string> same_row;
  for (const auto& place : places) {
    if (place != lines.front().place && same_rack_row(poses.at(place), first)) same_row.push_back(place);
  }
  // Lines from other places of the row until the boxes fill what carries them: a tray's two slots,
  // or a loader's pallet, which its stacker brought for the walk.
  while (room > 0 && !same_row.empty()) {
    const std::size_t pick = rng() % same_row.size();
    lines.push_back(take(same_row[pick], room));
    // The row's last place gives all it can.
    if (same_row.size() == 1) lines.back().quantity = std::min(room, stock.at(same_row[pick]).count);
    room -= lines.back().quantity;
    same_row.erase(same_row.begin() + static_cast<std::ptrdiff_t>(pick));
  }
  for (std::size_t i = 0; i < lines.size(); ++i) lines[i].line = static_cast<int>(i) + 1;
  return lines;
}

}  // namespace fleet::orders
