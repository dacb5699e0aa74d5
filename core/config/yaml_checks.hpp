#pragma once

#include <yaml-cpp/yaml.h>

#include <set>
#include <string>

namespace fleet::config::yaml {

/// "file:line" of a node, for messages.
std::string where(const std::string& source, const YAML::Node& node);

/// A finite number at `node`; ConfigError naming `key` otherwise.
double finite_number(const YAML::Node& node, const std::string& key, const std::string& source);

/// A positive finite number at `node`; ConfigError naming `key` otherwise.
double positive_number(const YAML::Node& node, const std::string& key, const std::string& source);

/// A finite number >= 0 at `node`; ConfigError naming `key` otherwise.
double non_negative_number(const YAML::Node& node, const std::string& key, const std::string& source);

/// The non-empty text `map[name]`; ConfigError naming `key.name` when it is missing.
std::string required_text(const YAML::Node& map, const std::string& name, const std::string& key,
                          const std::string& source);

/// ConfigError naming the first key of `map` not in `allowed`.
void check_keys(const YAML::Node& map, const std::set<std::string>& allowed, const std::string& key,
                const std::string& source);

}  // namespace fleet::config::yaml
