#pragma once
// GIBENCH_SIMD_CLONES marks a function whose loops run across SIMD lanes. GCC then compiles it
// for AVX2 (8 float lanes) as well as for Debian's x86-64 baseline (SSE2, 4 lanes), and the loader
// picks the AVX2 version on machines that have it (function multiversioning, target_clones).
// AVX2 only, not FMA: a clone must round exactly as the baseline does, since what it computes is
// compared bit for bit with scalar code (a fused multiply-add would round differently).

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define GIBENCH_SIMD_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define GIBENCH_SIMD_CLONES
#endif
