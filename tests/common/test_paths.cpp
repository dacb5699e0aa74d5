#include "test_paths.hpp"

namespace fleet::test {

const std::string& source_dir() {
  static const std::string dir = FLEET_SOURCE_DIR;
  return dir;
}

std::string source_path(const std::string& relative) {
  return source_dir() + relative;
}

const std::string& bin_dir() {
  static const std::string dir = FLEET_BIN_DIR;
  return dir;
}

const std::string& default_opendrive_data() {
  static const std::string dir = FLEET_DEFAULT_TEST_DATA;
  return dir;
}

}  // namespace fleet::test
