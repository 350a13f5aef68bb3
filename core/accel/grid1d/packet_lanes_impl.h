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
#include <cfloat>
#include <cstring>
#include <limits>

#include "core/accel/grid1d/packet_lanes.h"

namespace gs {
namespace {

template <class Lanes>
struct LaneMath {
  using Real = typename Lanes::Real;    // Lanes::kWidth doubles
  using Mask = typename Lanes::Mask;    // a Real compare's result
  using Int = typename Lanes::Int;      // Lanes::kWidth int32
  using Float = typename Lanes::Float;  // Lanes::kWidth floats
  using UInt = typename Lanes::UInt;    // Lanes::kWidth uint32
  static constexpr uint32_t kWidth = Lanes::kWidth;
  static constexpr uint64_t kGroup = (uint64_t{1} << kWidth) - 1;

  static Real load(const double* p) {
    Real v;
    std::memcpy(&v, p, sizeof v);
    return v;
  }
  static void store(double* p, Real v) { std::memcpy(p, &v, sizeof v); }
  static Real load(const float* p) {
    Float v;
    std::memcpy(&v, p, sizeof v);
    return __builtin_convertvector(v, Real);
  }
  static Float load_float(const float* p) {
    Float v;
    std::memcpy(&v, p, sizeof v);
    return v;
  }
  static void store(float* p, Float v) { std::memcpy(p, &v, sizeof v); }
  static void store(int32_t* p, Int v) { std::memcpy(p, &v, sizeof v); }
  // A double compare's lanes as a mask for float or int32 lanes.
  static Int narrow(Mask m) { return __builtin_convertvector(m, Int); }
  static Real fabs(Real x) { return Real(Mask(x) & INT64_MAX); }  // the sign bit cleared
  static Mask all() { return Mask{} == 0; }
  static Real splat(double x) { return Real{} + x; }
  static Real min(Real a, Real b) { return b < a ? b : a; }  // std::min(a, b)
  static Real max(Real a, Real b) { return a < b ? b : a; }  // std::max(a, b)
  static Float min(Float a, Float b) { return b < a ? b : a; }
  static Float max(Float a, Float b) { return a < b ? b : a; }
  // Lane i set where bit i of `group` is.
  static Int lanes_of(uint64_t group) {
    Int bit{};
    for (uint32_t i = 0; i < kWidth; ++i) bit[i] = int32_t(1) << i;
    return (bit & int32_t(group)) != 0;
  }

  // next_float_up, float_down and float_up (core/geometry/clip_box.h), lane by lane.
  // The bits as unsigned integers, as the scalar code has them: -0 minus one wraps.
  static Float next_float_up(Float f) {
    const UInt bits = UInt(f);
    UInt up = f > 0.0f ? bits + 1u : bits - 1u;
    up = f == 0.0f ? UInt{} + 1u : up;  // the smallest denormal
    return Float(f < std::numeric_limits<float>::infinity() ? up : bits);
  }
  static Float next_float_down(Float f) { return -next_float_up(-f); }
  static Float float_down(Real x) {
    const Float f = __builtin_convertvector(x, Float);
    return narrow(__builtin_convertvector(f, Real) > x) ? next_float_down(f) : f;
  }
  static Float float_up(Real x) {
    const Float f = __builtin_convertvector(x, Float);
    return narrow(__builtin_convertvector(f, Real) < x) ? next_float_up(f) : f;
  }

  // One clip of the segment [t0, t1] of lines origin + t dir to the box (ClipBox::clip and
  // start_walk's second clip): an axis the line is parallel to only excludes it.
  static Mask clip(const ClipBox& box, const Real origin[3], const Real dir[3],
                   const Real inv_dir[3], Real& t0, Real& t1) {
    Mask inside = all();
    for (int a = 0; a < 3; ++a) {
      const Mask flat = dir[a] == 0.0;
      inside &= ~(flat & ((origin[a] < box.lo[a]) | (origin[a] > box.hi[a])));
      const Real ta = (box.lo[a] - origin[a]) * inv_dir[a];
      const Real tb = (box.hi[a] - origin[a]) * inv_dir[a];
      const Mask swap = ta > tb;
      t0 = flat ? t0 : max(t0, swap ? tb : ta);
      t1 = flat ? t1 : min(t1, swap ? ta : tb);
    }
    return inside & (t0 <= t1);
  }

  // ClipBox::misses_surely for a lane group's rays, operation for operation: the rays the
  // float test turns away. maxps and minps are the selects below (their second operand
  // for a NaN), and the scalar test's maximum and minimum over its four lanes are the
  // running ones here, which drop a NaN axis as its lanes do.
  // Rays from inside the box are let in at once; a group of them only (a camera in a room,
  // shadow rays) makes no other test.
  static uint32_t misses_surely(const ClipBox& box, uint32_t first, uint32_t group,
                                const PacketLines& l) {
    const float infinity = std::numeric_limits<float>::infinity();
    const UInt sign = UInt{} + 0x80000000u;
    Int inside = Int{} == 0, near = inside;
    for (int a = 0; a < 3; ++a) {
      const Float o = load_float(&l.ray_origin[a][first]);
      inside &= (box.lo_float[a] <= o) & (o <= box.hi_float[a]);
      near &= Float(UInt(o) & ~sign) <= box.near_range;
    }
    if ((group & ~Lanes::bits(__builtin_convertvector(inside, Mask))) == 0) return 0;
    Float entry = load_float(&l.tmin[first]), exit = load_float(&l.tmax[first]);
    for (int a = 0; a < 3; ++a) {
      const Float o = load_float(&l.ray_origin[a][first]);
      const Float inv_dir = 1.0f / load_float(&l.ray_dir[a][first]);
      const Float t_lo = (box.lo_float[a] - o) * inv_dir, t_hi = (box.hi_float[a] - o) * inv_dir;
      const Float t_near = t_lo < t_hi ? t_lo : t_hi, exact_far = t_lo > t_hi ? t_lo : t_hi;
      // widened_exit (box_test.h): the larger of the two products, NaN staying NaN.
      const Float grown = exact_far * kExitGrowth, shrunk = exact_far * kExitShrink;
      const Float t_far = grown > shrunk ? grown : shrunk;
      entry = t_near > entry ? t_near : entry;
      exit = t_far < exit ? t_far : exit;
    }
    const Int turned =
        ~inside & near & (entry > exit + FLT_MIN) & (entry < infinity) & (exit > -infinity);
    return Lanes::bits(__builtin_convertvector(turned, Mask));
  }

  // Of rays 0 .. count - 1, those ClipBox::misses_surely turns away.
  static uint64_t turned_away(const ClipBox& box, uint32_t count, const PacketLines& l) {
    uint64_t turned = 0;
    for_each_group(rays_of(count), [&](uint32_t first, uint32_t group) {
      turned |= uint64_t(misses_surely(box, first, group, l) & group) << first;
    });
    return turned;
  }

  // ClipBox::starts_inside for a lane group's rays: whether each of `group` starts inside
  // the box (rounded inward) at tmin = +-0, where clip's t0 is tmin bit for bit.
  static bool start_inside(const ClipBox& box, uint32_t first, uint32_t group,
                           const PacketLines& l) {
    Int inside = load_float(&l.tmin[first]) == 0.0f;
    for (int a = 0; a < 3; ++a) {
      const Float o = load_float(&l.ray_origin[a][first]);
      inside &= (box.lo_inward[a] <= o) & (o <= box.hi_inward[a]);
    }
    return (group & ~Lanes::bits(__builtin_convertvector(inside, Mask))) == 0;
  }

  // start_walk (core/geometry/clip_box.cpp) and the kind, a lane group at a time. The float
  // test goes first, and a group whose rays it all turns away is passed over: in a tile at
  // the edge of the scene, most are. A group whose rays all start inside the box at tmin 0
  // (shadow rays, a camera in a room) skips the first clip, as start_walk does.
  static uint64_t start(const ClipBox& box, uint32_t count, PacketLines& l) {
    if (box.empty) return 0;
    uint64_t started = 0, far = 0;
    const uint64_t rays = rays_of(count) & ~turned_away(box, count, l);
    for_each_group(rays, [&](uint32_t first, uint32_t group) {
      Real o[3], d[3], inv_dir[3];
      const Real tmin = load(&l.tmin[first]), tmax = load(&l.tmax[first]);
      // ray_is_valid: finite origin and direction, a direction, tmin <= tmax.
      Mask valid = tmin <= tmax, zero_dir = all();
      for (int a = 0; a < 3; ++a) {
        o[a] = load(&l.ray_origin[a][first]), d[a] = load(&l.ray_dir[a][first]);
        valid &= (o[a] - o[a] == 0.0) & (d[a] - d[a] == 0.0);
        zero_dir &= d[a] == 0.0;
        inv_dir[a] = 1.0 / d[a];
      }
      Real shift = tmin, leave = tmax;
      Mask walks = valid & ~zero_dir;
      if (!start_inside(box, first, group, l)) walks &= clip(box, o, d, inv_dir, shift, leave);
      // walk_slack.
      Real largest = splat(box.magnitude), shortest_inverse = splat(kInf);
      for (int a = 0; a < 3; ++a) {
        largest = max(largest, fabs(o[a]));
        shortest_inverse = min(shortest_inverse, fabs(inv_dir[a]));
      }
      const Real slack = 1e-9 * largest * shortest_inverse;
      Real origin[3];
      Mask is_far = Mask{};
      const double near_range = WalkLine::kNearRange * box.magnitude;
      for (int a = 0; a < 3; ++a) {
        origin[a] = o[a] + shift * d[a];
        is_far |= ~(fabs(o[a]) <= near_range);
      }
      Real t0 = tmin - shift - slack, t1 = splat(kInf);
      walks &= clip(box, origin, d, inv_dir, t0, t1);
      for (int a = 0; a < 3; ++a) {
        store(&l.origin[a][first], origin[a]), store(&l.dir[a][first], d[a]);
        store(&l.inv_dir[a][first], inv_dir[a]);
      }
      store(&l.shift[first], shift), store(&l.slack[first], slack);
      store(&l.t0[first], t0);
      // The kind: the octant, and PreparedRay's kz (the largest magnitude, x before y before z).
      const Real mx = fabs(d[0]), my = fabs(d[1]), mz = fabs(d[2]);
      const Mask two = Mask{} + 2;
      const Mask kz = mx >= my ? (mx >= mz ? Mask{} : two) : (my >= mz ? Mask{} + 1 : two);
      Mask octant = Mask{};
      for (int a = 0; a < 3; ++a) octant |= (Mask(d[a]) < 0) & (int64_t{1} << a);
      store(&l.kind[first], narrow(octant | kz << 3));
      started |= uint64_t(Lanes::bits(walks)) << first;
      far |= uint64_t(Lanes::bits(is_far)) << first;
    });
    started &= rays;
    l.far = far & started;
    return started;
  }

  // PreparedRay, RayBoxes, box_test_start and set_stop (grid1d's records.h) for the packet.
  // No ray of `rays` is far (WalkLine::far): far rays walk alone (Grid1D::trace_together).
  static void prepare(PacketLines& l, uint64_t rays, const int axes[3], RayLanes& kernel_lanes,
                      RayBoxLanes& box_lanes) {
    const float infinity = std::numeric_limits<float>::infinity();
    Float lo[3], hi[3], inv_lo[3], inv_hi[3];  // the bounds of box_lanes' rays, per lane
    Float t0_lo = Float{} + infinity, t1_hi = Float{} - infinity;
    for (int a = 0; a < 3; ++a) lo[a] = inv_lo[a] = t0_lo, hi[a] = inv_hi[a] = t1_hi;
    for_each_group(rays, [&](uint32_t first, uint32_t group) {
      double* kernel_origin[3] = {kernel_lanes.ox, kernel_lanes.oy, kernel_lanes.oz};
      for (int k = 0; k < 3; ++k) store(kernel_origin[k] + first, load(&l.origin[axes[k]][first]));
      const Real sz = load(&l.inv_dir[axes[2]][first]);
      store(kernel_lanes.sx + first, load(&l.dir[axes[0]][first]) * sz);
      store(kernel_lanes.sy + first, load(&l.dir[axes[1]][first]) * sz);
      store(kernel_lanes.sz + first, sz);
      const Real shift = load(&l.shift[first]);
      store(kernel_lanes.shift + first, shift);
      const Float tmax = load_float(&l.tmax[first]);
      store(kernel_lanes.tmin + first, load_float(&l.tmin[first]));
      store(kernel_lanes.tmax + first, tmax);
      const Int in = lanes_of(group);
      for (int a = 0; a < 3; ++a) {
        const Float origin = load_float(&l.ray_origin[a][first]);
        const Float inv_dir = 1.0f / load_float(&l.ray_dir[a][first]);
        store(&box_lanes.origin[a][first], origin);
        store(&box_lanes.inv_dir[a][first], inv_dir);
        lo[a] = in ? min(lo[a], origin) : lo[a], hi[a] = in ? max(hi[a], origin) : hi[a];
        inv_lo[a] = in ? min(inv_lo[a], inv_dir) : inv_lo[a];
        inv_hi[a] = in ? max(inv_hi[a], inv_dir) : inv_hi[a];
      }
      const Real stop =
          __builtin_convertvector(next_float_up(tmax), Real) + load(&l.slack[first]) - shift;
      store(&l.stop[first], stop);
      const Float t0 = float_down(shift + load(&l.t0[first]));
      const Float t1 = float_up(shift + stop);
      store(&box_lanes.t0[first], t0);
      store(&box_lanes.t1[first], t1);
      t0_lo = in ? min(t0_lo, t0) : t0_lo, t1_hi = in ? max(t1_hi, t1) : t1_hi;
    });
    set_bounds(lo, hi, inv_lo, inv_hi, t0_lo, t1_hi, box_lanes.bounds);
  }

  // The packet's bounds (RayBoxBounds) from per-lane ones: the least and greatest over lanes.
  static void set_bounds(const Float lo[3], const Float hi[3], const Float inv_lo[3],
                         const Float inv_hi[3], Float t0_lo, Float t1_hi, RayBoxBounds& bounds) {
    float origin_lo[3], origin_hi[3], inv_dir_lo[3], inv_dir_hi[3];
    for (int a = 0; a < 3; ++a) {
      origin_lo[a] = least(lo[a]), origin_hi[a] = greatest(hi[a]);
      inv_dir_lo[a] = least(inv_lo[a]), inv_dir_hi[a] = greatest(inv_hi[a]);
    }
    bounds.set(origin_lo, origin_hi, inv_dir_lo, inv_dir_hi, least(t0_lo), greatest(t1_hi));
  }
  static float least(Float v) {
    float m = v[0];
    for (uint32_t i = 1; i < kWidth; ++i) m = v[i] < m ? v[i] : m;
    return m;
  }
  static float greatest(Float v) {
    float m = v[0];
    for (uint32_t i = 1; i < kWidth; ++i) m = m < v[i] ? v[i] : m;
    return m;
  }

  static uint64_t rays_of(uint32_t count) {
    return count >= 64 ? ~uint64_t{0} : (uint64_t{1} << count) - 1;
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

  static PacketLaneOps ops() { return {turned_away, start, prepare}; }
};

}  // namespace
}  // namespace gs
