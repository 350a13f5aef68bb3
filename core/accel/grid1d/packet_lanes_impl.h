// The packet walk's lane arithmetic (packet_lanes.h), written once for any lane width with
// GCC's vector extensions. Each packet_lanes*.cpp includes it after its target pragma with
// its own Lanes (vector types and the one instruction that turns a compare into bits), so
// that the compiler emits that instruction set's code. Everything here is in an unnamed
// namespace: each file's copy is its own, compiled for its own target, and no inline
// function compiled for a wider set can be picked by the linker for a narrower caller.
//
// The arithmetic is the scalar walk's, operation for operation: a < b ? a : b is std::min's
// and std::clamp's comparison, so each lane's figures are the scalar ones bit for bit.
#include <algorithm>
#include <bit>
#include <cstring>

#include "core/accel/grid1d/packet_lanes.h"

namespace gs {
namespace {

template <class Lanes>
struct LaneMath {
  using Real = typename Lanes::Real;  // Lanes::kWidth doubles
  using Mask = typename Lanes::Mask;  // a Real compare's result
  using Int = typename Lanes::Int;    // Lanes::kWidth int32
  static constexpr uint32_t kWidth = Lanes::kWidth;
  static constexpr uint64_t kGroup = (uint64_t{1} << kWidth) - 1;

  static Real load(const double* p) {
    Real v;
    std::memcpy(&v, p, sizeof v);
    return v;
  }
  static void store(double* p, Real v) { std::memcpy(p, &v, sizeof v); }
  static Real splat(double x) { return Real{} + x; }
  static Real min(Real a, Real b) { return b < a ? b : a; }  // std::min(a, b)
  static Real max(Real a, Real b) { return a < b ? b : a; }  // std::max(a, b)
  static Int min(Int a, Int b) { return b < a ? b : a; }
  static Int max(Int a, Int b) { return a < b ? b : a; }
  // Lane i set where bit i of `group` is.
  static Int lanes_of(uint64_t group) {
    Int bit{};
    for (uint32_t i = 0; i < kWidth; ++i) bit[i] = int32_t(1) << i;
    return (bit & int32_t(group)) != 0;
  }

  // The lane groups holding one of `rays`, by the number of their first ray.
  template <class Each>
  static void for_each_group(uint64_t rays, Each&& each) {
    while (rays != 0) {
      const uint32_t first = uint32_t(std::countr_zero(rays)) & ~(kWidth - 1);
      each(first, uint32_t(rays >> first & kGroup));
      rays &= ~(kGroup << first);
    }
  }

  // The node's cell where a ray's point lies: clamped to the node's cells, then truncated
  // (Grid1D::descend's location).
  static Int locate(Real p, const NodeCells& node) {
    const Real cell = (p - node.origin) * node.scale - node.first;
    const Real last = splat(node.last);
    const Real clamped = cell < 0.0 ? splat(0.0) : (last < cell ? last : cell);
    return __builtin_convertvector(clamped, Int);
  }

  static void cover(const PacketLines& lines, const NodeCells& node, uint64_t rays,
                    const double* t_in, const double* t_out, PacketCover& cover) {
    const int b = node.axis;
    const int32_t last = int32_t(node.last);
    Int cover_lo = Int{} + (last + 1), cover_hi = Int{} - 1;
    for_each_group(rays, [&](uint32_t first, uint32_t group) {
      const Real origin = load(&lines.origin[b][first]), dir = load(&lines.dir[b][first]);
      const Real inv_dir = load(&lines.inv_dir[b][first]);
      store(&cover.t_origin[first], (node.origin - origin) * inv_dir);
      store(&cover.t_width[first], node.width * inv_dir);
      const Int from = locate(origin + load(t_in + first) * dir, node);
      const Int to = locate(origin + load(t_out + first) * dir, node);
      const Int lo = max(min(from, to) - 1, Int{});
      const Int hi = min(max(from, to) + 1, Int{} + last);
      std::memcpy(&cover.lo[first], &lo, sizeof lo);
      std::memcpy(&cover.hi[first], &hi, sizeof hi);
      const Int in = lanes_of(group);
      cover_lo = min(cover_lo, in ? lo : cover_lo);
      cover_hi = max(cover_hi, in ? hi : cover_hi);
    });
    cover.cover_lo = last + 1, cover.cover_hi = -1;
    for (uint32_t i = 0; i < kWidth; ++i) {
      cover.cover_lo = std::min(cover.cover_lo, cover_lo[i]);
      cover.cover_hi = std::max(cover.cover_hi, cover_hi[i]);
    }
  }

  static uint64_t enter(const PacketLines& lines, int axis, const PacketCover& cover, double wall,
                        uint64_t rays, const double* t_in, const double* t_out, double* child_in,
                        double* child_out) {
    uint64_t entering = 0;
    for_each_group(rays, [&](uint32_t first, uint32_t /*group*/) {
      const Real t_origin = load(&cover.t_origin[first]), t_width = load(&cover.t_width[first]);
      const Real wall_a = t_origin + wall * t_width;
      const Real wall_b = t_origin + (wall + 1.0) * t_width;
      const Real slack = load(&lines.slack[first]);
      Real enter = load(t_in + first), exit = load(t_out + first);
      // A ray parallel to the axis stays in its segment (its walls are not numbers).
      const Mask moves = load(&lines.dir[axis][first]) != 0.0;
      enter = moves ? max(enter, min(wall_a, wall_b) - slack) : enter;
      exit = moves ? min(exit, max(wall_a, wall_b) + slack) : exit;
      store(child_in + first, enter);
      store(child_out + first, exit);
      const Mask steps = (enter <= exit) & (enter <= load(&lines.stop[first]));
      entering |= uint64_t(Lanes::bits(steps)) << first;
    });
    return entering & rays;
  }

  static PacketLaneOps ops() { return {cover, enter}; }
};

}  // namespace
}  // namespace gs
