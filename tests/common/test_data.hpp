#pragma once
// Third-party OpenDRIVE networks (written by other tools) that the parser tests read. They are not
// part of Fleet: the folder is $FLEET_TEST_DATA, or shared/data/opendrive beside the checkout.
// Tests over them are skipped, naming the folder, where it is absent.

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "test_paths.hpp"

namespace fleet::test {

inline std::string opendrive_test_data_dir() {
  if (const char* dir = std::getenv("FLEET_TEST_DATA"); dir && *dir) return dir;
  return default_opendrive_data();
}

inline std::string opendrive_test_file(const std::string& name) {
  return opendrive_test_data_dir() + "/" + name;
}

inline bool opendrive_test_data_present() {
  return std::filesystem::is_directory(opendrive_test_data_dir());
}

}  // namespace fleet::test

/// Ends the current test as skipped when the third-party OpenDRIVE folder is absent.
#define FLEET_SKIP_WITHOUT_OPENDRIVE_DATA()                                                             \
  if (!::fleet::test::opendrive_test_data_present())                                                    \
  GTEST_SKIP() << "third-party OpenDRIVE files not found: " << ::fleet::test::opendrive_test_data_dir() \
               << " is absent (set FLEET_TEST_DATA to the folder holding them)"
