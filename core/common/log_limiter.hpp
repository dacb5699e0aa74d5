#pragma once

#include <limits>
#include <string>
#include <unordered_map>

namespace fleet {

/// Rate limit of a warning that every sample of a bad sender would repeat: per key (a sender and
/// what is wrong), the first is logged, the next ones are counted, and once `interval_s` has passed
/// since the last line for that key, the next one is logged with the count of those held back.
class LogLimiter {
 public:
  explicit LogLimiter(double interval_s) : interval_s_(interval_s) {}

  /// Whether to log the warning `key` at `now_s` (any monotonic seconds); when it is, `held_back`
  /// says how many of its kind were not logged since the last line.
  bool allow(const std::string& key, double now_s, long& held_back) {
    Entry& entry = entries_[key];
    if (now_s - entry.last_logged_s < interval_s_) {
      ++entry.held_back;
      return false;
    }
    held_back = entry.held_back;
    entry.held_back = 0;
    entry.last_logged_s = now_s;
    return true;
  }

 private:
  struct Entry {
    double last_logged_s = -std::numeric_limits<double>::infinity();
    long held_back = 0;
  };
  double interval_s_;
  std::unordered_map<std::string, Entry> entries_;
};

}  // namespace fleet
