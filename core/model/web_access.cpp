#include "model/web_access.hpp"

#include <algorithm>

namespace fleet::model {

bool same_token(const std::string& given, const std::string& expected) {
  unsigned char diff = given.size() == expected.size() ? 0 : 1;
  for (std::size_t i = 0; i < given.size(); ++i) {
    diff |= static_cast<unsigned char>(given[i] ^ expected[i % std::max<std::size_t>(expected.size(), 1)]);
  }
  return diff == 0 && !expected.empty();
}

WebRole role_of(const std::string& given, const WebTokens& tokens) {
  // Both comparisons always run: which one matched must not show in the time taken either.
  const bool is_operator = same_token(given, tokens.operator_token);
  const bool is_viewer = same_token(given, tokens.viewer);
  if (is_operator) return WebRole::kOperator;
  return is_viewer ? WebRole::kViewer : WebRole::kNone;
}

bool allows(WebRole role, WebRole needed) {
  return static_cast<int>(role) >= static_cast<int>(needed);
}

const char* to_string(WebRole role) {
  switch (role) {
    case WebRole::kViewer:
      return "viewer";
    case WebRole::kOperator:
      return "operator";
    case WebRole::kNone:
      break;
  }
  return "none";
}

std::chrono::milliseconds FailedLogins::failed(const std::string& address, Clock::time_point now) {
  std::lock_guard lock(mutex_);
  ++total_;
  // Forgotten addresses go, so that a scan from many addresses cannot grow the map for good.
  std::erase_if(by_address_, [&](const auto& entry) { return now - entry.second.last > settings_.forget_after; });
  Record& record = by_address_[address];
  record.in_a_row = std::min(record.in_a_row + 1, 30);
  record.last = now;
  const auto doubled = settings_.first_delay * (std::int64_t{1} << std::min(record.in_a_row - 1, 20));
  return std::min(doubled, settings_.longest_delay);
}

void FailedLogins::succeeded(const std::string& address) {
  std::lock_guard lock(mutex_);
  by_address_.erase(address);
}

std::uint64_t FailedLogins::total() const {
  std::lock_guard lock(mutex_);
  return total_;
}

int FailedLogins::in_a_row(const std::string& address, Clock::time_point now) const {
  std::lock_guard lock(mutex_);
  const auto it = by_address_.find(address);
  if (it == by_address_.end() || now - it->second.last > settings_.forget_after) return 0;
  return it->second.in_a_row;
}

}  // namespace fleet::model
