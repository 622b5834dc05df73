include(GoogleTest)

# tocd_add_gtest(<target> LABEL <unit|integration|physics|physics-long> SOURCES <files...>
#                [LIBS <targets...>] [TIMEOUT <seconds>] [SANITIZE_SKIP])
# One test executable carries one label; ctest discovers its cases at test time.
# The default run (`ctest --preset dev`) runs every label except physics-long.
# SANITIZE_SKIP adds the label `sanitize-skip`, which only the sanitize preset leaves out: for
# pure high-statistics physics that AddressSanitizer would slow beyond the CI budget
# (docs/building.md lists them).
function(tocd_add_gtest target)
  cmake_parse_arguments(ARG "SANITIZE_SKIP" "LABEL;TIMEOUT" "SOURCES;LIBS" ${ARGN})
  if(NOT ARG_LABEL MATCHES "^(unit|integration|physics|physics-long)$")
    message(FATAL_ERROR "tocd_add_gtest(${target}): LABEL must be unit, integration, physics or physics-long")
  endif()
  if(NOT ARG_TIMEOUT)
    set(ARG_TIMEOUT 300)
  endif()
  add_executable(${target} ${ARG_SOURCES})
  target_link_libraries(${target} PRIVATE ${ARG_LIBS} GTest::gtest GTest::gmock GTest::gtest_main
                                          tocd_warnings)
  set(labels ${ARG_LABEL})
  if(ARG_SANITIZE_SKIP)
    # Escaped: the discovered tests' properties pass through one more list expansion.
    set(labels "${ARG_LABEL}\\;sanitize-skip")
  endif()
  gtest_discover_tests(${target}
    DISCOVERY_MODE PRE_TEST
    PROPERTIES LABELS ${labels} TIMEOUT ${ARG_TIMEOUT}
    WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR})
endfunction()
