#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/errors.hpp"

namespace fleet {

/// A command-line error; the message names the flag and value. Programs exit 2 on it.
class ArgError : public InputError {
 public:
  using InputError::InputError;
};

// The number parsers of every Fleet program: the whole text or nothing, no leading blanks or
// signs beyond a minus, no locale.

/// A number as a person writes it in a message: 232, 0.5, 1e-06 (never 232.000000).
std::string format_number(double value);

/// The whole of `text` as a finite number; nothing when it is not one.
std::optional<double> parse_finite(const std::string& text);
/// The whole of `text` as an integer (a minus allowed); nothing when it is not one or out of range.
std::optional<long> parse_long(const std::string& text);
/// The whole of `text` as a non-negative integer (digits only); nothing when it is not one or out
/// of range.
std::optional<std::uint64_t> parse_u64(const std::string& text);
/// The value `text` of flag --`name` as a non-negative integer; ArgError naming the flag and the
/// value when it is not one.
std::uint64_t parse_u64(const std::string& name, const std::string& text);

/// Whether a command-line word is a flag: a dash and more, but not a negative number ("-3", "-.5").
bool looks_like_flag(const std::string& word);

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
  /// The value of --name, left in the list; nothing when absent or without a value.
  std::optional<std::string> peek(const std::string& name) const;
  /// Whether --name is present (removed from the list).
  bool flag(const std::string& name);

  /// Parsed numbers, with ArgError naming the flag when the text is not a number or out of range.
  std::optional<double> number(const std::string& name, double min, double max);
  std::optional<long> integer(const std::string& name, long min, long max);
  /// A non-negative integer of the whole 64-bit range (seeds).
  std::optional<std::uint64_t> u64(const std::string& name);

  /// The remaining arguments; ArgError if any of them still looks like a flag.
  std::vector<std::string> positionals() const;
  const std::vector<std::string>& remaining() const { return args_; }

 private:
  std::vector<std::string> args_;
};

}  // namespace fleet
