// Loops over many right-hand sides at once (a year's hours) are compiled twice: for the baseline
// x86-64 and for x86-64-v3 (AVX2, FMA), the loader picking the one the processor runs (GCC's
// target_clones), so one binary serves every machine and uses wide vectors where they exist. The
// level is dispatched on the processor's features; "arch=haswell" was dispatched on its model (run
// on Haswells alone), and "avx2,fma" would make two clones (the comma separates them).
#pragma once

/// HEMIRAD_WIDE_KERNEL on a function: its clones. HEMIRAD_INLINE_KERNEL on what it calls: inlined
/// into each clone, so compiled for its target too.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define HEMIRAD_WIDE_KERNEL __attribute__((target_clones("default", "arch=x86-64-v3")))
#define HEMIRAD_INLINE_KERNEL inline __attribute__((always_inline))
#else
#define HEMIRAD_WIDE_KERNEL
#define HEMIRAD_INLINE_KERNEL inline
#endif
