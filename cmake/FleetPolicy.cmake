# Shared build policy: language level, warnings, output folders, helpers for core libraries.
set(CMAKE_CXX_STANDARD 20)
set(CMAKE_CXX_STANDARD_REQUIRED ON)
set(CMAKE_CXX_EXTENSIONS OFF)
set(CMAKE_POSITION_INDEPENDENT_CODE ON)
set(CMAKE_EXPORT_COMPILE_COMMANDS ON)

if(NOT CMAKE_BUILD_TYPE AND NOT CMAKE_CONFIGURATION_TYPES)
  set(CMAKE_BUILD_TYPE Release CACHE STRING "Build type" FORCE)
endif()

option(FLEET_WARNINGS_AS_ERRORS "Treat compiler warnings as errors (CI turns this on)" OFF)
option(FLEET_BUILD_TESTS "Build unit and integration tests" ON)
option(FLEET_BUILD_BENCH "Build benchmarks" ON)
option(FLEET_BUILD_FUZZ "Build libFuzzer targets (needs clang)" ON)
# Third-party OpenDRIVE networks for the parser tests; $FLEET_TEST_DATA overrides it at test time.
set(FLEET_DEFAULT_TEST_DATA "${PROJECT_SOURCE_DIR}/../shared/data/opendrive" CACHE PATH
    "Folder of third-party OpenDRIVE files read by the parser tests (skipped when absent)")

set(CMAKE_RUNTIME_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/bin)
set(CMAKE_LIBRARY_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/lib)
set(CMAKE_ARCHIVE_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/lib)

# Warnings for the project's own targets only; third-party headers come in as SYSTEM.
add_library(fleet_warnings INTERFACE)
target_compile_options(fleet_warnings INTERFACE -Wall -Wextra -Wpedantic -Wshadow)
if(FLEET_WARNINGS_AS_ERRORS)
  target_compile_options(fleet_warnings INTERFACE -Werror)
endif()

# fleet_core_library(NAME SOURCES ... DEPS ...): a core/ concern as a static library
# named fleet_<NAME>, whose public headers are included as "<concern>/header.hpp".
function(fleet_core_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_library(fleet_${name} STATIC ${ARG_SOURCES})
  target_include_directories(fleet_${name} PUBLIC ${PROJECT_SOURCE_DIR}/core)
  target_link_libraries(fleet_${name} PUBLIC ${ARG_DEPS} PRIVATE fleet_warnings)
endfunction()

# fleet_unit_test(NAME SOURCES ... DEPS ...): a GoogleTest executable registered with ctest.
function(fleet_unit_test name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS} fleet_test_paths GTest::gtest_main fleet_warnings)
  gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60 PROPERTIES LABELS unit)
endfunction()

# fleet_test_labels(TARGET LABEL...): the labels of every test gtest_discover_tests finds in
# TARGET. Its PROPERTIES cannot carry a list (CMake 3.25 writes "a;b" as two words, the second
# taken for a property name), so the labels are set after discovery, from the test list it records.
function(fleet_test_labels target)
  list(JOIN ARGN ";" labels)
  set(script ${CMAKE_CURRENT_BINARY_DIR}/${target}_labels.cmake)
  file(WRITE ${script} "foreach(test IN LISTS ${target}_TESTS)\n"
                       "  set_tests_properties(\"\${test}\" PROPERTIES LABELS \"${labels}\")\n"
                       "endforeach()\n")
  set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES ${script})
endfunction()
