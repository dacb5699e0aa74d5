#include "server/web_gate.hpp"

#include <httplib.h>

#include <chrono>
#include <thread>

#include "server/web_http.hpp"

namespace fleet::server {

WebGate::WebGate(model::WebTokens tokens, Logger log) : tokens_(std::move(tokens)), log_(std::move(log)) {}

bool WebGate::admit(const httplib::Request& req, httplib::Response& res, model::WebRole needed) {
  std::string given;
  const std::string header = req.get_header_value("Authorization");
  if (header.rfind("Bearer ", 0) == 0) {
    given = header.substr(7);
  } else if (req.has_param("token")) {
    given = req.get_param_value("token");
  }
  if (given.empty()) {
    res.set_header("WWW-Authenticate", "Bearer");
    refuse(req, res, 401, "missing; send 'Authorization: Bearer TOKEN' or ?token=TOKEN");
    return false;
  }
  const model::WebRole role = model::role_of(given, tokens_);
  if (role == model::WebRole::kNone) {
    refuse(req, res, 403, "wrong token");
    return false;
  }
  logins_.succeeded(req.remote_addr);
  if (!model::allows(role, needed)) {
    // A known token without the right: no guess, so no delay.
    send_error(res, 403, "token",
               std::string("the ") + model::to_string(role) + "'s token does not allow " + req.method + " " + req.path +
                   "; the " + model::to_string(needed) + "'s does");
    return false;
  }
  return true;
}

void WebGate::refuse(const httplib::Request& req, httplib::Response& res, int status, const std::string& message) {
  const auto delay = logins_.failed(req.remote_addr, std::chrono::steady_clock::now());
  {
    std::lock_guard lock(log_mutex_);
    long held_back = 0;
    const double now_s = std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
    if (log_limiter_.allow(req.remote_addr, now_s, held_back)) {
      log_->warn("web: authentication failed from {} ({} {}: token {}){}", req.remote_addr, req.method, req.path,
                 status == 401 ? "missing" : "wrong",
                 held_back > 0 ? fmt::format("; {} more since the last line", held_back) : std::string());
    }
  }
  std::this_thread::sleep_for(delay);
  send_error(res, status, "token", message);
}

}  // namespace fleet::server
