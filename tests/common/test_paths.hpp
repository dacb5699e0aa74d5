#pragma once
// Where the checkout, the built binaries and the third-party test data are, as configured. They are
// compiled into one translation unit (test_paths.cpp) only: every other test file compiles the same
// wherever the checkout lies, so a compiler cache serves them to every clone.

#include <string>

namespace fleet::test {

/// The checkout's root directory.
const std::string& source_dir();
/// A path inside the checkout: `relative` starts with '/' ("/maps/table_a.yaml").
std::string source_path(const std::string& relative);
/// The directory the Fleet executables are built into.
const std::string& bin_dir();
/// The third-party OpenDRIVE folder beside the checkout (FLEET_DEFAULT_TEST_DATA at configure time).
const std::string& default_opendrive_data();

}  // namespace fleet::test
