#pragma once
// The web API's small HTTP pieces: JSON answers and errors that name the field, the body and its
// fields read with a clear error.

#include <httplib.h>

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

namespace fleet::server {

void send_json(httplib::Response& res, int status, const nlohmann::json& body);

/// {"error": "FIELD: MESSAGE", "field": FIELD}, or {"error": MESSAGE} without a field.
void send_error(httplib::Response& res, int status, const std::string& field, const std::string& message);

/// The request body as a JSON object (an empty body is an empty object), or an error response
/// naming the body.
std::optional<nlohmann::json> body_object(const httplib::Request& req, httplib::Response& res);

/// The longest name (an area, robot, fleet, map or kind) a body may carry.
constexpr std::size_t kMaxNameLength = 200;

/// An optional string field; nullopt and an error response when it is there but not a string, or
/// longer than `max_length` bytes.
std::optional<std::string> string_field(const nlohmann::json& body, const char* name, bool required,
                                        httplib::Response& res, std::size_t max_length = kMaxNameLength);

/// A value as an error message may quote it: its JSON, cut after a few dozen characters.
std::string quoted_excerpt(const nlohmann::json& value);

/// A required boolean field; nullopt and an error response when it is missing or not a boolean.
std::optional<bool> bool_field(const nlohmann::json& body, const char* name, httplib::Response& res);

/// Whether every field of `body` is one of `allowed`; an error response naming the first other
/// one (and the allowed ones) when not.
bool only_fields(const nlohmann::json& body, std::initializer_list<const char*> allowed, httplib::Response& res);

/// Whether a request announces a body it will send, by Content-Length or Transfer-Encoding.
/// One that does not (curl -X POST without -d) would keep cpp-httplib reading until the client
/// hangs up; such requests are answered as if their body were empty.
bool announces_body(const httplib::Request& req);

}  // namespace fleet::server
