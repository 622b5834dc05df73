#pragma once
// Run-time dispatch of the hot kernels (docs/building.md, "CPU baseline and dispatch"). A
// kernel is written once as an always-inline body and defined three times, each a thin
// definition marked TOCD_ISA_V4, TOCD_ISA_V3 and TOCD_ISA_BASE that calls the body; GCC's
// function multiversioning compiles the body into each and picks, when the program starts,
// the best version the CPU has. So a package built for the x86-64-v2 baseline
// (cmake/TocdArch.cmake) still runs its kernels with AVX2 or AVX-512.
//
// The versions name ISA extensions, not `arch=` levels: GCC inlines a callee (std::min, an
// Eigen product) only into a caller of the same arch, and the kernels are fast only when all
// of it inlines into each version. AVX-512 comes with VL, BW and DQ: with AVX512F alone GCC
// widened the (then four-lane) kernel's selects to 512-bit masked code, 30 % slower than AVX2.
//
// Where the build has no dispatch (TOCD_NATIVE, clang, another architecture) TOCD_ISA_V4 and
// TOCD_ISA_V3 are not defined and TOCD_ISA_BASE is empty: one version, for the build's flags.
#if defined(TOCD_ISA_DISPATCH) && defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define TOCD_ISA_VERSIONS 1
#define TOCD_ISA_V4 __attribute__((target("avx512f,avx512vl,avx512bw,avx512dq,avx512cd,avx2,fma,bmi,bmi2")))
#define TOCD_ISA_V3 __attribute__((target("avx2,fma,bmi,bmi2")))
#define TOCD_ISA_BASE __attribute__((target("default")))
#else
#define TOCD_ISA_VERSIONS 0
#define TOCD_ISA_BASE
#endif
