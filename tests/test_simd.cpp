// The kernels of every instruction set this CPU has against the scalar kernel, lane by lane
// and bit for bit, on triangles and rays chosen to reach every branch (misses, hits, hits
// through shared edges and vertices, edge functions that round to zero and go to wider
// arithmetic); the content-box test against the exact segment-box intersection; and every
// structure, with each kernel, against brute force.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "core/accel/grid1d/packet_lanes.h"
#include "core/base/bit_count.h"
#include "core/geometry/box_test.h"
#include "core/geometry/clip_box.h"
#include "core/geometry/leaf.h"
#include "tests/cases.h"
#include "tests/test_util.h"

namespace gs {
namespace {

// The packet walk's bit count (the POPCNT instruction where this CPU has it) against a count
// of the bits one at a time, on masks with every bit alone, every run from bit 0 and random
// ones.
TEST(BitCount, CountsAsOneBitAtATime) {
  const auto one_at_a_time = [](uint64_t bits) {
    uint32_t count = 0;
    for (int i = 0; i < 64; ++i) count += uint32_t(bits >> i & 1);
    return count;
  };
  std::vector<uint64_t> masks = {0, ~uint64_t{0}};
  for (int i = 0; i < 64; ++i)
    masks.push_back(uint64_t{1} << i), masks.push_back(~uint64_t{0} >> i);
  std::mt19937_64 random(7);
  for (int i = 0; i < 1000; ++i) masks.push_back(random() & random());
  for (const uint64_t mask : masks) EXPECT_EQ(count_ones(mask), one_at_a_time(mask)) << mask;
}

std::vector<Isa> supported_isas() {
  std::vector<Isa> isas;
  for (const Isa isa : {Isa::scalar, Isa::avx2, Isa::avx512})
    if (isa_supported(isa)) isas.push_back(isa);
  return isas;
}

// Triangles around the unit square with shared edges and vertices (a fan and its
// neighbours), tiny and huge ones, and rays through random points, through the shared
// vertices and edges, and parallel to triangles.
struct KernelCase {
  std::vector<TriangleVerts> triangles;
  std::vector<Ray> rays;
};

KernelCase kernel_case(uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  KernelCase c;
  const glm::vec3 centre(0.0f, 0.0f, 0.0f);
  for (int k = 0; k < 8; ++k) {  // a fan: every pair shares an edge, all share the centre
    const float a0 = float(k) * 0.785398f, a1 = float(k + 1) * 0.785398f;
    c.triangles.push_back({centre,
                           {std::cos(a0), std::sin(a0), 0.1f * unit(rng)},
                           {std::cos(a1), std::sin(a1), 0.1f * unit(rng)}});
  }
  for (int k = 0; k < 40; ++k) {
    const glm::vec3 p(unit(rng), unit(rng), unit(rng));
    const float size = k % 10 == 0 ? 1e-4f : k % 10 == 1 ? 50.0f : 0.5f;
    c.triangles.push_back({p, p + size * glm::vec3(unit(rng), unit(rng), unit(rng)),
                           p + size * glm::vec3(unit(rng), unit(rng), unit(rng))});
  }
  for (int k = 0; k < 400; ++k) {
    Ray ray;
    ray.origin = {3.0f * unit(rng), 3.0f * unit(rng), 3.0f};
    glm::vec3 target(unit(rng), unit(rng), 0.0f);
    if (k % 4 == 1) target = centre;                 // through the fan's shared vertex
    if (k % 4 == 2) target = c.triangles[k % 8].v1;  // through a shared edge's end
    if (k % 4 == 3) target = 0.5f * (c.triangles[k % 8].v1 + c.triangles[k % 8].v2);
    ray.dir = target - ray.origin;
    if (k % 16 == 5) ray.dir.x = 0.0f;  // zero components: the shear's special cases
    if (k % 16 == 6) ray.dir.y = -0.0f;
    if (k % 32 == 7) ray.dir = {1.0f, 0.0f, 0.0f}, ray.origin = {-2.0f, 0.0f, 0.05f};
    if (k % 8 == 4) ray.tmax = 0.9f, ray.tmin = 0.2f;
    c.rays.push_back(ray);
  }
  return c;
}

TEST(LeafKernels, EveryLaneGivesTheScalarKernelsAnswerBitForBit) {
  const KernelCase c = kernel_case(7);
  std::vector<uint32_t> ids(c.triangles.size());
  for (uint32_t i = 0; i < ids.size(); ++i) ids[i] = i;
  Scene scene;
  for (const TriangleVerts& t : c.triangles) test::add_triangle(scene, t.v0, t.v1, t.v2);
  LeafStore store(uint64_t{1} << 20);
  const LeafView leaf = store.view(store.add(ids, BuildInput(scene)));
  uint64_t lanes_checked = 0, hits = 0;
  for (const Isa isa : supported_isas()) {
    const Kernel kernel = kernel_for(isa);
    for (const Ray& ray : c.rays) {
      const PreparedRay<KernelReal> prepared(ray, 0.0);
      for (uint32_t first = 0; first < leaf.count; first += kernel.lanes) {
        const uint32_t width = std::min(kernel.lanes, leaf.count - first);
        // Every lane, then every other lane (masked lanes must not be reported).
        for (const uint32_t lanes : {(1u << width) - 1u, ((1u << width) - 1u) & 0x55u}) {
          LaneHits out;
          const uint32_t got = kernel.test(leaf, first, lanes, prepared, ray.tmax, out);
          EXPECT_EQ(got & ~lanes, 0u) << isa_name(isa);
          for (uint32_t j = 0; j < width; ++j) {
            if (!(lanes >> j & 1)) continue;
            const TriangleVerts& tri = c.triangles[first + j];
            float t = 0.0f, u = 0.0f, v = 0.0f;
            const bool expected =
                intersect_triangle(prepared, tri.v0, tri.v1, tri.v2, ray.tmax, t, u, v);
            ASSERT_EQ(bool(got >> j & 1), expected) << isa_name(isa) << " triangle " << first + j;
            ++lanes_checked;
            if (!expected) continue;
            ++hits;
            EXPECT_EQ(std::bit_cast<uint32_t>(out.t[j]), std::bit_cast<uint32_t>(t));
            EXPECT_EQ(std::bit_cast<uint32_t>(out.u[j]), std::bit_cast<uint32_t>(u));
            EXPECT_EQ(std::bit_cast<uint32_t>(out.v[j]), std::bit_cast<uint32_t>(v));
          }
        }
      }
    }
  }
  EXPECT_GT(hits, 200u);
  RecordProperty("lanes_checked", int(lanes_checked));
}

// The rays-in-lanes kernels (a packet's rays against one triangle) give, lane by lane, the
// scalar kernel's answer bit for bit: rays grouped by axis order, each group against every
// triangle, all lanes and every other lane.
TEST(LeafKernels, RaysInLanesGiveTheScalarKernelsAnswerBitForBit) {
  const KernelCase c = kernel_case(9);
  std::vector<uint32_t> ids(c.triangles.size());
  Scene scene;
  for (uint32_t i = 0; i < ids.size(); ++i) {
    ids[i] = i;
    const TriangleVerts& t = c.triangles[i];
    scene.vertices.insert(scene.vertices.end(), {t.v0, t.v1, t.v2});
    scene.triangles.push_back({3 * i, 3 * i + 1, 3 * i + 2});
  }
  LeafStore store(uint64_t{1} << 20);
  const LeafView leaf = store.view(store.add(ids, BuildInput(scene)));
  std::vector<PreparedRay<KernelReal>> prepared;
  for (const Ray& ray : c.rays) prepared.emplace_back(ray, 0.0);
  uint64_t lanes_checked = 0, hits = 0;
  for (const Isa isa : supported_isas()) {
    const Kernel kernel = kernel_for(isa);
    for (int kz = 0; kz < 3; ++kz)
      for (const bool swapped : {false, true}) {
        RayLanes lanes;
        std::vector<size_t> ray_of;
        for (size_t i = 0; i < prepared.size() && lanes.count < RayLanes::kMaxRays; ++i) {
          const PreparedRay<KernelReal>& p = prepared[i];
          if (p.kz != kz || (p.kx != (kz + 1) % 3) == swapped) continue;
          if (lanes.count == 0) lanes.kx = p.kx, lanes.ky = p.ky, lanes.kz = p.kz;
          lanes.add(p, c.rays[i].tmax);
          ray_of.push_back(i);
        }
        if (lanes.count == 0) continue;
        const uint64_t all = lanes.count == 64 ? ~uint64_t{0} : (uint64_t{1} << lanes.count) - 1;
        for (uint32_t tri = 0; tri < leaf.count; ++tri)
          for (const uint64_t mask : {all, all & 0x5555555555555555u}) {
            RayHits out;
            const uint64_t got = kernel.test_rays(leaf, tri, lanes, mask, out);
            EXPECT_EQ(got & ~mask, 0u) << isa_name(isa);
            for (uint32_t r = 0; r < lanes.count; ++r) {
              if (!(mask >> r & 1)) continue;
              const Ray& ray = c.rays[ray_of[r]];
              const TriangleVerts& t = c.triangles[tri];
              float th = 0.0f, u = 0.0f, v = 0.0f;
              const bool expected =
                  intersect_triangle(prepared[ray_of[r]], t.v0, t.v1, t.v2, ray.tmax, th, u, v);
              ASSERT_EQ(bool(got >> r & 1), expected) << isa_name(isa) << " ray " << ray_of[r];
              ++lanes_checked;
              if (!expected) continue;
              ++hits;
              EXPECT_EQ(std::bit_cast<uint32_t>(out.t[r]), std::bit_cast<uint32_t>(th));
              EXPECT_EQ(std::bit_cast<uint32_t>(out.u[r]), std::bit_cast<uint32_t>(u));
              EXPECT_EQ(std::bit_cast<uint32_t>(out.v[r]), std::bit_cast<uint32_t>(v));
            }
          }
      }
  }
  EXPECT_GT(hits, 200u);
  RecordProperty("lanes_checked", int(lanes_checked));
}

// The exact answer: does the segment [t0, t1] of the ray meet the closed box? In long
// double, with the zero-direction rule of ClipBox::clip.
bool segment_meets_box(const Ray& ray, const float box[6], double t0, double t1) {
  long double lo = t0, hi = t1;
  for (int a = 0; a < 3; ++a) {
    const long double o = ray.origin[a], d = ray.dir[a];
    if (d == 0) {
      if (o < box[a] || o > box[a + 3]) return false;
      continue;
    }
    long double ta = (box[a] - o) / d, tb = (box[a + 3] - o) / d;
    if (ta > tb) std::swap(ta, tb);
    lo = std::max(lo, ta), hi = std::min(hi, tb);
  }
  return lo <= hi;
}

// Never a miss for a crossing, however close to a face or corner the ray passes, wherever
// it starts (before, inside, beyond the box; at negative t), with zero and -0 components.
TEST(BoxTest, NeverReportsAMissForACrossing) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  uint64_t crossings = 0, boxes_tested = 0;
  for (int k = 0; k < 20000; ++k) {
    float box[6];
    const float scale = k % 3 == 0 ? 1e-3f : k % 3 == 1 ? 1.0f : 1e4f;
    for (int a = 0; a < 3; ++a) {
      const float x = scale * unit(rng), y = scale * unit(rng);
      box[a] = std::min(x, y), box[a + 3] = k % 17 == 0 ? std::min(x, y) : std::max(x, y);
    }
    Ray ray;
    // Aimed at a face's or an edge's point, so that many rays just graze the box.
    glm::vec3 target;
    for (int a = 0; a < 3; ++a) target[a] = (k >> a & 1) ? box[a] : box[a + 3];
    target[k % 3] = box[k % 3] + (box[k % 3 + 3] - box[k % 3]) * (0.5f + 0.5f * unit(rng));
    ray.origin = target + scale * 3.0f * glm::vec3(unit(rng), unit(rng), unit(rng));
    ray.dir = target - ray.origin;
    if (k % 11 == 0) ray.dir[k % 3] = 0.0f, ray.origin[k % 3] = target[k % 3];
    if (k % 13 == 0) ray.dir[(k + 1) % 3] = -0.0f;
    if (ray.dir == glm::vec3(0.0f)) continue;
    const double t0 = k % 5 == 0 ? -2.0 : 0.0, t1 = k % 7 == 0 ? 0.999999 : 1e30;
    const RayBoxes test(ray);
    float soa[box_floats(4)] = {};
    for (int f = 0; f < 6; ++f) soa[f * 4] = box[f];
    const bool crossed =
        test.crossed4(soa, 4, 0, _mm_set1_ps(float_down(t0)), _mm_set1_ps(float_up(t1))) & 1u;
    ++boxes_tested;
    if (!segment_meets_box(ray, box, t0, t1)) continue;
    ++crossings;
    ASSERT_TRUE(crossed) << "box " << k;
  }
  EXPECT_GT(crossings, boxes_tested / 4);
}

// Scenes and rays for the clip box's float test: a box of size about `scale` (flat on an
// axis one time in 19), and rays aimed at a point of a face or an edge of its clip box (the
// double faces), so that many graze it, from before, inside and beyond it, with zero and
// -0 components, tiny components (whose 1 / dir overflows in float), origins beyond the near
// range, and short segments.
float grazing_scale(int k) { return k % 3 == 0 ? 1e-3f : k % 3 == 1 ? 1.0f : 1e4f; }
Box grazing_box(int k, std::mt19937_64& rng) {
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  const float scale = grazing_scale(k);
  Box scene;
  for (int a = 0; a < 3; ++a) {
    const float x = scale * unit(rng), y = scale * unit(rng);
    scene.lo[a] = std::min(x, y), scene.hi[a] = k % 19 == 0 ? std::min(x, y) : std::max(x, y);
  }
  return scene;
}
Ray grazing_ray(int k, float scale, const ClipBox& box, std::mt19937_64& rng) {
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  double target[3];
  for (int a = 0; a < 3; ++a) target[a] = (k >> a & 1) ? box.lo[a] : box.hi[a];
  target[k % 3] = box.lo[k % 3] + (box.hi[k % 3] - box.lo[k % 3]) * (0.5 + 0.5 * unit(rng));
  Ray ray;
  for (int a = 0; a < 3; ++a) {
    ray.origin[a] = float(target[a]) + scale * 3.0f * unit(rng);
    ray.dir[a] = float(target[a]) - ray.origin[a] + (k % 4 == 0 ? scale * 0.3f * unit(rng) : 0.0f);
  }
  if (k % 11 == 0) ray.dir[k % 3] = 0.0f, ray.origin[k % 3] = float(target[k % 3]);
  if (k % 13 == 0) ray.dir[(k + 1) % 3] = -0.0f;
  if (k % 23 == 0) ray.dir[(k + 2) % 3] = 1e-41f;
  if (k % 29 == 0) ray.origin *= 2e4f;
  ray.tmin = k % 5 == 0 ? 0.5f : 0.0f;
  ray.tmax = k % 7 == 0 ? 0.999999f : INFINITY;
  return ray;
}

// Case k of the grazing rays: its scale, box and ray.
struct GrazingCase {
  float scale;
  ClipBox box;
  Ray ray;
};
GrazingCase grazing_case(int k, std::mt19937_64& rng) {
  const float scale = grazing_scale(k);
  const ClipBox box(grazing_box(k, rng));
  return {scale, box, grazing_ray(k, scale, box, rng)};
}

// The clip box's float test (ClipBox::misses_surely) turns a ray away only when its
// segment [tmin, tmax] misses the box: never for a ray whose exact segment (long double)
// meets the box, nor for one the double clip (clip_segment) lets in, nor for one from
// beyond the near range. And it does turn away every ray that misses the box by a clear
// margin.
TEST(ClipBoxTest, FloatTestTurnsAwayOnlyRaysThatMissTheBox) {
  std::mt19937_64 rng(29);
  uint64_t meeting = 0, clear_misses = 0, turned_away = 0, far = 0;
  for (int k = 0; k < 30000; ++k) {
    const auto [scale, box, ray] = grazing_case(k, rng);
    if (ray.dir == glm::vec3(0.0f)) continue;
    const bool turned = box.misses_surely(ray);
    turned_away += turned;
    double t0 = ray.tmin, t1 = ray.tmax;
    const double origin[3] = {ray.origin.x, ray.origin.y, ray.origin.z};
    const double dir[3] = {ray.dir.x, ray.dir.y, ray.dir.z};
    if (clip_segment(origin, dir, box.lo, box.hi, t0, t1)) {
      ASSERT_FALSE(turned) << "ray " << k;
    }
    const bool beyond = std::fabs(double(ray.origin.x)) > 1e4 * box.magnitude ||
                        std::fabs(double(ray.origin.y)) > 1e4 * box.magnitude ||
                        std::fabs(double(ray.origin.z)) > 1e4 * box.magnitude;
    if (beyond) {
      ++far;
      ASSERT_FALSE(turned) << "ray " << k;
    }
    const float faces[6] = {float(box.lo[0]), float(box.lo[1]), float(box.lo[2]),
                            float(box.hi[0]), float(box.hi[1]), float(box.hi[2])};
    // The exact test against the box's float faces, which hold the double box within an
    // ulp: a ray that meets them, or passes within 1e-6 of the box's size, is let in.
    if (segment_meets_box(ray, faces, ray.tmin, ray.tmax)) {
      ++meeting;
      ASSERT_FALSE(turned) << "ray " << k;
    }
    // A ray with no zero or tiny component that misses the box grown by 1e-3 of its size
    // on every side is turned away: the test's margin is about 5e-7 of the distances.
    float grown[6];
    for (int a = 0; a < 3; ++a) {
      const float margin = 1e-3f * std::max(faces[a + 3] - faces[a], scale);
      grown[a] = faces[a] - margin, grown[a + 3] = faces[a + 3] + margin;
    }
    const bool plain = !beyond && std::min({std::fabs(ray.dir.x), std::fabs(ray.dir.y),
                                            std::fabs(ray.dir.z)}) > 1e-30f;
    if (plain && !segment_meets_box(ray, grown, ray.tmin, ray.tmax)) {
      ++clear_misses;
      EXPECT_TRUE(turned) << "ray " << k;
    }
  }
  EXPECT_GT(meeting, 5000u);
  EXPECT_GT(far, 500u);
  EXPECT_GT(clear_misses, 3000u);
  EXPECT_GE(turned_away, clear_misses);
}

// The slab clip one axis at a time, in scalar double: the clip box's and start_walk's
// distances as first written, for the tests below.
bool scalar_clip(const double origin[3], const double dir[3], const double inv_dir[3],
                 const double lo[3], const double hi[3], double& t0, double& t1, double t_exit[3]) {
  for (int a = 0; a < 3; ++a) {
    t_exit[a] = INFINITY;
    if (dir[a] == 0.0) {
      if (origin[a] < lo[a] || origin[a] > hi[a]) return false;
      continue;
    }
    double ta = (lo[a] - origin[a]) * inv_dir[a], tb = (hi[a] - origin[a]) * inv_dir[a];
    if (ta > tb) std::swap(ta, tb);
    t_exit[a] = tb;
    t0 = std::max(t0, ta), t1 = std::min(t1, tb);
  }
  return t0 <= t1;
}

// Bits of a double and a float, for bit-for-bit comparisons (NaN included).
uint64_t bits(double x) { return std::bit_cast<uint64_t>(x); }
uint32_t bits(float x) { return std::bit_cast<uint32_t>(x); }

// The clip (ClipBox::clip) and the walk's start (start_walk), which compute two axes at a
// time in SSE2 lanes, give the scalar clip's answer bit for bit: whether the ray is let in,
// its t0 and t1 (signs of zero included), 1 / dir, and the walk line's origin, interval,
// slab exits and slack, on the float test's grazing rays, with zero, negative zero and
// tiny components, origins on and off the slabs of axes the ray is parallel to, tmin 0,
// -0 and 0.5, from inside and outside the box.
TEST(ClipBoxTest, ClipAndWalkStartAreTheScalarClipBitForBit) {
  std::mt19937_64 rng(31);
  uint64_t clipped = 0, parallel_outside = 0, zero_t0 = 0, negative_zero = 0;
  for (int k = 0; k < 30000; ++k) {
    auto [scale, box, ray] = grazing_case(k, rng);
    if (k % 11 == 0 && k % 2 == 0) ray.origin[k % 3] += scale;  // off a parallel slab
    if (k % 5 == 2) {  // from the box's centre, tmin +0 or -0
      for (int a = 0; a < 3; ++a) ray.origin[a] = float(0.5 * (box.lo[a] + box.hi[a]));
      ray.tmin = k % 2 ? -0.0f : 0.0f;
    }
    if (k % 17 == 0) ray.tmin = -0.0f;
    if (ray.dir == glm::vec3(0.0f)) continue;
    double t0 = 0.0, t1 = 0.0, inv_dir[3];
    const bool let_in = box.clip(ray, t0, t1, inv_dir);
    WalkLine line;
    const bool started = start_walk(box, ray, line);
    // The reference: the float test and validity as the clip has them, then scalar slabs.
    const double origin[3] = {ray.origin.x, ray.origin.y, ray.origin.z};
    const double dir[3] = {ray.dir.x, ray.dir.y, ray.dir.z};
    double inv[3], exits[3], ref_t0 = ray.tmin, ref_t1 = ray.tmax;
    for (int a = 0; a < 3; ++a) inv[a] = 1.0 / dir[a];
    const bool ref_in = !box.turns_away(ray) &&
                        scalar_clip(origin, dir, inv, box.lo, box.hi, ref_t0, ref_t1, exits);
    parallel_outside += !ref_in && !box.turns_away(ray) && ref_t0 <= ref_t1;
    ASSERT_EQ(let_in, ref_in) << "ray " << k;
    ASSERT_EQ(started, ref_in) << "ray " << k;
    if (!ref_in) continue;
    ++clipped;
    zero_t0 += ref_t0 == 0.0;
    negative_zero += bits(ref_t0) == bits(-0.0);
    EXPECT_EQ(bits(t0), bits(ref_t0)) << "ray " << k;
    EXPECT_EQ(bits(t1), bits(ref_t1)) << "ray " << k;
    for (int a = 0; a < 3; ++a) {
      EXPECT_EQ(bits(inv_dir[a]), bits(inv[a])) << "ray " << k << " axis " << a;
      EXPECT_EQ(bits(line.inv_dir[a]), bits(inv[a])) << "ray " << k << " axis " << a;
    }
    // The walk line: the origin moved to the entry (or kept, from inside), its interval.
    const double shift = box.starts_inside(ray) ? double(ray.tmin) : ref_t0;
    double moved[3];
    for (int a = 0; a < 3; ++a) moved[a] = origin[a] + shift * dir[a];
    const double slack = walk_slack(ray, box.magnitude, inv);
    double line_t0 = double(ray.tmin) - shift - slack, line_t1 = INFINITY;
    ASSERT_TRUE(scalar_clip(moved, dir, inv, box.lo, box.hi, line_t0, line_t1, exits) ||
                !(line.t0 <= line.t1))
        << "ray " << k;
    EXPECT_EQ(bits(line.shift), bits(shift)) << "ray " << k;
    EXPECT_EQ(bits(line.slack), bits(slack)) << "ray " << k;
    EXPECT_EQ(bits(line.t0), bits(line_t0)) << "ray " << k;
    EXPECT_EQ(bits(line.t1), bits(line_t1)) << "ray " << k;
    for (int a = 0; a < 3; ++a) {
      EXPECT_EQ(bits(line.origin[a]), bits(moved[a])) << "ray " << k << " axis " << a;
      EXPECT_EQ(bits(line.dir[a]), bits(dir[a])) << "ray " << k << " axis " << a;
      EXPECT_EQ(bits(line.t_exit[a]), bits(exits[a])) << "ray " << k << " axis " << a;
    }
  }
  EXPECT_GT(clipped, 8000u);
  EXPECT_GT(parallel_outside, 100u);
  EXPECT_GT(zero_t0, 3000u);
  EXPECT_GT(negative_zero, 1000u);
}

// A ray that starts inside the clip box at tmin = 0 takes start_walk's short way
// (ClipBox::starts_inside), and only such a ray: its origin inside the double box and tmin
// +0 or -0. Its walk line then starts where clip's t0 says and with clip's 1 / dir, bit for
// bit, on origins inside the box, on its faces and a float beyond them, with zero, negative
// zero and tiny direction components, at three scales.
TEST(ClipBoxTest, RaysFromInsideStartAsTheClipStartsThem) {
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  uint64_t short_ways = 0;
  for (int k = 0; k < 30000; ++k) {
    const float scale = grazing_scale(k);
    const ClipBox box(grazing_box(k, rng));
    Ray ray;
    for (int a = 0; a < 3; ++a) {
      const double t = 0.5 + 0.5 * double(unit(rng));
      float o = float(box.lo[a] + (box.hi[a] - box.lo[a]) * t);
      const int where = k >> (2 * a) & 3;  // 0, 1: inside; 2: on a face; 3: a float beyond
      if (where >= 2) {
        const bool high = unit(rng) > 0.0f;
        o = float(high ? box.hi[a] : box.lo[a]);
        if (where == 3) o = high ? next_float_up(o) : next_float_down(o);
      }
      ray.origin[a] = o;
      ray.dir[a] = scale * unit(rng);
    }
    if (k % 11 == 0) ray.dir[k % 3] = 0.0f;
    if (k % 13 == 0) ray.dir[(k + 1) % 3] = -0.0f;
    if (k % 23 == 0) ray.dir[(k + 2) % 3] = 1e-41f;
    ray.tmin = k % 5 == 0 ? 0.5f : k % 5 == 1 ? -0.0f : 0.0f;
    ray.tmax = k % 7 == 0 ? 0.999999f : INFINITY;
    bool inside = ray.tmin == 0.0f;
    for (int a = 0; a < 3; ++a)
      inside = inside && box.lo[a] <= double(ray.origin[a]) && double(ray.origin[a]) <= box.hi[a];
    if (box.starts_inside(ray)) {
      ASSERT_TRUE(inside) << "ray " << k;
      ++short_ways;
    }
    double t0 = 0.0, t1 = 0.0, inv_dir[3];
    const bool clipped = box.clip(ray, t0, t1, inv_dir);
    WalkLine line;
    const bool started = start_walk(box, ray, line);
    if (!clipped) {
      EXPECT_FALSE(started) << "ray " << k;
      continue;
    }
    EXPECT_EQ(std::bit_cast<uint64_t>(line.shift), std::bit_cast<uint64_t>(t0)) << "ray " << k;
    for (int a = 0; a < 3; ++a)
      EXPECT_EQ(std::bit_cast<uint64_t>(line.inv_dir[a]), std::bit_cast<uint64_t>(inv_dir[a]))
          << "ray " << k << " axis " << a;
  }
  EXPECT_GT(short_ways, 2000u);
}

// One ray against a run of a leaf's boxes, 4, 8 or 16 at a time (Kernel::boxes_crossed, by
// every kernel this CPU has), says for every box what the four-at-a-time test
// (RayBoxes::crossed4) says: runs of 1 to 64 boxes from every offset of blocks of up to 80,
// the last box of a block at the end of its storage (masked reads stay inside), rays with
// zero and -0 components and rays from far away, over segments that start before the ray.
TEST(BoxTest, BoxesInWideLanesAgreeWithFourAtATime) {
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  uint64_t compared = 0, crossings = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const auto count = uint32_t(1 + trial % 80);
    const uint32_t stride = box_stride(count);
    std::vector<float> soa(box_floats(count));
    for (uint32_t box = 0; box < count; ++box)
      for (int a = 0; a < 3; ++a) {
        const float x = unit(rng), y = unit(rng);
        soa[a * stride + box] = std::min(x, y), soa[(a + 3) * stride + box] = std::max(x, y);
      }
    // The wide tests read no further than the last box's own floats (the SSE one reads
    // whole fours: box_floats' padding).
    std::vector<float> tight(soa.begin(), soa.begin() + 5 * stride + count);
    Ray ray;
    ray.origin = {2.0f * unit(rng), 2.0f * unit(rng), 2.0f * unit(rng)};
    ray.dir = {unit(rng), unit(rng), unit(rng)};
    if (trial % 9 == 0) ray.dir[trial % 3] = trial % 2 ? 0.0f : -0.0f;
    const RayBoxes one(ray, trial % 17 != 0);
    const __m128 t0 = _mm_set1_ps(trial % 5 == 0 ? -1.0f : 0.0f);
    const __m128 t1 = _mm_set1_ps(trial % 7 == 0 ? 0.5f : 1e30f);
    for (uint32_t first = 0; first < count; first += 1 + trial % 5) {
      const uint32_t run = std::min<uint32_t>(count - first, 1 + (first * 7 + trial) % 64);
      for (const Isa isa : supported_isas()) {
        const float* boxes = isa == Isa::scalar ? soa.data() : tight.data();
        const uint64_t got = kernel_for(isa).boxes_crossed(one, boxes, stride, first, run, t0, t1);
        EXPECT_EQ(run == 64 ? 0u : got >> run, 0u) << isa_name(isa);
        for (uint32_t k = 0; k < run; ++k) {
          const bool expected = one.crossed4(soa.data(), stride, first + k, t0, t1) & 1u;
          EXPECT_EQ(bool(got >> k & 1), expected)
              << isa_name(isa) << ", trial " << trial << " box " << first + k;
          ++compared;
          crossings += expected;
        }
      }
    }
  }
  EXPECT_GT(crossings, compared / 20);
  EXPECT_LT(crossings, compared);
}

// The wide tests widen every exit as the four-at-a-time one does, negative exits too: boxes
// grazed at a face, an edge or a corner (grazing_box, grazing_ray: the ray reaches its
// target on the box at t = 1, or at t = -1 with its direction reversed) over segments that
// start or end right there, where only the widening decides. Fails if a kernel widens
// differently (or not at all) for either sign.
TEST(BoxTest, WideLanesWidenExitsAsFourAtATime) {
  std::mt19937_64 rng(31);
  uint64_t compared = 0, decided_by_widening = 0;
  for (int k = 0; k < 20000; ++k) {
    const float scale = grazing_scale(k);
    const ClipBox clip(grazing_box(k, rng));
    Ray ray = grazing_ray(k, scale, clip, rng);
    const bool behind = k % 4 >= 2;
    if (behind) ray.dir = -ray.dir;
    const float target = behind ? -1.0f : 1.0f;
    const __m128 t0 = _mm_set1_ps(k % 2 ? target : -1e30f);
    const __m128 t1 = _mm_set1_ps(k % 2 ? 1e30f : target);
    float soa[box_floats(1)] = {};
    for (int a = 0; a < 3; ++a) soa[4 * a] = clip.lo_float[a], soa[4 * (a + 3)] = clip.hi_float[a];
    const RayBoxes one(ray);
    const bool expected = one.crossed4(soa, 4, 0, t0, t1) & 1u;
    // The same test with unwidened exits: where it differs, the widening decided.
    __m128 entry = t0, exit = t1;
    for (int a = 0; a < 3; ++a) {
      const __m128 near_face = _mm_set1_ps(soa[4 * one.near_array[a]]);
      const __m128 far_face = _mm_set1_ps(soa[4 * one.far_array[a]]);
      entry = _mm_max_ps(_mm_mul_ps(_mm_sub_ps(near_face, one.origin[a]), one.inv_dir[a]), entry);
      exit = _mm_min_ps(_mm_mul_ps(_mm_sub_ps(far_face, one.origin[a]), one.inv_dir[a]), exit);
    }
    decided_by_widening += expected != bool(_mm_movemask_ps(_mm_cmple_ps(entry, exit)) & 1);
    for (const Isa isa : supported_isas()) {
      EXPECT_EQ(kernel_for(isa).boxes_crossed(one, soa, 4, 0, 1, t0, t1), uint64_t{expected})
          << isa_name(isa) << ", ray " << k;
      ++compared;
    }
  }
  EXPECT_GT(compared, 20000u);
  EXPECT_GT(decided_by_widening, 100u);
}

// The wide kernels widen only the least of the axes' exact exits, once per box, where the
// four-lane test widens each axis's exit: the same answer, since the widening is
// nondecreasing in the distance. Checked box by box against the four-lane test on slab
// distances from a pool of grazing (a far face one float either side of where the ray
// reaches it at t = +-1), zero, negative-zero, tiny, huge and infinite figures, faces the
// origin lies on (0 * inf = NaN, dropped) and zero direction components; counts the boxes
// where the widening decided (the test without it answers otherwise), so that it cannot pass
// without meeting a case the widening matters for.
TEST(BoxTest, WideningTheLeastExitDecidesAsWideningEach) {
  std::mt19937_64 rng(37);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  const float kSpecial[] = {0.0f, -0.0f, 1e-41f, -1e-41f, 1e30f, -1e30f, INFINITY, -INFINITY};
  const auto pick = [&](int k) {
    return k % 5 == 0 ? kSpecial[rng() % 8] : (k % 3 == 0 ? 1e4f : 1.0f) * unit(rng);
  };
  constexpr uint32_t kBoxes = 16;
  uint64_t compared = 0, decided_by_widening = 0;
  for (int k = 0; k < 20000; ++k) {
    Ray ray;
    ray.origin = {unit(rng), unit(rng), unit(rng)};
    ray.dir = {unit(rng), unit(rng), unit(rng)};
    if (k % 7 == 0) ray.dir[k % 3] = k % 2 ? 0.0f : -0.0f;
    RayBoxes one(ray);
    float origin[3], inv_dir[3];
    for (int a = 0; a < 3; ++a) {
      if (k % 3 == 0) one.origin[a] = _mm_set1_ps(pick(k + a));
      origin[a] = _mm_cvtss_f32(one.origin[a]), inv_dir[a] = _mm_cvtss_f32(one.inv_dir[a]);
    }
    float soa[box_floats(kBoxes)] = {};
    for (uint32_t box = 0; box < kBoxes; ++box)
      for (int a = 0; a < 3; ++a) {
        const float reach = origin[a] + (box % 2 ? 1.0f : -1.0f) / inv_dir[a];
        const float far = box % 4 == 0 ? pick(k + int(box))
                                       : std::nextafter(reach, rng() % 2 ? INFINITY : -INFINITY);
        const float near = box % 9 == 0 ? origin[a] : pick(k + 2 * int(box));
        soa[one.far_array[a] * kBoxes + box] = far, soa[one.near_array[a] * kBoxes + box] = near;
      }
    const float ends[] = {-1e30f, -1.0f, -0.0f, 0.0f, 1.0f, 1e30f, INFINITY};
    const __m128 t0 = _mm_set1_ps(ends[rng() % 5]), t1 = _mm_set1_ps(ends[2 + rng() % 5]);
    for (uint32_t box = 0; box < kBoxes; ++box) {
      const bool expected = one.crossed4(soa, kBoxes, box, t0, t1) & 1u;
      // The same test with unwidened exits: where it differs, the widening decided.
      __m128 entry = t0, exit = t1;
      for (int a = 0; a < 3; ++a) {
        const __m128 near = _mm_set1_ps(soa[one.near_array[a] * kBoxes + box]);
        const __m128 far = _mm_set1_ps(soa[one.far_array[a] * kBoxes + box]);
        entry = _mm_max_ps(_mm_mul_ps(_mm_sub_ps(near, one.origin[a]), one.inv_dir[a]), entry);
        exit = _mm_min_ps(_mm_mul_ps(_mm_sub_ps(far, one.origin[a]), one.inv_dir[a]), exit);
      }
      decided_by_widening += expected != bool(_mm_movemask_ps(_mm_cmple_ps(entry, exit)) & 1);
      for (const Isa isa : supported_isas()) {
        const uint64_t got = kernel_for(isa).boxes_crossed(one, soa, kBoxes, 0, kBoxes, t0, t1);
        ASSERT_EQ(bool(got >> box & 1), expected)
            << isa_name(isa) << ", case " << k << " box " << box;
        ++compared;
      }
    }
  }
  EXPECT_EQ(compared, 20000u * kBoxes * supported_isas().size());
  EXPECT_GT(decided_by_widening, 1000u);
}

// A packet's rays against one box or a run of boxes, several rays at a time (RayBoxLanes, by
// every kernel this CPU has: 4, 8 or 16 rays in lanes), say for every ray and box what the
// one-ray test (RayBoxes) says:
// rays with the same direction signs (zero and -0 components among them, and rays from far
// away, which every box passes), each over its own segment.
TEST(BoxTest, RaysInLanesAgreeWithOneRayAtATime) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f), positive(0.0f, 1.0f);
  uint64_t agreed = 0, crossings = 0;
  for (int trial = 0; trial < 200; ++trial) {
    float soa[box_floats(4)] = {};
    for (int box = 0; box < 4; ++box)
      for (int a = 0; a < 3; ++a) {
        const float x = unit(rng), y = unit(rng);
        soa[a * 4 + box] = std::min(x, y), soa[(a + 3) * 4 + box] = std::max(x, y);
      }
    const glm::vec3 signs(trial & 1 ? -1.0f : 1.0f, trial & 2 ? -1.0f : 1.0f,
                          trial & 4 ? -1.0f : 1.0f);
    RayBoxLanes lanes;
    std::vector<RayBoxes> one;
    struct Segment {
      __m128 t0, t1;
    };
    std::vector<Segment> segments;
    for (uint32_t r = 0; r < 64; ++r) {
      Ray ray;
      ray.origin = {2.0f * unit(rng), 2.0f * unit(rng), 2.0f * unit(rng)};
      ray.dir = signs * glm::vec3(positive(rng), positive(rng), positive(rng));
      if (r % 9 == 0) ray.dir[r % 3] = signs[r % 3] * 0.0f;  // +0 or -0 with the sign
      const bool cull = r % 17 != 0;
      const __m128 t0 = _mm_set1_ps(r % 5 == 0 ? -1.0f : 0.0f);
      const __m128 t1 = _mm_set1_ps(r % 7 == 0 ? 0.5f : 1e30f);
      one.emplace_back(ray, cull);
      segments.push_back({t0, t1});
      lanes.set(r, one.back(), t0, t1);
    }
    const uint64_t mask = trial % 3 == 0 ? 0x0F0F00FF0000F0F1u : ~uint64_t{0};
    // Boxes 1 .. 3 together, or box 2 alone.
    const uint32_t first = 1 + trial % 2, count = trial % 2 ? 1 : 3;
    for (const Isa isa : supported_isas()) {
      uint64_t got[4] = {};
      const uint64_t crossed =
          kernel_for(isa).rays_crossed(lanes, soa, 4, first, (uint64_t{1} << count) - 1, mask, got);
      for (uint32_t k = 0; k < count; ++k) {
        EXPECT_EQ(got[k] & ~mask, 0u);
        EXPECT_EQ(bool(crossed >> k & 1), got[k] != 0);
        for (uint32_t r = 0; r < 64; ++r) {
          if (!(mask >> r & 1)) continue;
          const bool expected =
              one[r].crossed4(soa, 4, 0, segments[r].t0, segments[r].t1) >> (first + k) & 1u;
          EXPECT_EQ(bool(got[k] >> r & 1), expected)
              << isa_name(isa) << ", trial " << trial << " box " << first + k << " ray " << r;
          agreed += bool(got[k] >> r & 1) == expected;
          crossings += expected;
        }
      }
    }
  }
  EXPECT_GT(crossings, agreed / 20);  // about one in ten rays crosses the box
  EXPECT_LT(crossings, agreed);
}

// The bounds of `rays` (bits) of `lanes`, from their lanes by plain loops: the least and the
// greatest origin and 1 / dir per axis, the least t0 and the greatest t1.
RayBoxBounds bounds_of(const RayBoxLanes& lanes, uint64_t rays) {
  const float inf = std::numeric_limits<float>::infinity();
  float lo[3] = {inf, inf, inf}, hi[3] = {-inf, -inf, -inf};
  float inv_lo[3] = {inf, inf, inf}, inv_hi[3] = {-inf, -inf, -inf};
  float t0 = inf, t1 = -inf;
  for (uint32_t r = 0; r < 64; ++r) {
    if (!(rays >> r & 1)) continue;
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], lanes.origin[a][r]), hi[a] = std::max(hi[a], lanes.origin[a][r]);
      inv_lo[a] = std::min(inv_lo[a], lanes.inv_dir[a][r]);
      inv_hi[a] = std::max(inv_hi[a], lanes.inv_dir[a][r]);
    }
    t0 = std::min(t0, lanes.t0[r]), t1 = std::max(t1, lanes.t1[r]);
  }
  RayBoxBounds bounds;
  bounds.set(lo, hi, inv_lo, inv_hi, t0, t1);
  return bounds;
}

// A packet's bounds rule out a box only when no ray of the packet crosses it, by the one-ray
// test (RayBoxes), with every instruction set this CPU has: packets whose rays share an
// origin (a camera's) or spread from many, with zero and -0 components and far rays among
// them, against boxes around, behind and beside them. And they do rule boxes out: most of
// those no ray of a one-origin packet crosses.
TEST(BoxTest, PacketBoundsRuleOutOnlyBoxesNoRayCrosses) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f), positive(0.2f, 1.0f);
  uint64_t boxes_seen = 0, crossed = 0, missed_by_all = 0, ruled_out = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const glm::vec3 signs(trial & 1 ? -1.0f : 1.0f, trial & 2 ? -1.0f : 1.0f,
                          trial & 4 ? -1.0f : 1.0f);
    const bool one_origin = trial % 3 != 0, specials = trial % 5 == 4;
    const glm::vec3 eye(2.0f * unit(rng), 2.0f * unit(rng), 2.0f * unit(rng));
    const glm::vec3 centre = signs * glm::vec3(positive(rng), positive(rng), positive(rng));
    RayBoxLanes lanes;
    std::vector<RayBoxes> one;
    struct Segment {
      __m128 t0, t1;
    };
    std::vector<Segment> segments;
    std::vector<Ray> traced;
    for (uint32_t r = 0; r < 64; ++r) {
      Ray ray;
      ray.origin = one_origin ? eye : eye + 0.3f * glm::vec3(unit(rng), unit(rng), unit(rng));
      ray.dir = centre + 0.05f * glm::vec3(unit(rng), unit(rng), unit(rng));
      for (int a = 0; a < 3; ++a) ray.dir[a] = signs[a] * std::abs(ray.dir[a]);
      if (specials && r % 9 == 0) ray.dir[r % 3] = signs[r % 3] * 0.0f;  // +0 or -0
      const bool cull = !(specials && r % 17 == 3);                      // a far ray
      const __m128 t0 = _mm_set1_ps(r % 5 == 0 ? -0.5f : 0.0f);
      const __m128 t1 = _mm_set1_ps(r % 7 == 0 ? 2.0f : 1e30f);
      one.emplace_back(ray, cull);
      traced.push_back(ray);
      segments.push_back({t0, t1});
      lanes.set(r, one.back(), t0, t1);
    }
    // All rays, some, or one (whose bounds are the ray itself).
    const uint64_t rays = trial % 4 == 0   ? 0x00FF0F0F000000F1u
                          : trial % 4 == 1 ? uint64_t{1} << (trial % 64)
                                           : ~uint64_t{0};
    lanes.bounds = bounds_of(lanes, rays);
    alignas(16) float soa[box_floats(64)] = {};
    for (uint32_t box = 0; box < 64; ++box) {
      // Every other box has a corner on a ray of the mask, so that many rays just graze it.
      uint32_t grazed = uint32_t(rng() % 64);
      while (!(rays >> grazed & 1)) grazed = (grazed + 1) % 64;
      const glm::vec3 corner = traced[grazed].origin + (0.5f + positive(rng)) * traced[grazed].dir;
      for (int a = 0; a < 3; ++a) {
        const float size = 0.05f + 0.5f * positive(rng);
        float lo = eye[a] + 3.0f * unit(rng) - size, hi = lo + 2.0f * size;
        if (box % 2) lo = box >> (a + 1) & 1 ? corner[a] : corner[a] - size, hi = lo + size;
        soa[a * 64 + box] = lo, soa[(a + 3) * 64 + box] = hi;
      }
    }
    const uint32_t first = uint32_t(trial % 3) * 4, count = 64 - first - uint32_t(trial % 7);
    uint64_t four_at_a_time = 0;
    for (uint32_t k = 0; k < count; k += 4)
      four_at_a_time |= uint64_t(lanes.may_cross4(soa, 64, first + k)) << k;
    if (count < 64) four_at_a_time &= (uint64_t{1} << count) - 1;
    for (const Isa isa : supported_isas())
      EXPECT_EQ(kernel_for(isa).bounds_crossed(lanes, soa, 64, first, count), four_at_a_time)
          << isa_name(isa) << ", trial " << trial;
    for (uint32_t k = 0; k < count; ++k) {
      bool any = false;
      for (uint32_t r = 0; r < 64; ++r)
        any |= (rays >> r & 1) &&
               (one[r].crossed4(soa, 64, (first + k) & ~3u, segments[r].t0, segments[r].t1) >>
                    ((first + k) & 3) &
                1);
      const bool may = four_at_a_time >> k & 1;
      if (any) {
        EXPECT_TRUE(may) << "trial " << trial << " box " << first + k;
      }
      ++boxes_seen, crossed += any;
      if (!any && one_origin && !specials) ++missed_by_all, ruled_out += !may;
    }
  }
  EXPECT_GT(crossed, boxes_seen / 20);
  EXPECT_GT(missed_by_all, boxes_seen / 4);
  EXPECT_GT(ruled_out, missed_by_all * 3 / 4);
}

// The box the packet start's rays are made for.
const Box kStartBox{glm::vec3(-1.0f, -2.0f, -1.5f), glm::vec3(2.0f, 1.0f, 2.5f)};

// Rays for the packet start: ordinary ones through and past a box, and the cases every
// branch of start_walk takes: zero and negative-zero components, origins on the box's faces
// and far away, empty or inverted [tmin, tmax], infinite and NaN numbers. Then packets of
// rays from outside that mostly miss the box, one in eight aimed at a point of a face or an
// edge and grazing it: lane groups the float test (ClipBox::misses_surely) turns away whole,
// and groups it splits.
std::vector<Ray> start_rays(std::mt19937& random) {
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  const float inf = std::numeric_limits<float>::infinity(), nan = std::nanf("");
  const float specials[] = {0.0f, -0.0f, 2.0f, -1.0f, 1e-30f, -1e30f, inf, nan, 3e9f};
  std::vector<Ray> rays;
  for (int i = 0; i < 64 * 40; ++i) {
    Ray ray;
    // Mostly toward a point near the box's centre, so that most rays start a walk.
    for (int a = 0; a < 3; ++a)
      ray.origin[a] = 4.0f * unit(random), ray.dir[a] = unit(random) - ray.origin[a];
    ray.tmin = 0.0f, ray.tmax = inf;
    switch (i % 11) {
      case 1:  // a component special
        ray.dir[i % 3] = specials[(i / 11) % 9];
        break;
      case 2:
        ray.origin[(i / 3) % 3] = specials[(i / 7) % 9];
        break;
      case 3:  // on a face, along it
        ray.origin[i % 3] = 2.0f, ray.dir[i % 3] = (i / 11) % 2 ? 0.0f : -0.0f;
        break;
      case 4:
        ray.tmin = 2.0f * unit(random), ray.tmax = ray.tmin + unit(random);
        break;
      case 5:  // the stop distance's next float up from zero is the smallest denormal
        ray.tmax = std::array{nan, 0.5f, 0.0f, -0.0f}[(i / 11) % 4];
        ray.tmin = ray.tmax == 0.0f ? -1.0f : 0.0f;
        break;
      case 6:  // from far away toward the box
        for (int a = 0; a < 3; ++a)
          ray.origin[a] = 1e7f * unit(random), ray.dir[a] = -ray.origin[a];
        break;
      default:
        break;
    }
    rays.push_back(ray);
  }
  const glm::vec3 centre = 0.5f * (kStartBox.lo + kStartBox.hi);
  for (int i = 0; i < 64 * 6; ++i) {
    Ray ray;
    glm::vec3 target;
    for (int a = 0; a < 3; ++a) target[a] = (i >> a & 1) ? kStartBox.lo[a] : kStartBox.hi[a];
    target[i % 3] = centre[i % 3] + 0.5f * unit(random) * (kStartBox.hi - kStartBox.lo)[i % 3];
    const glm::vec3 out(unit(random), unit(random), unit(random));
    ray.origin = target + 3.0f * out;
    ray.dir = i % 8 == 0 ? target - ray.origin : out + 0.3f * glm::vec3(unit(random));
    rays.push_back(ray);
  }
  // Packets of rays from inside the box at tmin +-0 (shadow rays, a camera in a room), which
  // skip the first clip when a whole lane group does: every one inside in the first blocks;
  // then one in five on the box rounded inward, one float beyond the box, or at a tmin that
  // is not zero, so that groups mix the two ways.
  const ClipBox clip(kStartBox);
  for (int i = 0; i < 64 * 8; ++i) {
    Ray ray;
    for (int a = 0; a < 3; ++a) {
      const float t = 0.5f + 0.5f * unit(random);
      ray.origin[a] = kStartBox.lo[a] + t * (kStartBox.hi[a] - kStartBox.lo[a]);
      ray.dir[a] = unit(random);
    }
    ray.tmin = (i / 64) % 2 ? -0.0f : 0.0f, ray.tmax = (i % 7 == 3) ? 0.0f : 1.5f;
    if (i % 13 == 5) ray.dir[i % 3] = (i / 13) % 2 ? 0.0f : -0.0f;
    if (i >= 64 * 4 && i % 5 == 0) {
      const int a = (i / 5) % 3;
      switch ((i / 15) % 4) {
        case 0:
          ray.origin[a] = (i / 2) % 2 ? clip.hi_inward[a] : clip.lo_inward[a];
          break;
        case 1:  // the box rounded outward: outside the box itself where that rounded
          ray.origin[a] = (i / 2) % 2 ? clip.hi_float[a] : clip.lo_float[a];
          break;
        case 2:
          ray.origin[a] = (i / 2) % 2 ? std::nextafter(clip.hi_float[a], INFINITY)
                                      : std::nextafter(clip.lo_float[a], -INFINITY);
          break;
        default:
          ray.tmin = (i / 2) % 2 ? 1e-30f : -1e-30f;
          break;
      }
    }
    rays.push_back(ray);
  }
  return rays;
}

// The packet's start in lanes (PacketLaneOps::start and prepare), with every instruction
// set this CPU has, sets each ray up exactly as the single-ray walk does: start_walk's line,
// PreparedRay's figures, RayBoxes' float origin and 1 / dir, box_test_start, the stop
// distance and box_test_end, bit for bit; and the packet's bounds (RayBoxBounds) are those
// of its rays' lanes.
TEST(PacketLanes, StartIsTheSingleRayStartBitForBit) {
  std::mt19937 random(11);
  const std::vector<Ray> rays = start_rays(random);
  const ClipBox box(kStartBox);
  size_t tried = 0, walks = 0, misses = 0, far = 0, bounded_axes = 0, from_inside = 0;
  for (const Isa isa : supported_isas()) {
    const PacketLaneOps ops = packet_lane_ops(isa);
    for (size_t packet = 0; packet < rays.size(); packet += 64) {
      PacketLines lines;
      const uint32_t count = 1 + uint32_t(packet / 64) % 64;  // every packet size
      for (uint32_t i = 0; i < count; ++i) lines.set_ray(i, rays[packet + i]);
      const uint64_t started = ops.start(box, count, lines);
      EXPECT_EQ(count == 64 ? 0u : started >> count, 0u);
      for (uint32_t i = 0; i < count; ++i) {
        const Ray& ray = rays[packet + i];
        WalkLine line;
        const bool starts = start_walk(box, ray, line);
        ASSERT_EQ(bool(started >> i & 1), starts) << isa_name(isa) << " ray " << packet + i;
        ++tried, misses += !starts;
        if (!starts) continue;
        ++walks, from_inside += box.starts_inside(ray);
        for (int a = 0; a < 3; ++a) {
          EXPECT_EQ(bits(lines.origin[a][i]), bits(line.origin[a]));
          EXPECT_EQ(bits(lines.dir[a][i]), bits(line.dir[a]));
          EXPECT_EQ(bits(lines.inv_dir[a][i]), bits(line.inv_dir[a]));
        }
        EXPECT_EQ(bits(lines.shift[i]), bits(line.shift));
        EXPECT_EQ(bits(lines.t0[i]), bits(line.t0));
        EXPECT_EQ(bits(lines.slack[i]), bits(line.slack));
        EXPECT_EQ(bool(lines.far >> i & 1), line.far);
        far += line.far;
        const PreparedRay<KernelReal> prepared(ray, line.shift, line.inv_dir);
        const int octant = std::signbit(line.dir[0]) | std::signbit(line.dir[1]) << 1 |
                           std::signbit(line.dir[2]) << 2;
        EXPECT_EQ(lines.kind[i], octant | prepared.kz << 3) << isa_name(isa);
        if (line.far) continue;  // a far ray walks alone: never prepared in lanes
        // The rest for this ray alone, with its own axes.
        RayLanes kernel_lanes;
        RayBoxLanes box_lanes;
        const int axes[3] = {prepared.kx, prepared.ky, prepared.kz};
        kernel_lanes.kx = axes[0], kernel_lanes.ky = axes[1], kernel_lanes.kz = axes[2];
        ops.prepare(lines, uint64_t{1} << i, axes, kernel_lanes, box_lanes);
        const PreparedRay<KernelReal> got = kernel_lanes.prepared(i);
        for (int a = 0; a < 3; ++a) EXPECT_EQ(bits(got.origin[a]), bits(prepared.origin[a]));
        EXPECT_EQ(bits(got.sx), bits(prepared.sx));
        EXPECT_EQ(bits(got.sy), bits(prepared.sy));
        EXPECT_EQ(bits(got.sz), bits(prepared.sz));
        EXPECT_EQ(bits(got.shift), bits(prepared.shift));
        EXPECT_EQ(bits(got.tmin), bits(prepared.tmin));
        EXPECT_EQ(bits(kernel_lanes.tmax[i]), bits(ray.tmax));
        const RayBoxes boxes(ray, !line.far);
        for (int a = 0; a < 3; ++a) {
          EXPECT_EQ(bits(box_lanes.origin[a][i]), bits(_mm_cvtss_f32(boxes.origin[a])));
          EXPECT_EQ(bits(box_lanes.inv_dir[a][i]), bits(_mm_cvtss_f32(boxes.inv_dir[a])));
        }
        const double stop = line.stop(ray.tmax);
        EXPECT_EQ(bits(lines.stop[i]), bits(stop));
        EXPECT_EQ(bits(box_lanes.t0[i]), bits(_mm_cvtss_f32(box_test_start(line))));
        EXPECT_EQ(bits(box_lanes.t1[i]), bits(_mm_cvtss_f32(box_test_end(line, stop))));
      }
      // The packet's bounds over the started rays (not far) of the first one's kind, as
      // prepare leaves them: those of its lanes.
      const uint64_t near = started & ~lines.far;
      if (near == 0) continue;
      const int32_t kind = lines.kind[std::countr_zero(near)];
      uint64_t group = 0;
      for (uint32_t i = 0; i < count; ++i)
        group |= uint64_t((near >> i & 1) && lines.kind[i] == kind) << i;
      RayLanes kernel_lanes;
      RayBoxLanes box_lanes;
      const int axes[3] = {0, 1, 2};
      ops.prepare(lines, group, axes, kernel_lanes, box_lanes);
      const RayBoxBounds expected = bounds_of(box_lanes, group);
      const RayBoxBounds& got = box_lanes.bounds;
      const auto same = [](__m128 x, __m128 y) {
        return bits(_mm_cvtss_f32(x)) == bits(_mm_cvtss_f32(y));
      };
      EXPECT_EQ(got.axes, expected.axes) << isa_name(isa) << " packet " << packet;
      bounded_axes += std::popcount(got.axes);
      EXPECT_TRUE(same(got.t0_lo, expected.t0_lo) && same(got.t1_hi, expected.t1_hi));
      for (int a = 0; a < 3; ++a)
        EXPECT_TRUE(same(got.near_origin[a], expected.near_origin[a]) &&
                    same(got.far_origin[a], expected.far_origin[a]) &&
                    same(got.inv_lo[a], expected.inv_lo[a]) &&
                    same(got.inv_hi[a], expected.inv_hi[a]))
            << isa_name(isa) << " packet " << packet << " axis " << a;
    }
  }
  EXPECT_GT(bounded_axes, 0u);
  // Both outcomes, far rays and rays from inside at tmin 0 (whole lane groups of them, by
  // the packets built for them), are checked.
  EXPECT_GT(walks, tried / 4);
  EXPECT_GT(misses, tried / 10);
  EXPECT_GT(far, 10u);
  EXPECT_GT(from_inside, walks / 10);
}

// The packet start's float test (PacketLaneOps::turned_away), with every instruction set
// this CPU has, turns away exactly the rays ClipBox::misses_surely turns away, and the
// start then starts exactly the rays start_walk starts: packets of 64 rays grazing one box,
// at three scales.
TEST(PacketLanes, FloatTestIsTheClipBoxsBitForBit) {
  std::mt19937_64 rng(31);
  uint64_t turned_total = 0, rays_total = 0;
  for (const Isa isa : supported_isas()) {
    const PacketLaneOps ops = packet_lane_ops(isa);
    for (int packet = 0; packet < 600; ++packet) {
      const float scale = grazing_scale(packet);
      const ClipBox box(grazing_box(packet, rng));
      PacketLines lines;
      Ray rays[64];
      for (uint32_t i = 0; i < 64; ++i) {
        rays[i] = grazing_ray(64 * packet + int(i), scale, box, rng);
        lines.set_ray(i, rays[i]);
      }
      const uint64_t turned = ops.turned_away(box, 64, lines);
      const uint64_t started = ops.start(box, 64, lines);
      for (uint32_t i = 0; i < 64; ++i) {
        ASSERT_EQ(bool(turned >> i & 1), box.misses_surely(rays[i]))
            << isa_name(isa) << " packet " << packet << " ray " << i;
        WalkLine line;
        ASSERT_EQ(bool(started >> i & 1), start_walk(box, rays[i], line))
            << isa_name(isa) << " packet " << packet << " ray " << i;
      }
      turned_total += uint64_t(std::popcount(turned)), rays_total += 64;
    }
  }
  EXPECT_GT(turned_total, rays_total / 8);
}

// Every structure, with every kernel this CPU has, answers exactly what brute answers:
// nearest hits bit for bit, lazy and eager, 1 and 2 threads.
class EveryKernel : public testing::TestWithParam<Isa> {};

TEST_P(EveryKernel, EveryStructureMatchesBrute) {
  const Isa before = kernel_isa();
  force_kernel_isa(GetParam());
  const Scene scene = test::sphere_in_soup();
  test::RayMix mix;
  mix.camera_width = mix.camera_height = 24;
  mix.chords = mix.axis_parallel = mix.edges_and_vertices = 600;
  const std::vector<Ray> rays = test::mixed_rays(scene, mix);
  const std::vector<Hit> expected = test::brute_answers(scene, rays);
  size_t hits = 0;
  for (const Hit& hit : expected) hits += hit.found();
  EXPECT_GT(hits, rays.size() / 4);
  for (const std::string name : {"grid1d", "uniform", "octree", "grid3d", "bvh"}) {
    std::vector<test::StructureRun> runs = test::lazy_and_eager_runs(name);
    for (test::StructureRun run : test::lazy_and_eager_runs(name)) {
      run.sample = true;
      runs.push_back(run);
    }
    // grid1d's packet walk: its per-ray node arithmetic and its leaf tests run on this
    // instruction set's lanes too.
    for (test::StructureRun run : test::lazy_and_eager_runs(name)) {
      if (name != "grid1d") break;
      run.packet = 64;
      runs.push_back(run);
    }
    EXPECT_EQ(test::disagreements(scene, rays, runs, expected), 0u)
        << name << " " << isa_name(GetParam());
  }
  force_kernel_isa(before);
}

INSTANTIATE_TEST_SUITE_P(Isas, EveryKernel, testing::ValuesIn(supported_isas()),
                         [](const auto& info) { return std::string(isa_name(info.param)); });

}  // namespace
}  // namespace gs
