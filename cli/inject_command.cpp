// fleetctl inject: random valid orders at a rate, or the rows of a CSV file checked whole first.

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <ostream>
#include <sstream>
#include <thread>

#include "cli/client.hpp"
#include "cli/command_flags.hpp"
#include "cli/online_support.hpp"
#include "cli/order_injection.hpp"
#include "cli/order_progress.hpp"
#include "cli/processes.hpp"
#include "common/args.hpp"
#include "common/clock.hpp"
#include "orders/order_request_check.hpp"

namespace fleet::cli {

namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

/// How long a random order may wait for a valid pick and drop (all pallets promised to open
/// orders, say) before it counts as not placed.
constexpr auto kDrawPatience = 10s;
/// Refusals caused by a race (another client or the server's automatic orders took the area
/// between our reading and our request) are retried with a fresh draw this often.
constexpr int kDrawAttempts = 20;

/// One order of the run: what was planned and what became of it.
struct Injection {
  PlannedOrder plan;
  std::int64_t order_id = 0;  ///< 0: not placed
  std::string not_placed_reason;
};

/// The server's refusals for pallets (FleetServer::validate_areas): none to pick, one in the way,
/// or promised to another order.
bool refused_for_pallets(const std::string& error) {
  return error.find("holds no pallet") != std::string::npos || error.find("holds a pallet") != std::string::npos ||
         error.find("is promised to order") != std::string::npos;
}

class Injector {
 public:
  Injector(const CommandArgs& command, const Connection& connection, FleetClient& client, model::ServerInfo info,
           std::ostream& out, std::ostream& err, bool wait)
      : command_(command),
        connection_(connection),
        client_(client),
        info_(std::move(info)),
        out_(out),
        err_(err),
        wait_(wait),
        started_(Clock::now()) {}

  /// Sends `plan` (drawing it from `rng` first when `rng` is given); false when the server did
  /// not answer, after which nothing more can be sent.
  bool place(PlannedOrder plan, std::mt19937_64* rng) {
    Injection injection;
    injection.plan = plan;
    const auto give_up_drawing = Clock::now() + kDrawPatience;
    for (int attempt = 0; attempt < kDrawAttempts; ++attempt) {
      if (rng) {
        auto drawn = draw(*rng);
        while (!drawn && Clock::now() < give_up_drawing && !stop_requested()) {
          pause(250ms);
          drawn = draw(*rng);
        }
        if (!drawn) {
          injection.not_placed_reason = "no loading area holds a pallet that no open order takes, or none is free";
          break;
        }
        drawn->priority = plan.priority;
        injection.plan = *drawn;
      }
      model::OrderRequest request;
      request.pick_area = injection.plan.pick_area;
      request.drop_area = injection.plan.drop_area;
      request.priority = injection.plan.priority;
      const auto reply = client_.request_order(request, connection_.timeout);
      if (!reply) {
        injection.not_placed_reason =
            "fleet-server on DDS domain " + std::to_string(connection_.domain) + " did not answer the order request";
        record(std::move(injection));
        return false;
      }
      if (reply->accepted) {
        injection.order_id = reply->order_id;
        injection.not_placed_reason.clear();
        break;
      }
      injection.not_placed_reason = "refused by the server: " + reply->error;
      if (!rng || !refused_for_pallets(reply->error)) break;
      pause(100ms);  // let the OrderInfo that beat us arrive, then draw again
    }
    record(std::move(injection));
    return true;
  }

  /// Waits until `until`, reading order updates (and reporting them with --wait) meanwhile.
  void wait_until(Clock::time_point until) {
    while (Clock::now() < until && !stop_requested()) pause(std::min<Clock::duration>(50ms, until - Clock::now()));
  }

  /// Follows every placed order to its end, --timeout or Ctrl-C; false when the server went away.
  bool follow() {
    const auto started = Clock::now();
    while (true) {
      pause(50ms);
      if (open_orders() == 0) return true;
      if (stop_requested()) return true;
      if (connection_.timeout_given && Clock::now() - started >= connection_.timeout) return true;
      if (!client_.check_server()) return false;
    }
  }

  void not_sent(PlannedOrder plan, const std::string& why) {
    Injection injection{std::move(plan), 0, why};
    record(std::move(injection));
  }

  /// The summary (always as JSON with --json; as text with --wait) and the exit code.
  /// `origin` says where the orders came from (file, or seed and rate) and heads the summary.
  int finish(bool server_lost, const std::string& source, nlohmann::json origin) {
    read_updates();
    long done = 0, failed = 0, cancelled = 0, open = 0, lost = 0, not_placed = 0, failed_without_reason = 0;
    nlohmann::json rows = nlohmann::json::array();
    for (const auto& injection : injections_) {
      nlohmann::json row{
          {"order_id", injection.order_id ? nlohmann::json(injection.order_id) : nlohmann::json(nullptr)},
          {"pick_area", injection.plan.pick_area},
          {"drop_area", injection.plan.drop_area},
          {"priority", injection.plan.priority}};
      if (injection.plan.line > 0) row["line"] = injection.plan.line;
      if (!injection.order_id) {
        ++not_placed;
        row["state"] = "NOT_PLACED";
        row["reason"] = injection.not_placed_reason;
        rows.push_back(row);
        continue;
      }
      const auto it = client_.known_orders().find(injection.order_id);
      std::string state = it == client_.known_orders().end() ? "QUEUED" : it->second.state;
      if (it != client_.known_orders().end()) {
        row["robot_id"] = it->second.robot_id;
        row["reason"] = it->second.reason;
        if (is_final_state(state))
          row["duration_s"] = std::round((it->second.updated_sim - it->second.created_sim) * 10) / 10;
      } else {
        row["robot_id"] = "";
        row["reason"] = "";
      }
      if (!is_final_state(state) && wait_ && server_lost) {
        state = "LOST";
        row["reason"] = "fleet-server went away before the order ended";
      }
      row["state"] = state;
      if (state == "DONE") ++done;
      if (state == "FAILED") ++failed;
      if (state == "FAILED" && row["reason"].get<std::string>().empty()) ++failed_without_reason;
      if (state == "CANCELLED") ++cancelled;
      if (state == "LOST") ++lost;
      if (!is_final_state(state) && state != "LOST") ++open;
      rows.push_back(row);
    }
    const long placed = static_cast<long>(injections_.size()) - not_placed;
    bool ok = not_placed == 0;
    if (wait_) ok = ok && lost == 0 && open == 0 && failed_without_reason == 0;
    nlohmann::json summary = std::move(origin);
    summary.update({{"requested", injections_.size()},
                    {"placed", placed},
                    {"not_placed", not_placed},
                    {"waited", wait_},
                    {"done", done},
                    {"failed", failed},
                    {"cancelled", cancelled},
                    {"open", open},
                    {"lost", lost},
                    {"ok", ok},
                    {"orders", rows}});
    if (command_.json) {
      out_ << summary.dump() << "\n";
    } else if (wait_) {
      out_ << placed << " of " << injections_.size() << " orders placed (" << source << "): " << done << " DONE, "
           << failed << " FAILED, " << cancelled << " CANCELLED, " << open << " still open, " << lost << " lost, "
           << not_placed << " not placed\n";
      for (const auto& row : rows) {
        out_ << "  " << (row["order_id"].is_null() ? std::string("-") : "order " + row["order_id"].dump()) << "  "
             << row["pick_area"].get<std::string>() << " -> " << row["drop_area"].get<std::string>() << "  "
             << row["state"].get<std::string>();
        if (row.contains("robot_id") && !row["robot_id"].get<std::string>().empty()) {
          out_ << " on " << row["robot_id"].get<std::string>();
        }
        if (row.contains("duration_s")) out_ << " after " << row["duration_s"].get<double>() << " s sim";
        if (!row["reason"].get<std::string>().empty()) out_ << ": " << row["reason"].get<std::string>();
        out_ << "\n";
      }
    }
    if (wait_ && open > 0) {
      err_ << "fleetctl: " << open << " orders had not ended when following them stopped\n";
    }
    return ok ? kExitOk : kExitFailed;
  }

 private:
  std::optional<PlannedOrder> draw(std::mt19937_64& rng) {
    read_updates();
    auto pallets = client_.pallets(0ms);
    if (pallets.empty()) return draw_any_order(info_.loading_areas, rng);  // no pallet state: let the server judge
    // Our own orders count even before their OrderInfo arrives.
    auto orders = client_.known_orders();
    for (const auto& injection : injections_) {
      if (injection.order_id && !orders.contains(injection.order_id)) {
        model::OrderInfo placeholder;
        placeholder.order_id = injection.order_id;
        placeholder.pick_area = injection.plan.pick_area;
        placeholder.drop_area = injection.plan.drop_area;
        placeholder.state = "QUEUED";
        orders[injection.order_id] = placeholder;
      }
    }
    return draw_order(area_balance(info_.loading_areas, pallets, orders), rng);
  }

  void record(Injection injection) {
    if (injection.order_id) {
      if (command_.json) {
        nlohmann::json line{{"order_id", injection.order_id},
                            {"pick_area", injection.plan.pick_area},
                            {"drop_area", injection.plan.drop_area},
                            {"priority", injection.plan.priority},
                            {"state", "QUEUED"}};
        if (injection.plan.line > 0) line["line"] = injection.plan.line;
        out_ << line.dump() << "\n" << std::flush;
      } else {
        out_ << "order " << injection.order_id << ": " << injection.plan.pick_area << " -> " << injection.plan.drop_area
             << (injection.plan.priority ? " priority " + std::to_string(injection.plan.priority) : "") << "\n"
             << std::flush;
      }
    } else {
      err_ << "fleetctl: " << (injection.plan.line > 0 ? "line " + std::to_string(injection.plan.line) + ": " : "")
           << "order " << injection.plan.pick_area << " -> " << injection.plan.drop_area
           << " not placed: " << injection.not_placed_reason << "\n";
    }
    injections_.push_back(std::move(injection));
  }

  /// Sleeps a little, then reads order updates.
  void pause(Clock::duration duration) {
    std::this_thread::sleep_for(duration);
    read_updates();
  }

  /// Takes the order updates that arrived; with --wait (and no --json) reports changes of our
  /// orders on stderr, as `order add --wait` does. Every read goes through here, so none is missed.
  void read_updates() {
    for (const auto& o : client_.take_order_updates()) {
      const bool ours = std::any_of(injections_.begin(), injections_.end(),
                                    [&](const Injection& i) { return i.order_id == o.order_id; });
      if (!ours || !wait_ || command_.json) continue;
      const std::string key = change_key(o);
      if (reported_[o.order_id] == key) continue;
      reported_[o.order_id] = key;
      std::ostringstream line;
      line << std::fixed << std::setprecision(1) << "["
           << std::chrono::duration<double>(Clock::now() - started_).count() << " s] order " << o.order_id << " "
           << o.state;
      if (o.state == "ACTIVE" && !o.phase.empty()) line << " " << o.phase;
      if (!o.robot_id.empty()) line << " on " << o.robot_id;
      if (!o.reason.empty()) line << ": " << o.reason;
      err_ << line.str() << "\n";
    }
  }

  long open_orders() const {
    long open = 0;
    for (const auto& injection : injections_) {
      if (!injection.order_id) continue;
      const auto it = client_.known_orders().find(injection.order_id);
      if (it == client_.known_orders().end() || !is_final_state(it->second.state)) ++open;
    }
    return open;
  }

  const CommandArgs& command_;
  const Connection& connection_;
  FleetClient& client_;
  model::ServerInfo info_;
  std::ostream& out_;
  std::ostream& err_;
  bool wait_;
  Clock::time_point started_;
  std::vector<Injection> injections_;
  std::map<std::int64_t, std::string> reported_;
};

/// Reads and checks an orders file whole; CommandExit (exit 2) listing every bad row as
/// FILE:LINE: message when any is bad, so that nothing is injected.
std::vector<PlannedOrder> checked_orders_file(const std::string& path, FleetClient& client,
                                              const Connection& connection, const CommandArgs& command,
                                              std::ostream& out, std::ostream& err, model::ServerInfo& info) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot read the file");
  OrdersFile file = parse_orders_csv(in);
  std::vector<RowProblem> problems = file.problems;
  const auto server = client.find_server(connection.timeout);
  if (server) {
    info = *server;
    client.orders(600ms);
    const auto pallets = client.pallets(0ms);
    std::optional<AreaBalance> balance;
    if (!pallets.empty()) balance = area_balance(info.loading_areas, pallets, client.known_orders());
    const auto site_problems = check_orders_against_site(file.rows, info.loading_areas, balance);
    problems.insert(problems.end(), site_problems.begin(), site_problems.end());
    std::stable_sort(problems.begin(), problems.end(), [](const auto& a, const auto& b) { return a.line < b.line; });
  }
  if (problems.empty() && file.rows.empty()) problems.push_back({0, "no order rows in it"});
  if (!problems.empty()) {
    nlohmann::json listed = nlohmann::json::array();
    for (const auto& p : problems) {
      err << path;
      if (p.line > 0) err << ":" << p.line;
      err << ": " << p.message << "\n";
      listed.push_back({{"line", p.line}, {"message", p.message}});
    }
    const std::string message = path + ": " + std::to_string(problems.size()) +
                                (problems.size() == 1 ? " problem" : " problems") + "; nothing was injected";
    if (command.json) {
      out << nlohmann::json{{"file", path}, {"placed", 0}, {"problems", listed}, {"ok", false}}.dump() << "\n";
    }
    throw CommandExit{kExitBadInput, message};
  }
  if (!server) throw CommandExit{kExitNoServer, "no fleet-server on DDS domain " + std::to_string(connection.domain)};
  return file.rows;
}

}  // namespace

int inject_command(const CommandArgs& command, const Connection& connection, std::ostream& out, std::ostream& err) {
  try {
    const CommandFlags args("inject", "", command.args);
    const auto file = args.value("file");
    const auto count = args.integer("count");
    const auto rate_text = args.value("rate");
    const auto seed = args.integer("seed");
    const auto priority = args.integer("priority");
    const bool wait = args.flag("wait");
    if (file && (count || rate_text || seed || priority)) {
      throw ArgError(
          "inject --file takes areas, priorities and delays from the file; leave out --count, --rate, "
          "--seed and --priority");
    }
    if (!file && !count) throw ArgError("inject needs --count M (random orders) or --file ORDERS.csv");
    const double per_second = parse_rate(rate_text.value_or("60/min"));

    FleetClient client(connection.domain);
    model::ServerInfo info;
    std::vector<PlannedOrder> rows;
    if (file) {
      rows = checked_orders_file(*file, client, connection, command, out, err, info);
    } else {
      info = require_server(client, connection);
      client.orders(600ms);
      client.pallets(0ms);
    }
    install_stop_handlers();
    Injector injector(command, connection, client, info, out, err, wait);
    const auto start = Clock::now();
    bool server_answers = true;
    std::string source;
    nlohmann::json origin;
    if (file) {
      source = *file;
      origin["file"] = *file;
      auto due = start;
      for (std::size_t i = 0; i < rows.size(); ++i) {
        due += std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(rows[i].delay_s));
        injector.wait_until(due);
        if (stop_requested() || !server_answers) {
          injector.not_sent(rows[i], stop_requested() ? "interrupted before it was sent" : "fleet-server went away");
          continue;
        }
        server_answers = injector.place(rows[i], nullptr);
      }
    } else {
      const long seed_value = seed.value_or(1);
      std::ostringstream describe;
      describe << "seed " << seed_value << ", " << per_second * 60.0 << "/min";
      source = describe.str();
      origin = {{"seed", seed_value}, {"rate_per_min", per_second * 60.0}};
      std::mt19937_64 rng(static_cast<std::uint64_t>(seed_value));
      PlannedOrder plan;
      plan.priority = static_cast<int>(priority.value_or(0));
      for (long i = 0; i < *count; ++i) {
        // Spaced from the start, not from the previous request, so slow answers do not lower the rate.
        injector.wait_until(start + std::chrono::duration_cast<Clock::duration>(
                                        std::chrono::duration<double>(static_cast<double>(i) / per_second)));
        if (stop_requested() || !server_answers) {
          injector.not_sent(plan, stop_requested() ? "interrupted before it was sent" : "fleet-server went away");
          continue;
        }
        server_answers = injector.place(plan, &rng);
      }
    }
    const bool server_lost = !server_answers || (wait && !injector.follow());
    return injector.finish(server_lost, source, origin);
  } catch (const CommandExit& e) {
    return report_failure(command.json, e.code, e.message, out, err);
  }
}

}  // namespace fleet::cli
