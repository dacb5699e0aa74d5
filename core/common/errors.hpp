#pragma once

#include <stdexcept>

namespace fleet {

/// Bad input from a person or a file: a flag, a configuration key, a map, a database path. Every
/// Fleet program answers it with its message, which names the file, key or value, and exit code 2.
/// Other failures are std::exceptions of other kinds and exit 1.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace fleet
