# The instruction set the binaries assume, and where they choose one at run time
# (docs/building.md, "CPU baseline and dispatch").
#
# TOCD_NATIVE=ON: -march=native, every kernel compiled for the building machine alone.
# Otherwise (the default, and what the package is built with): the x86-64-v2 baseline
# (SSE4.2, POPCNT: every x86-64 CPU since 2009), and the hot kernels (Monte Carlo transport,
# FE element assembly; tocd/core/isa_dispatch.hpp) compiled also for AVX2 and AVX-512 (GCC
# function multiversioning) and chosen when the program starts. TOCD_ARCH_BASELINE picks
# another baseline ("" for the compiler's).
#
# TOCD_KERNEL_FMA: whether those kernels may fuse a*b+c into one FMA where the CPU has it.
# OFF: every product is rounded alone, so every CPU (and every version of a kernel) gives
# bit-identical answers. ON (the release preset): the AVX2/AVX-512 versions run ~8 % faster
# Monte Carlo (the packet's dependency chain is shorter), and answers on CPUs with FMA differ
# from those without in the last bits, far below the Monte Carlo error.
set(TOCD_ARCH_BASELINE "x86-64-v2" CACHE STRING "-march level of the binaries when TOCD_NATIVE is OFF (x86-64 only; empty: the compiler's default)")
option(TOCD_ISA_DISPATCH "Compile the hot kernels also for AVX2 and AVX-512 and pick one at run time (GCC, x86-64, TOCD_NATIVE=OFF)" ON)
option(TOCD_KERNEL_FMA "Let the hot kernels fuse multiply-adds (faster; answers then differ in the last bits between CPUs with and without FMA)" OFF)
# For the kernels' COMPILE_OPTIONS (sim/mc, sim/fe).
if(TOCD_KERNEL_FMA)
  set(TOCD_KERNEL_FP_CONTRACT -ffp-contract=fast)
else()
  set(TOCD_KERNEL_FP_CONTRACT -ffp-contract=off)
endif()

if(TOCD_NATIVE)
  add_compile_options(-march=native)
  return()
endif()
if(NOT CMAKE_SYSTEM_PROCESSOR MATCHES "^(x86_64|AMD64|amd64)$")
  return()
endif()
if(TOCD_ARCH_BASELINE)
  add_compile_options(-march=${TOCD_ARCH_BASELINE})
endif()
# clang 14 has no x86-64-v* clones; its builds (the sanitize preset) run the baseline code.
if(TOCD_ISA_DISPATCH AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  add_compile_definitions(TOCD_ISA_DISPATCH=1)
endif()
