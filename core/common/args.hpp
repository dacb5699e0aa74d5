#pragma once

#include <optional>

#include "common/errors.hpp"
#include <stdexcept>
#include <string>
#include <vector>

namespace fleet {

/// A command-line error; the message names the flag and value. Programs exit 2 on it.
class ArgError : public InputError {
 public:
  using InputError::InputError;
};

/// The whole of `text` as a finite number; nothing when it is not one.
std::optional<double> parse_finite(const std::string& text);

/// Takes flags out of an argument list one by one; what remains is positional. Accepts
/// `--name value` and `--name=value`.
class Args {
 public:
  explicit Args(std::vector<std::string> args) : args_(std::move(args)) {}
  Args(int argc, char** argv, int first = 1) {
    for (int i = first; i < argc; ++i) args_.emplace_back(argv[i]);
  }

  /// The value of --name, removed from the list; nothing when absent; ArgError when the value is missing.
  std::optional<std::string> value(const std::string& name);
  /// Whether --name is present (removed from the list).
  bool flag(const std::string& name);

  /// Parsed numbers, with ArgError naming the flag when the text is not a number or out of range.
  std::optional<double> number(const std::string& name, double min, double max);
  std::optional<long> integer(const std::string& name, long min, long max);

  /// The remaining arguments; ArgError if any of them still looks like a flag.
  std::vector<std::string> positionals() const;
  const std::vector<std::string>& remaining() const { return args_; }

 private:
  std::vector<std::string> args_;
};

}  // namespace fleet
