#pragma once
// Who may use the web view: the viewer's token opens the API's reading calls and the event
// stream, the operator's every call. A failure is answered after a delay that grows with the
// client address's failures in a row (model::FailedLogins), counted and logged at a limited rate.

#include <cstdint>
#include <mutex>
#include <string>

#include "common/log_limiter.hpp"
#include "common/logging.hpp"
#include "model/web_access.hpp"

namespace httplib {
struct Request;
struct Response;
}  // namespace httplib

namespace fleet::server {

class WebGate {
 public:
  WebGate(model::WebTokens tokens, Logger log);

  /// Whether the request's token ('Authorization: Bearer TOKEN' or ?token=TOKEN) opens `needed`;
  /// when not, answers 401 (no token) or 403 (a token that does not open it) after the delay.
  bool admit(const httplib::Request& req, httplib::Response& res, model::WebRole needed);

  /// Failed authentications since start.
  std::uint64_t failures() const { return logins_.total(); }

 private:
  void refuse(const httplib::Request& req, httplib::Response& res, int status, const std::string& message);

  model::WebTokens tokens_;
  Logger log_;
  model::FailedLogins logins_;
  std::mutex log_mutex_;
  LogLimiter log_limiter_{10.0};
};

}  // namespace fleet::server
