#include "config/settings.hpp"

#include <cmath>

#include "common/args.hpp"
#include "config/schema.hpp"

namespace fleet::config {

namespace {

std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (std::size_t i = 0; i < items.size(); ++i) out += (i ? ", " : "") + items[i];
  return out;
}

}  // namespace

Settings::Settings() {
  for (const KeySpec& spec : schema()) values_[spec.key] = spec.default_value;
}

void Settings::set(const std::string& key, const std::string& value, const std::string& origin) {
  const KeySpec* spec = find_key(key);
  if (!spec) throw ConfigError(origin + ": unknown key '" + key + "'");
  auto bad = [&](const std::string& why) {
    return ConfigError(origin + ": key '" + key + "': value '" + value + "' " + why);
  };
  switch (spec->type) {
    case ValueType::kDouble:
    case ValueType::kInt: {
      const auto parsed = parse_finite(value);
      if (!parsed) throw bad("is not a finite number");
      const double v = *parsed;
      if (spec->type == ValueType::kInt && v != std::floor(v)) throw bad("is not an integer");
      if (v < spec->min || v > spec->max) {
        throw bad("is outside " + format_number(spec->min) + " .. " + format_number(spec->max) +
                  (spec->unit.empty() ? "" : " " + spec->unit));
      }
      break;
    }
    case ValueType::kBool:
      if (value != "true" && value != "false") throw bad("is not true or false");
      break;
    case ValueType::kChoice: {
      bool found = false;
      for (const auto& c : spec->choices) found = found || c == value;
      if (!found) throw bad("is not one of " + join(spec->choices));
      break;
    }
    case ValueType::kString:
      break;
  }
  values_[key] = value;
}

const std::string& Settings::raw(const std::string& key) const {
  auto it = values_.find(key);
  if (it == values_.end()) throw std::logic_error("configuration key '" + key + "' is not declared");
  return it->second;
}

double Settings::get_double(const std::string& key) const {
  return std::stod(raw(key));
}
long Settings::get_int(const std::string& key) const {
  return std::stol(raw(key));
}
bool Settings::get_bool(const std::string& key) const {
  return raw(key) == "true";
}
const std::string& Settings::get_string(const std::string& key) const {
  return raw(key);
}

}  // namespace fleet::config
