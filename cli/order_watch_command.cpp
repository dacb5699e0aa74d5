// fleetctl order watch [ID]: live progress of one order or of all of them.

#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <iomanip>
#include <optional>
#include <ostream>
#include <sstream>
#include <thread>

#include "cli/client.hpp"
#include "cli/command_flags.hpp"
#include "cli/online_support.hpp"
#include "cli/order_progress.hpp"
#include "cli/processes.hpp"
#include "common/args.hpp"
#include "common/clock.hpp"

namespace fleet::cli {

namespace {

using namespace std::chrono_literals;

/// Whether stdout is a terminal that understands ANSI cursor movement.
bool stdout_is_terminal() {
  const char* term = std::getenv("TERM");
  return isatty(STDOUT_FILENO) && term && std::strcmp(term, "dumb") != 0;
}

std::size_t terminal_columns() {
  winsize size{};
  if (ioctl(STDOUT_FILENO, TIOCGWINSZ, &size) == 0 && size.ws_col > 0) return size.ws_col;
  return 80;
}

/// A block of lines at the bottom of the terminal, redrawn in place; lines logged above it scroll
/// up like ordinary output. Lines are cut to the terminal's width: a wrapped line would make the
/// next redraw move the cursor up too little.
class LiveBlock {
 public:
  explicit LiveBlock(std::ostream& out) : out_(out) {}

  void log(const std::string& line) { logged_.push_back(line); }

  void draw(const std::vector<std::string>& lines) {
    const std::size_t width = terminal_columns() - 1;
    if (drawn_ > 0) out_ << "\r\x1b[" << drawn_ << "A\x1b[J";  // up to the block's first line, clear below
    for (const auto& line : logged_) out_ << line.substr(0, width) << "\n";
    for (const auto& line : lines) out_ << line.substr(0, width) << "\n";
    logged_.clear();
    drawn_ = lines.size();
    out_ << std::flush;
  }

 private:
  std::ostream& out_;
  std::vector<std::string> logged_;
  std::size_t drawn_ = 0;
};

/// "[#####.....]" for how far an order is, from its estimate; blank when unknown.
std::string progress_bar(const model::OrderInfo& order, const OrderProgress& progress, const DurationModel& durations) {
  constexpr int kWidth = 10;
  const auto work = durations.mean_work();
  if (order.state == "QUEUED") return "[" + std::string(kWidth, '.') + "]";
  if (!progress.left_s || !work || *work <= 0.0) return std::string(kWidth + 2, ' ');
  const double fraction = std::clamp(1.0 - *progress.left_s / *work, 0.0, 1.0);
  const int filled = static_cast<int>(std::round(fraction * kWidth));
  return "[" + std::string(filled, '#') + std::string(kWidth - filled, '.') + "]";
}

std::vector<std::string> table_of(const std::vector<const model::OrderInfo*>& shown, const DurationModel& durations,
                                  double now_sim, const std::string& title) {
  std::vector<std::string> lines{title};
  std::ostringstream header;
  header << std::left << std::setw(7) << "ORDER" << std::setw(6) << "FROM" << std::setw(6) << "TO" << std::setw(10)
         << "STATE" << std::setw(11) << "PHASE" << std::setw(7) << "ROBOT" << std::setw(10) << "ELAPSED" << std::setw(9)
         << "LEFT"
         << "PROGRESS";
  lines.push_back(header.str());
  for (const auto* order : shown) {
    const OrderProgress progress = progress_of(*order, durations, now_sim);
    std::ostringstream row, elapsed, left;
    elapsed << std::fixed << std::setprecision(1) << progress.elapsed_s << " s";
    if (progress.left_s) {
      left << std::fixed << std::setprecision(1) << *progress.left_s << " s";
    } else {
      left << "?";
    }
    row << std::left << std::setw(7) << order->order_id << std::setw(6) << order->pick_area << std::setw(6)
        << order->drop_area << std::setw(10) << order->state << std::setw(11)
        << (order->state == "ACTIVE" ? order->phase : "") << std::setw(7)
        << (order->robot_id.empty() ? "-" : order->robot_id) << std::setw(10) << elapsed.str() << std::setw(9)
        << left.str() << progress_bar(*order, progress, durations);
    if (!order->reason.empty()) row << " " << order->reason;
    lines.push_back(row.str());
  }
  return lines;
}

std::string summary_title(std::uint32_t domain, const std::map<std::int64_t, model::OrderInfo>& orders,
                          const DurationModel& durations) {
  long open = 0, done = 0, failed = 0;
  for (const auto& [id, o] : orders) {
    if (!is_final_state(o.state)) ++open;
    if (o.state == "DONE") ++done;
    if (o.state == "FAILED") ++failed;
  }
  std::ostringstream title;
  title << std::fixed << std::setprecision(1) << "domain " << domain << ": " << open << " open, " << done << " done, "
        << failed << " failed; ";
  if (const auto work = durations.mean_work()) {
    title << "assigned to DONE " << *work << " s (sim) on average";
  } else {
    title << "time left ? until an order is DONE";
  }
  return title.str();
}

}  // namespace

int order_watch(const std::vector<std::string>& words, const CommandArgs& command, const Connection& connection,
                std::ostream& out, std::ostream& err) {
  try {
    const CommandFlags args("order", "watch", words);
    const std::vector<std::string>& positionals = args.positionals();
    if (positionals.size() > 1) throw ArgError("order watch takes at most one order id");
    // Order ids are positive: 0 watches every order.
    const std::int64_t watched = positionals.empty() ? 0 : order_id_of(positionals[0]);

    FleetClient client(connection.domain);
    const model::ServerInfo info = require_server(client, connection);
    const SimClock clock(info.time_scale);
    client.orders(600ms);  // every order's latest record (latched), for the estimates
    if (watched && !client.known_orders().contains(watched)) {
      const auto& known = client.known_orders();
      throw CommandExit{kExitBadInput,
                        "unknown order " + std::to_string(watched) +
                            (known.empty() ? "; the server has no orders"
                                           : "; the server knows orders " + std::to_string(known.begin()->first) +
                                                 " .. " + std::to_string(known.rbegin()->first))};
    }
    install_stop_handlers();
    const bool live = !command.json && stdout_is_terminal();
    LiveBlock block(out);
    std::map<std::int64_t, std::string> printed;  // the change key last printed per order
    std::optional<DurationModel> durations;
    const auto selected = [&](const model::OrderInfo& o) { return watched == 0 || o.order_id == watched; };

    // One line (or JSON line) per change when piped; on a terminal, endings scroll above the
    // live table and everything else shows in it.
    const auto report = [&](const model::OrderInfo& o) {
      const std::string key = change_key(o);
      if (printed[o.order_id] == key) return;
      printed[o.order_id] = key;
      const OrderProgress progress = progress_of(o, *durations, clock.now());
      if (command.json) {
        out << progress_json(o, progress).dump() << "\n" << std::flush;
      } else if (!live) {
        out << progress_line(o, progress) << "\n" << std::flush;
      } else if (is_final_state(o.state)) {
        block.log(progress_line(o, progress));
      }
    };

    durations.emplace(client.known_orders());
    for (const auto& [id, o] : client.known_orders()) {
      // At the start: the watched order whatever its state, or every open order.
      if (watched ? id == watched : !is_final_state(o.state)) report(o);
    }
    const auto started = std::chrono::steady_clock::now();
    auto next_draw = started;
    std::string stopped_why;
    while (true) {
      const auto updates = client.take_order_updates();
      if (!updates.empty()) durations.emplace(client.known_orders());
      for (const auto& o : updates) {
        if (selected(o)) report(o);
      }
      const auto now = std::chrono::steady_clock::now();
      if (live && (now >= next_draw || !updates.empty())) {
        std::vector<const model::OrderInfo*> shown;
        for (const auto& [id, o] : client.known_orders()) {
          if (watched ? id == watched : !is_final_state(o.state)) shown.push_back(&o);
        }
        const std::string title = watched ? "order " + std::to_string(watched) + " (sim seconds)"
                                          : summary_title(connection.domain, client.known_orders(), *durations);
        block.draw(table_of(shown, *durations, clock.now(), title));
        next_draw = now + 250ms;
      }
      if (watched) {
        const auto& o = client.known_orders().at(watched);
        if (is_final_state(o.state)) return o.state == "DONE" ? kExitOk : kExitFailed;
      }
      if (stop_requested()) {
        stopped_why = "stopped";
        break;
      }
      if (connection.timeout_given && now - started >= connection.timeout) {
        stopped_why = "--timeout reached";
        break;
      }
      if (!client.check_server()) {
        throw CommandExit{kExitNoServer,
                          "fleet-server on DDS domain " + std::to_string(connection.domain) + " went away"};
      }
      std::this_thread::sleep_for(50ms);
    }
    if (!watched) return kExitOk;  // watching all orders ends only by Ctrl-C or --timeout
    const auto& o = client.known_orders().at(watched);
    err << "fleetctl: " << stopped_why << " while order " << watched << " was still " << o.state << "\n";
    return kExitFailed;
  } catch (const CommandExit& e) {
    return report_failure(command.json, e.code, e.message, out, err);
  }
}

}  // namespace fleet::cli
