#pragma once

#include <string>
#include <vector>

namespace fleet::config {

enum class ValueType { Double, Int, Bool, String, Choice };

/// One configuration key, declared once with its default, unit, allowed range and meaning.
/// Everything else (validation, `fleetctl config keys`, the README table) derives from it.
struct KeySpec {
  std::string key;  ///< dotted path in fleet.yaml, e.g. "server.dispatch_policy"
  ValueType type = ValueType::Double;
  std::string default_value;
  std::string unit;                  ///< SI unit or empty
  double min = 0.0;                  ///< for Double and Int
  double max = 0.0;                  ///< for Double and Int
  std::vector<std::string> choices;  ///< for Choice
  std::string description;
};

/// The table of every key Fleet understands.
const std::vector<KeySpec>& schema();

/// Null when the key is not declared.
const KeySpec* find_key(const std::string& key);

/// A Markdown table of the schema, for the README and `fleetctl config keys`.
std::string schema_markdown();

}  // namespace fleet::config
