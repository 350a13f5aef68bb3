// How many bits of a 64-bit mask are set, with the POPCNT instruction where the CPU has one.
// On baseline x86-64, which has no POPCNT (x86-64-v2 brought it), std::popcount compiles to a
// call into libgcc (__popcountdi2, a dozen instructions and the call's); the packet walk counts
// its rays' masks at every step, and that call took 1.6-2.2% of a packet trace's time. The
// instruction is picked at run time, as the kernels' instruction set is, so that one binary
// still runs on plain x86-64; a compiler with POPCNT enabled needs no choice.
#pragma once
#include <bit>
#include <cstdint>

namespace gs {

// Set once, before main: whether this CPU has POPCNT.
inline const bool kCpuHasPopcnt = [] {
  __builtin_cpu_init();  // the feature table may not be filled yet this early
  return __builtin_cpu_supports("popcnt") != 0;
}();

inline uint32_t count_ones(uint64_t bits) {
#if !defined(__POPCNT__) && defined(__x86_64__)
  if (kCpuHasPopcnt) {
    uint64_t count;
    asm("popcnt %1, %0" : "=r"(count) : "rm"(bits) : "cc");
    return uint32_t(count);
  }
#endif
  return uint32_t(std::popcount(bits));
}

}  // namespace gs
