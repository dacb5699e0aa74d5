#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <limits>
#include <string_view>

namespace fleet::planning {

/// Outcome of one planning query. Expected outcomes are statuses, never exceptions (STYLE 7).
enum class PlanStatus {
  kFound,           ///< a complete path from start to goal
  kBlockedPartial,  ///< every route is blocked; the path ends at the last free point before the block
  kNoPath,          ///< the search space holds no route at all
  kTimeout,         ///< the time budget or node cap ran out first
  kCancelled,       ///< the caller raised the cancel flag
  kInvalidStart,    ///< start or goal outside the map or inside an obstacle
};

constexpr std::string_view to_string(PlanStatus s) {
  switch (s) {
    case PlanStatus::kFound:
      return "FOUND";
    case PlanStatus::kBlockedPartial:
      return "BLOCKED_PARTIAL";
    case PlanStatus::kNoPath:
      return "NO_PATH";
    case PlanStatus::kTimeout:
      return "TIMEOUT";
    case PlanStatus::kCancelled:
      return "CANCELLED";
    case PlanStatus::kInvalidStart:
      return "INVALID_START";
  }
  return "UNKNOWN";
}

/// Per-query settings (STYLE 5-6): the planner's Configuration stays fixed, these change per call.
struct PlanOptions {
  std::chrono::microseconds time_budget{std::chrono::seconds(1)};
  std::size_t node_cap = std::numeric_limits<std::size_t>::max();
  const std::atomic<bool>* cancel = nullptr;  ///< polled while searching; may be raised from another thread
};

/// Polls the budget and the cancel flag. Reading the clock costs tens of nanoseconds, so callers
/// in tight loops ask only every `stride` iterations.
class Deadline {
 public:
  using Clock = std::chrono::steady_clock;

  explicit Deadline(const PlanOptions& options)
      : start_(Clock::now()), end_(start_ + options.time_budget), cancel_(options.cancel) {}

  bool cancelled() const { return cancel_ != nullptr && cancel_->load(std::memory_order_relaxed); }
  bool expired() const { return Clock::now() >= end_; }
  Clock::time_point start() const { return start_; }
  Clock::time_point end() const { return end_; }
  double elapsed_ms() const { return std::chrono::duration<double, std::milli>(Clock::now() - start_).count(); }
  /// kFound when the search may go on, else the status to stop with.
  PlanStatus check() const {
    if (cancelled()) return PlanStatus::kCancelled;
    if (expired()) return PlanStatus::kTimeout;
    return PlanStatus::kFound;
  }

 private:
  Clock::time_point start_;
  Clock::time_point end_;
  const std::atomic<bool>* cancel_;
};

}  // namespace fleet::planning
