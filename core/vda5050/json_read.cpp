#include "vda5050/json_read.hpp"

#include <cmath>

namespace fleet::vda5050::json_read {

using nlohmann::json;

const json& required(const json& object, const char* key, const std::string& where) {
  const auto it = object.find(key);
  if (it == object.end() || it->is_null()) throw MessageError(where + ": key '" + key + "' is missing");
  return *it;
}

std::string text(const json& object, const char* key, const std::string& where) {
  const json& value = required(object, key, where);
  if (!value.is_string()) throw MessageError(where + ": key '" + key + "' must be a string, not " + value.dump());
  return value.get<std::string>();
}

double number(const json& object, const char* key, const std::string& where) {
  const json& value = required(object, key, where);
  if (!value.is_number()) throw MessageError(where + ": key '" + key + "' must be a number, not " + value.dump());
  const double v = value.get<double>();
  if (!std::isfinite(v)) throw MessageError(where + ": key '" + key + "' is not finite");
  return v;
}

std::uint32_t count(const json& object, const char* key, const std::string& where) {
  const json& value = required(object, key, where);
  if (!value.is_number_unsigned() && !(value.is_number_integer() && value.get<std::int64_t>() >= 0)) {
    throw MessageError(where + ": key '" + key + "' must be a whole number >= 0, not " + value.dump());
  }
  return value.get<std::uint32_t>();
}

bool flag(const json& object, const char* key, const std::string& where) {
  const json& value = required(object, key, where);
  if (!value.is_boolean()) throw MessageError(where + ": key '" + key + "' must be true or false");
  return value.get<bool>();
}

const json& list(const json& object, const char* key, const std::string& where) {
  const json& value = required(object, key, where);
  if (!value.is_array()) throw MessageError(where + ": key '" + key + "' must be a list");
  return value;
}

}  // namespace fleet::vda5050::json_read
