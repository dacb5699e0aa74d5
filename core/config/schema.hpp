#pragma once

#include <string>
#include <vector>

namespace fleet::config {

enum class ValueType { kDouble, kInt, kBool, kString, kChoice };

/// One configuration key, declared once with its default, unit, allowed range and meaning.
/// Everything else (validation, `fleetctl config keys`, the README table) derives from it.
struct KeySpec {
  std::string key;  ///< dotted path in fleet.yaml, e.g. "server.dispatch_policy"
  ValueType type = ValueType::kDouble;
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

/// The header of the Markdown table of keys: key, default, unit, allowed, meaning.
inline constexpr const char* kMarkdownHeader = "| key | default | unit | allowed | meaning |\n|---|---|---|---|---|\n";

/// One key as a row of that table.
std::string markdown_row(const KeySpec& spec);

/// A Markdown table of the schema, printed by `fleetctl config keys`.
std::string schema_markdown();

/// docs/configuration.md: how keys are set, then one table per section (server, agent, ...),
/// printed by `fleetctl config keys --markdown`.
std::string configuration_page();

}  // namespace fleet::config
