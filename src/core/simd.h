// Whether the core compiles its SSE2 paths (a few point and voxel loops that work on two or
// four values at once). On x86-64 SSE2 is part of the base instruction set, so they are on
// unless HOPE_SCALAR_ONLY is defined (CMake option hope_SCALAR_ONLY): then the portable scalar
// paths, the ones an ARM robot (Jetson, Raspberry Pi) runs, are compiled instead, which lets
// scripts/scalar_check.sh run the tests on them here. Both give the same results bit for bit.
// 32-bit x86 takes the scalar paths too: the grid's loop moves 64-bit words between SSE and
// general registers (_mm_cvtsi64_si128), which only x86-64 has.
#pragma once

#if defined(__SSE2__) && defined(__x86_64__) && !defined(HOPE_SCALAR_ONLY)
#define HOPE_SSE2 1
#include <emmintrin.h>
#else
#define HOPE_SSE2 0
#endif
