#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>

namespace fleet::model {

/// What a web view token lets its bearer do.
enum class WebRole {
  kNone,      ///< no token, or one that is neither of the two
  kViewer,    ///< the page, GET and the event stream
  kOperator,  ///< everything a viewer may, and every change (orders, obstacles, maps, robots)
};

/// The two tokens of the web view. The operator's also opens what the viewer's does.
struct WebTokens {
  std::string viewer;
  std::string operator_token;
};

/// Compares without an early exit, so the time taken does not tell how much of a guess matched.
bool same_token(const std::string& given, const std::string& expected);

/// The role `given` opens; both tokens are always compared, in constant time each.
WebRole role_of(const std::string& given, const WebTokens& tokens);

/// Whether `role` may do what needs `needed`.
bool allows(WebRole role, WebRole needed);

const char* to_string(WebRole role);

/// Failed authentications per client address, each answered after a delay that doubles with the
/// address's failures in a row (so guessing a token costs time that grows with the guesses). A
/// success clears the address; an address quiet for `forget_after` starts afresh. Thread-safe:
/// the web view's request threads share one.
class FailedLogins {
 public:
  using Clock = std::chrono::steady_clock;
  struct Settings {
    std::chrono::milliseconds first_delay{100};
    std::chrono::milliseconds longest_delay{5000};
    std::chrono::seconds forget_after{600};
  };
  FailedLogins() : FailedLogins(Settings{}) {}
  explicit FailedLogins(Settings settings) : settings_(settings) {}

  /// Counts a failure from `address` at `now`; how long its answer waits.
  std::chrono::milliseconds failed(const std::string& address, Clock::time_point now);
  /// A good token from `address`: its failures in a row are cleared.
  void succeeded(const std::string& address);
  /// Failures counted since start, from every address.
  std::uint64_t total() const;
  /// Failures in a row of `address` as of `now`.
  int in_a_row(const std::string& address, Clock::time_point now) const;

 private:
  struct Record {
    int in_a_row = 0;
    Clock::time_point last;
  };
  Settings settings_;
  mutable std::mutex mutex_;
  std::map<std::string, Record> by_address_;
  std::uint64_t total_ = 0;
};

}  // namespace fleet::model
