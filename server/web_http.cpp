#include "server/web_http.hpp"

#include <algorithm>

#include "model/names.hpp"

namespace fleet::server {

using nlohmann::json;

void send_json(httplib::Response& res, int status, const json& body) {
  res.status = status;
  res.set_content(body.dump(), "application/json");
}

void send_error(httplib::Response& res, int status, const std::string& field, const std::string& message) {
  json body{{"error", field.empty() ? message : field + ": " + message}};
  if (!field.empty()) body["field"] = field;
  send_json(res, status, body);
}

std::optional<json> body_object(const httplib::Request& req, httplib::Response& res) {
  if (req.body.empty()) return json::object();
  json body = json::parse(req.body, nullptr, false);
  if (body.is_discarded() || !body.is_object()) {
    send_error(res, 400, "body", "not a JSON object");
    return std::nullopt;
  }
  return body;
}

std::string quoted_excerpt(const json& value) {
  constexpr std::size_t kLongest = 60;
  std::string text = value.dump(-1, ' ', false, json::error_handler_t::replace);
  if (text.size() > kLongest) text = text.substr(0, kLongest) + "... (" + std::to_string(text.size()) + " bytes)";
  return text;
}

std::optional<std::string> string_field(const json& body, const char* name, bool required, httplib::Response& res,
                                        std::size_t max_length) {
  const auto it = body.find(name);
  if (it == body.end() || it->is_null()) {
    if (required) {
      send_error(res, 400, name, "missing");
      return std::nullopt;
    }
    return std::string();
  }
  if (!it->is_string()) {
    send_error(res, 400, name, "must be a string, got " + quoted_excerpt(*it));
    return std::nullopt;
  }
  if (it->get_ref<const std::string&>().size() > max_length) {
    send_error(res, 400, name,
               "longer than " + std::to_string(max_length) + " bytes (" +
                   std::to_string(it->get_ref<const std::string&>().size()) + ")");
    return std::nullopt;
  }
  if (required && it->get<std::string>().empty()) {
    send_error(res, 400, name, "must not be empty");
    return std::nullopt;
  }
  return it->get<std::string>();
}

std::optional<bool> bool_field(const json& body, const char* name, httplib::Response& res) {
  const auto it = body.find(name);
  if (it == body.end()) {
    send_error(res, 400, name, "missing (true or false)");
    return std::nullopt;
  }
  if (!it->is_boolean()) {
    send_error(res, 400, name, "must be true or false, got " + quoted_excerpt(*it));
    return std::nullopt;
  }
  return it->get<bool>();
}

bool only_fields(const json& body, std::initializer_list<const char*> allowed, httplib::Response& res) {
  for (const auto& [key, value] : body.items()) {
    if (std::none_of(allowed.begin(), allowed.end(), [&](const char* name) { return key == name; })) {
      const std::string named = key.size() > kMaxNameLength ? key.substr(0, kMaxNameLength) + "..." : key;
      send_error(res, 400, named, "unknown field; the fields are " + model::join({allowed.begin(), allowed.end()}));
      return false;
    }
  }
  return true;
}

bool announces_body(const httplib::Request& req) {
  return req.has_header("Content-Length") || req.has_header("Transfer-Encoding");
}

}  // namespace fleet::server
