// A cheap 32-bit integer hash with good avalanche: lowbias32 by Chris Wellons (published
// constants). Used for per-pixel jitter and for spreading ids over a colour palette.
#pragma once
#include <cstdint>

namespace gs {

inline uint32_t mix_bits(uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}

}  // namespace gs
