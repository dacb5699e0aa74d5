#pragma once
// Reading VDA 5050 JSON: each reader throws MessageError naming the key and where it sits.

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "vda5050/messages.hpp"

namespace fleet::vda5050::json_read {

const nlohmann::json& required(const nlohmann::json& object, const char* key, const std::string& where);
std::string text(const nlohmann::json& object, const char* key, const std::string& where);
/// A finite number.
double number(const nlohmann::json& object, const char* key, const std::string& where);
/// A whole number >= 0.
std::uint32_t count(const nlohmann::json& object, const char* key, const std::string& where);
/// true or false.
bool flag(const nlohmann::json& object, const char* key, const std::string& where);
const nlohmann::json& list(const nlohmann::json& object, const char* key, const std::string& where);

}  // namespace fleet::vda5050::json_read
