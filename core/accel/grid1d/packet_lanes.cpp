// The packet walk's lanes on baseline x86-64 (SSE2: 2 doubles), and the choice of lanes by
// instruction set.
#include <emmintrin.h>

#include "core/accel/grid1d/packet_lanes_impl.h"

namespace gs {
namespace {

struct Sse2Lanes {
  static constexpr uint32_t kWidth = 2;
  typedef double Real __attribute__((vector_size(16)));
  typedef int64_t Mask __attribute__((vector_size(16)));
  typedef int32_t Int __attribute__((vector_size(8)));
  typedef uint32_t UInt __attribute__((vector_size(8)));
  typedef float Float __attribute__((vector_size(8)));
  static uint32_t bits(Mask m) { return uint32_t(_mm_movemask_pd(__m128d(m))); }
};

}  // namespace

PacketLaneOps packet_lane_ops_sse2() { return LaneMath<Sse2Lanes>::ops(); }

PacketLaneOps packet_lane_ops(Isa isa) {
  switch (isa) {
    case Isa::avx2:
      return packet_lane_ops_avx2();
    case Isa::avx512:
      return packet_lane_ops_avx512();
    case Isa::scalar:
      break;
  }
  return packet_lane_ops_sse2();
}

}  // namespace gs
