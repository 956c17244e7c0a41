// The instruction set a translation unit is compiled for, as a namespace name: TRIPSITTER_RENDER_ISA is avx2,
// avx or sse2 (baseline x86-64).
//
// Why: the render library is compiled for x86-64-v3 (CMake option TRIPSITTER_X86_64_V3) and the programs and
// tests that link it for baseline x86-64. A header's inline function compiled both ways would be two different
// functions under one name, and the linker keeps one of them for every caller: AVX code in a program meant for
// any x86-64, or a struct laid out for one set read as the other. Headers whose inline code depends on the
// instruction set (simd8.h, sphere_lanes.h, ray_sphere.h) therefore open `inline namespace TRIPSITTER_RENDER_ISA`:
// each instruction set gets its own names, and callers still write them without it.
#pragma once

#if defined(__AVX2__)
#define TRIPSITTER_RENDER_ISA avx2
#elif defined(__AVX__)
#define TRIPSITTER_RENDER_ISA avx
#else
#define TRIPSITTER_RENDER_ISA sse2
#endif
