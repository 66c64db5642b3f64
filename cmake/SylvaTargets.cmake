# Helpers that keep every folder's CMakeLists short.

# sylva_library(NAME SOURCES... [DEPS ...]): a static library rooted at the repository (includes
# are spelled "pipeline/graph.h", "libs/tree/tree.h", "stages/lod/lod_core.h").
function(sylva_library name)
  cmake_parse_arguments(A "" "" "SOURCES;DEPS" ${ARGN})
  add_library(${name} STATIC ${A_SOURCES})
  target_include_directories(${name} PUBLIC ${CMAKE_SOURCE_DIR})
  target_link_libraries(${name} PUBLIC ${A_DEPS} PRIVATE sylva_warnings)
endfunction()

# sylva_test(NAME SOURCES... [DEPS ...]): a GoogleTest executable registered with ctest. Tests
# run from the repository root so recipes and fixtures are found by relative path.
function(sylva_test name)
  cmake_parse_arguments(A "" "" "SOURCES;DEPS" ${ARGN})
  add_executable(${name} ${A_SOURCES})
  target_link_libraries(${name} PRIVATE ${A_DEPS} sylva_test_support GTest::gtest GTest::gmock
                                        GTest::gtest_main sylva_warnings)
  gtest_discover_tests(${name} WORKING_DIRECTORY ${CMAKE_SOURCE_DIR}
                       PROPERTIES ENVIRONMENT "SYLVA_DATA_DIR=${SYLVA_DATA_DIR}"
                       DISCOVERY_TIMEOUT 60)
endfunction()
