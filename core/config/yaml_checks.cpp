#include "config/yaml_checks.hpp"

#include <cmath>

#include "config/settings.hpp"

namespace fleet::config::yaml {

std::string where(const std::string& source, const YAML::Node& node) {
  return source + ":" + std::to_string(node.Mark().line + 1);
}

double finite_number(const YAML::Node& node, const std::string& key, const std::string& source) {
  if (!node || !node.IsScalar()) throw ConfigError(source + ": key '" + key + "' is missing");
  double v = 0.0;
  try {
    v = node.as<double>();
  } catch (const YAML::Exception&) {
    throw ConfigError(where(source, node) + ": key '" + key + "': '" + node.Scalar() + "' is not a number");
  }
  if (!std::isfinite(v)) {
    throw ConfigError(where(source, node) + ": key '" + key + "': '" + node.Scalar() + "' is not a finite number");
  }
  return v;
}

double positive_number(const YAML::Node& node, const std::string& key, const std::string& source) {
  const double v = finite_number(node, key, source);
  if (!(v > 0.0)) {
    throw ConfigError(where(source, node) + ": key '" + key + "': '" + node.Scalar() + "' must be positive");
  }
  return v;
}

double non_negative_number(const YAML::Node& node, const std::string& key, const std::string& source) {
  const double v = finite_number(node, key, source);
  if (!(v >= 0.0)) {
    throw ConfigError(where(source, node) + ": key '" + key + "': '" + node.Scalar() + "' must not be negative");
  }
  return v;
}

std::string required_text(const YAML::Node& map, const std::string& name, const std::string& key,
                          const std::string& source) {
  const YAML::Node node = map[name];
  if (!node || !node.IsScalar() || node.Scalar().empty()) {
    throw ConfigError(where(source, map) + ": key '" + key + "." + name + "' is missing");
  }
  return node.Scalar();
}

void check_keys(const YAML::Node& map, const std::set<std::string>& allowed, const std::string& key,
                const std::string& source) {
  for (const auto& item : map) {
    const std::string name = item.first.as<std::string>();
    if (!allowed.contains(name)) {
      throw ConfigError(where(source, item.first) + ": unknown key '" + key + "." + name + "'");
    }
  }
}

}  // namespace fleet::config::yaml
