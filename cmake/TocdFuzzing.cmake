# TOCD_BUILD_FUZZ: libFuzzer targets (tests/fuzz). Every library the targets call is compiled
# with libFuzzer's coverage instrumentation (fuzzer-no-link) and with AddressSanitizer and
# UndefinedBehaviorSanitizer, so a finding inside project code is seen where it happens; UB
# aborts (no recover) so that libFuzzer records it as a crash with its input.
if(NOT TOCD_BUILD_FUZZ)
  return()
endif()
if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
  message(FATAL_ERROR "TOCD_BUILD_FUZZ needs clang (libFuzzer), not ${CMAKE_CXX_COMPILER_ID}. Configure with\n"
                      "  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ (apt-get install clang libclang-rt-14-dev)\n"
                      "or use the sanitize preset: cmake --preset sanitize")
endif()
# -fno-sanitize=vptr: UBSan's dynamic-type check looks types up at run time and reports a
# valid object as "invalid vptr" when the process is out of file descriptors (the server tests
# exhaust them on purpose); ASan still catches a use of a freed or overrun object.
add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize=vptr
                    -fno-sanitize-recover=undefined -fno-omit-frame-pointer)
add_link_options(-fsanitize=address,undefined)

# Seconds each `fuzz` test fuzzes after replaying its corpus and regression inputs.
set(TOCD_FUZZ_SECONDS 15 CACHE STRING "Seconds of fuzzing per target in the ctest `fuzz` label")
