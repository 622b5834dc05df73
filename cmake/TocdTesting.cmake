include(GoogleTest)

# Labels whose test executables a build leaves out: defined (so later target_* calls still
# apply) but neither built by default nor registered with ctest. The sanitize preset sets
# "physics;physics-long;soak", the labels its test preset never runs, so the sanitizer stage
# does not compile suites it would not run.
set(TOCD_SKIP_TEST_LABELS "" CACHE STRING "Test labels whose executables are not built or registered")

# tocd_add_gtest(<target> LABEL <unit|integration|physics|physics-long> SOURCES <files...>
#                [LIBS <targets...>] [TIMEOUT <seconds>] [SERIAL])
# One test executable carries one label; ctest discovers its cases at test time. Every test
# links tests/support (tocd/test/...: temporary directories, files, the CLI runner).
# The default run (`ctest --preset dev`) runs every label except physics-long.
# SERIAL: ctest runs the cases alone, never beside another test (for a test that sets up a
# load of its own and claims to hold under exactly that load).
function(tocd_add_gtest target)
  cmake_parse_arguments(ARG "SERIAL" "LABEL;TIMEOUT" "SOURCES;LIBS" ${ARGN})
  if(NOT ARG_LABEL MATCHES "^(unit|integration|physics|physics-long|soak)$")
    message(FATAL_ERROR "tocd_add_gtest(${target}): LABEL must be unit, integration, physics, physics-long or soak")
  endif()
  if(NOT ARG_TIMEOUT)
    set(ARG_TIMEOUT 300)
  endif()
  set(exclude "")
  if(ARG_LABEL IN_LIST TOCD_SKIP_TEST_LABELS)
    set(exclude EXCLUDE_FROM_ALL)
  endif()
  add_executable(${target} ${exclude} ${ARG_SOURCES})
  target_link_libraries(${target} PRIVATE ${ARG_LIBS} tocd_test_support GTest::gtest GTest::gmock
                                          GTest::gtest_main tocd_warnings)
  if(exclude)
    return()
  endif()
  set(serial "")
  if(ARG_SERIAL)
    set(serial RUN_SERIAL TRUE)
  endif()
  gtest_discover_tests(${target}
    DISCOVERY_MODE PRE_TEST
    PROPERTIES LABELS ${ARG_LABEL} TIMEOUT ${ARG_TIMEOUT} ${serial}
    WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR})
endfunction()
