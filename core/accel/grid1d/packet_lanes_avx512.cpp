// The packet walk's lanes with AVX-512 (8 doubles). The pragma comes after every header the
// lane template uses, so that no inline function shared with other files is compiled for
// it; the template itself is in an unnamed namespace (packet_lanes_impl.h). Called
// only when the CPU has AVX-512 (F, VL, DQ).
#include <immintrin.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <limits>

#include "core/accel/grid1d/packet_lanes.h"

#if defined(__clang__)
#pragma clang attribute push(__attribute__((target("avx512f,avx512vl,avx512dq"))), \
                             apply_to = function)
#else
#pragma GCC push_options
#pragma GCC target("avx512f,avx512vl,avx512dq")
#endif

#include "core/accel/grid1d/packet_lanes_impl.h"

namespace gs {
namespace {

struct Avx512Lanes {
  static constexpr uint32_t kWidth = 8;
  typedef double Real __attribute__((vector_size(64)));
  typedef int64_t Mask __attribute__((vector_size(64)));
  typedef int32_t Int __attribute__((vector_size(32)));
  typedef uint32_t UInt __attribute__((vector_size(32)));
  typedef float Float __attribute__((vector_size(32)));
  static uint32_t bits(Mask m) { return uint32_t(_mm512_movepi64_mask(__m512i(m))); }
};

}  // namespace

PacketLaneOps packet_lane_ops_avx512() { return LaneMath<Avx512Lanes>::ops(); }

}  // namespace gs

#if defined(__clang__)
#pragma clang attribute pop
#else
#pragma GCC pop_options
#endif
