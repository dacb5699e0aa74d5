#pragma once

#include <cstdint>
#include <iosfwd>
#include <map>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "model/messages.hpp"

namespace fleet::cli {

/// Per loading area, what will stand there once every open order is done: a pallet standing
/// there now, minus open orders taking it away, plus open orders bringing one. This is the
/// server's own acceptance rule (an order may pick where the balance is above 0 and drop where it
/// is 0 or below), computed from what the server publishes (PalletTruth, OrderInfo). It does not
/// change when an order completes, only when one fails or another client orders.
using AreaBalance = std::map<std::string, int>;

AreaBalance area_balance(const std::vector<std::string>& areas, const std::map<int, model::PalletTruth>& pallets,
                         const std::map<std::int64_t, model::OrderInfo>& orders);

/// Whether the server would accept pick -> drop on `balance` (names known, distinct, a pallet to
/// pick, room to drop); the reason when not.
std::optional<std::string> refusal_reason(const AreaBalance& balance, const std::string& pick, const std::string& drop);

/// Books pick -> drop into `balance` as the server will once the order exists.
void book_order(AreaBalance& balance, const std::string& pick, const std::string& drop);

struct PlannedOrder {
  std::string pick_area;
  std::string drop_area;
  int priority = 0;
  double delay_s = 0.0;  ///< wall seconds after the previous order was sent (files)
  int line = 0;          ///< line in the file, 0 for random orders
};

/// A random valid order on `balance`: an area holding a pallet no open order takes, to an area
/// that stays free. Both come from `rng` drawn in a fixed way (no std distributions, whose
/// algorithms differ between standard libraries), so a seed gives the same orders on the same
/// fleet state. Nothing when no valid pair exists.
std::optional<PlannedOrder> draw_order(const AreaBalance& balance, std::mt19937_64& rng);

/// Random distinct areas, for when the server publishes no pallet state: the server then refuses
/// or queues them by its own rule.
std::optional<PlannedOrder> draw_any_order(const std::vector<std::string>& areas, std::mt19937_64& rng);

/// --rate: "N/min", "N/s" or "N/h"; orders per wall second. ArgError when malformed or not positive.
double parse_rate(const std::string& text);

/// One problem in an orders file, with its line (1-based).
struct RowProblem {
  int line = 0;
  std::string message;
};

/// An orders file read whole: the rows, and every problem found in them.
struct OrdersFile {
  std::vector<PlannedOrder> rows;
  std::vector<RowProblem> problems;
};

/// Reads CSV rows `from,to,priority,delay_s`. Blank lines and lines starting with '#' are
/// skipped; a first row `from,to,priority,delay_s` is a header. Fields may be padded with spaces.
/// Finds wrong column counts, numbers that are not numbers (priority an integer in -1000 .. 1000,
/// delay_s seconds >= 0) and from == to.
OrdersFile parse_orders_csv(std::istream& in);

/// Checks parsed rows against the server: unknown areas (named, with the valid or closest ones)
/// and, when `balance` is given, that each row in turn finds a pallet to pick and a free area to
/// drop to after the rows before it (the server would refuse it otherwise).
std::vector<RowProblem> check_orders_against_site(const std::vector<PlannedOrder>& rows,
                                                  const std::vector<std::string>& areas,
                                                  std::optional<AreaBalance> balance);

}  // namespace fleet::cli
