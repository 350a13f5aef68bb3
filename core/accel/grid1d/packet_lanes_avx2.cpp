// The packet walk's lanes with AVX2 (4 doubles). The pragma comes after every header the
// lane template uses, so that no inline function shared with other files is compiled for
// it; the template itself is in an unnamed namespace (packet_lanes_impl.h). Called
// only when the CPU has AVX2.
#include <immintrin.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <limits>

#include "core/accel/grid1d/packet_lanes.h"

#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx2"))), apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx2")
#endif

#include "core/accel/grid1d/packet_lanes_impl.h"

namespace gs {
namespace {

struct Avx2Lanes {
  static constexpr uint32_t kWidth = 4;
  typedef double Real __attribute__((vector_size(32)));
  typedef int64_t Mask __attribute__((vector_size(32)));
  typedef int32_t Int __attribute__((vector_size(16)));
  typedef uint32_t UInt __attribute__((vector_size(16)));
  typedef float Float __attribute__((vector_size(16)));
  static uint32_t bits(Mask m) { return uint32_t(_mm256_movemask_pd(__m256d(m))); }
};

}  // namespace

PacketLaneOps packet_lane_ops_avx2() { return LaneMath<Avx2Lanes>::ops(); }

}  // namespace gs

#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif
