#include "cli/order_injection.hpp"

#include <algorithm>
#include <istream>

#include "common/args.hpp"
#include "model/names.hpp"
#include "orders/order.hpp"
#include "orders/order_request_check.hpp"

namespace fleet::cli {

namespace {

std::string trim(const std::string& text) {
  const auto first = text.find_first_not_of(" \t\r");
  if (first == std::string::npos) return "";
  return text.substr(first, text.find_last_not_of(" \t\r") - first + 1);
}

std::vector<std::string> split_fields(const std::string& line) {
  std::vector<std::string> fields;
  std::size_t start = 0;
  while (true) {
    const auto comma = line.find(',', start);
    fields.push_back(trim(line.substr(start, comma == std::string::npos ? std::string::npos : comma - start)));
    if (comma == std::string::npos) return fields;
    start = comma + 1;
  }
}

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

std::vector<std::string> areas_where(const AreaBalance& balance, bool holding_pallet) {
  std::vector<std::string> out;
  for (const auto& [area, count] : balance) {
    if ((count > 0) == holding_pallet) out.push_back(area);
  }
  return out;
}

std::string listed(const std::vector<std::string>& areas) {
  return areas.empty() ? "none" : model::join(areas);
}

}  // namespace

AreaBalance area_balance(const std::vector<std::string>& areas, const std::map<int, model::PalletTruth>& pallets,
                         const std::map<std::int64_t, model::OrderInfo>& orders) {
  AreaBalance balance;
  for (const auto& area : areas) balance[area] = 0;
  for (const auto& [id, pallet] : pallets) {
    if (!pallet.area_id.empty() && pallet.carried_by.empty() && balance.contains(pallet.area_id)) {
      ++balance[pallet.area_id];
    }
  }
  for (const auto& [id, order] : orders) {
    const auto status = orders::parse_status(order.state);
    if (!status || orders::is_final(*status)) continue;
    if (balance.contains(order.pick_area)) --balance[order.pick_area];
    if (balance.contains(order.drop_area)) ++balance[order.drop_area];
  }
  return balance;
}

std::optional<std::string> refusal_reason(const AreaBalance& balance, const std::string& pick,
                                          const std::string& drop) {
  if (pick == drop) return "from and to are the same area ('" + pick + "')";
  const auto from = balance.find(pick);
  const auto to = balance.find(drop);
  if (from == balance.end() || to == balance.end()) return "unknown loading area";
  if (from->second <= 0) {
    return "loading area '" + pick +
           "' holds no pallet to pick by then (pallets to pick: " + listed(areas_where(balance, true)) + ")";
  }
  if (to->second > 0) {
    return "loading area '" + drop + "' is occupied by a pallet by then (free: " + listed(areas_where(balance, false)) +
           ")";
  }
  return std::nullopt;
}

void book_order(AreaBalance& balance, const std::string& pick, const std::string& drop) {
  --balance[pick];
  ++balance[drop];
}

std::optional<PlannedOrder> draw_order(const AreaBalance& balance, std::mt19937_64& rng) {
  const auto picks = areas_where(balance, true);
  const auto drops = areas_where(balance, false);
  if (picks.empty() || drops.empty()) return std::nullopt;
  PlannedOrder order;
  order.pick_area = picks[rng() % picks.size()];
  order.drop_area = drops[rng() % drops.size()];
  return order;
}

std::optional<PlannedOrder> draw_any_order(const std::vector<std::string>& areas, std::mt19937_64& rng) {
  if (areas.size() < 2) return std::nullopt;
  PlannedOrder order;
  const std::size_t pick = rng() % areas.size();
  const std::size_t drop = (pick + 1 + rng() % (areas.size() - 1)) % areas.size();  // any area but the pick
  order.pick_area = areas[pick];
  order.drop_area = areas[drop];
  return order;
}

double parse_rate(const std::string& text) {
  const auto slash = text.find('/');
  const std::string number = text.substr(0, slash);
  const std::string unit = slash == std::string::npos ? "" : text.substr(slash + 1);
  const auto parsed = parse_finite(number);
  const double count = parsed.value_or(0.0);
  double per_second = 0.0;
  if (unit == "s") per_second = 1.0;
  if (unit == "min") per_second = 1.0 / 60.0;
  if (unit == "h") per_second = 1.0 / 3600.0;
  if (!parsed || per_second == 0.0) {
    throw ArgError("flag --rate: '" + text + "' is not a rate; write N/min (or N/s, N/h), for example 30/min");
  }
  if (count <= 0.0) throw ArgError("flag --rate: " + text + " is not above 0");
  return count * per_second;
}

OrdersFile parse_orders_csv(std::istream& in) {
  OrdersFile file;
  bool seen_row = false;
  int line_number = 0;
  for (std::string line; std::getline(in, line);) {
    ++line_number;
    // Spreadsheets save UTF-8 with a byte order mark before the first cell.
    if (line_number == 1 && line.starts_with("\xEF\xBB\xBF")) line.erase(0, 3);
    const std::string text = trim(line);
    if (text.empty() || text[0] == '#') continue;
    const auto fields = split_fields(text);
    const bool first_row = !seen_row;
    seen_row = true;
    if (first_row && fields.size() == 4 && lower(fields[0]) == "from" && lower(fields[1]) == "to" &&
        lower(fields[2]) == "priority" && lower(fields[3]) == "delay_s") {
      continue;  // the header
    }
    const auto problem = [&](const std::string& message) { file.problems.push_back({line_number, message}); };
    if (fields.size() != 4) {
      problem("expected 4 columns from,to,priority,delay_s, found " + std::to_string(fields.size()));
      continue;
    }
    PlannedOrder row;
    row.line = line_number;
    row.pick_area = fields[0];
    row.drop_area = fields[1];
    bool ok = true;
    if (row.pick_area.empty() || row.drop_area.empty()) {
      problem(std::string(row.pick_area.empty() ? "from" : "to") + " is empty");
      ok = false;
    } else if (row.pick_area == row.drop_area) {
      problem("from and to are the same area ('" + row.pick_area + "')");
      ok = false;
    }
    const auto& p = fields[2];
    const auto priority = parse_long(p);
    if (!priority) {
      problem("priority '" + p + "' is not an integer");
      ok = false;
    } else if (*priority < orders::kMinPriority || *priority > orders::kMaxPriority) {
      problem("priority " + p + " is outside " + std::to_string(orders::kMinPriority) + " .. " +
              std::to_string(orders::kMaxPriority));
      ok = false;
    }
    row.priority = static_cast<int>(priority.value_or(0));
    const auto& d = fields[3];
    const auto delay = parse_finite(d);
    row.delay_s = delay.value_or(0.0);
    if (!delay) {
      problem("delay_s '" + d + "' is not a number of seconds");
      ok = false;
    } else if (row.delay_s < 0.0) {
      problem("delay_s " + d + " is negative (it is the wait after the previous row, in seconds)");
      ok = false;
    }
    if (ok) file.rows.push_back(std::move(row));
  }
  return file;
}

std::vector<RowProblem> check_orders_against_site(const std::vector<PlannedOrder>& rows,
                                                  const std::vector<std::string>& areas,
                                                  std::optional<AreaBalance> balance) {
  std::vector<RowProblem> problems;
  const auto known = [&](const std::string& area) {
    return std::find(areas.begin(), areas.end(), area) != areas.end();
  };
  for (const auto& row : rows) {
    bool names_ok = true;
    for (const auto& [column, area] : {std::pair{"from", row.pick_area}, std::pair{"to", row.drop_area}}) {
      if (!known(area)) {
        problems.push_back(
            {row.line, std::string(column) + ": " + model::unknown_name_message("loading area", area, areas)});
        names_ok = false;
      }
    }
    if (!names_ok || !balance) continue;
    if (const auto reason = refusal_reason(*balance, row.pick_area, row.drop_area)) {
      problems.push_back({row.line, *reason + "; the server would refuse this row"});
      continue;
    }
    book_order(*balance, row.pick_area, row.drop_area);
  }
  return problems;
}

}  // namespace fleet::cli
