#pragma once

#include <map>
#include <stdexcept>
#include <string>

#include "common/errors.hpp"

namespace fleet::config {

/// A configuration or input error; the message names the file, key and value.
class ConfigError : public InputError {
 public:
  using InputError::InputError;
};

/// Values of the declared keys (see schema.hpp), defaults filled in. Every value is checked
/// against its declaration when set, so a Settings object never holds an invalid value.
class Settings {
 public:
  Settings();

  /// Sets a key from text. `origin` names where the value came from (a file, "--flag") and is
  /// used in the error message. Throws ConfigError for unknown keys and invalid values.
  void set(const std::string& key, const std::string& value, const std::string& origin);

  double get_double(const std::string& key) const;
  long get_int(const std::string& key) const;
  bool get_bool(const std::string& key) const;
  const std::string& get_string(const std::string& key) const;

  const std::map<std::string, std::string>& values() const { return values_; }

 private:
  const std::string& raw(const std::string& key) const;
  std::map<std::string, std::string> values_;
};

}  // namespace fleet::config
