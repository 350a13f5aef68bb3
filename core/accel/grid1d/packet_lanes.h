// The packet walk's per-ray arithmetic (packet.cpp), a packet's rays several at a time in
// SIMD lanes: each ray's start (validity, clipped line, kind) and its kernel and box-test
// set-up. Every lane performs the scalar operations in the same order (no fused
// multiply-adds), so each ray's figures do not depend on the instruction set. One template
// (packet_lanes_impl.h) compiled per instruction set, picked with the leaf kernel's
// instruction set (core/geometry/leaf.h).
#pragma once
#include <bit>
#include <cstdint>

#include "core/base/bit_count.h"
#include "core/geometry/box_test.h"
#include "core/geometry/clip_box.h"
#include "core/geometry/leaf.h"

namespace gs {

// Arrays indexed by a ray's number in the packet, padded so that the widest lanes (8)
// read from any ray on stay inside.
inline constexpr uint32_t kPacketLanes = 64 + 8;

// A packet's rays, numbered as given (up to 64), structure of arrays: the rays themselves
// (float, as Ray holds them), their walk lines (WalkLine, computed in double as start_walk
// computes them), and each ray's stop distance (WalkLine::stop of its nearest hit so far).
struct PacketLines {
  // The rays: filled by the caller before start.
  alignas(64) float ray_origin[3][kPacketLanes] = {}, ray_dir[3][kPacketLanes] = {};
  alignas(64) float tmin[kPacketLanes] = {}, tmax[kPacketLanes] = {};
  // Their lines.
  alignas(64) double origin[3][kPacketLanes] = {}, dir[3][kPacketLanes] = {},
                     inv_dir[3][kPacketLanes] = {};
  alignas(64) double shift[kPacketLanes] = {}, t0[kPacketLanes] = {};
  alignas(64) double slack[kPacketLanes] = {}, stop[kPacketLanes] = {};
  // The octant of the direction (bit a: component a's sign bit) and, times 8, the kernel's
  // axis kz (PreparedRay): rays of one kind take cells in one order with one kernel layout.
  alignas(64) int32_t kind[kPacketLanes] = {};
  uint64_t far = 0;  // bits: WalkLine::far

  void set_ray(uint32_t lane, const Ray& ray) {
    for (int a = 0; a < 3; ++a) ray_origin[a][lane] = ray.origin[a], ray_dir[a][lane] = ray.dir[a];
    tmin[lane] = ray.tmin, tmax[lane] = ray.tmax;
  }
};

// Of rays 0 .. count - 1 (set_ray'd), those the box's float test turns away
// (ClipBox::misses_surely, bit for bit): the start's first step.
using TurnedAway = uint64_t (*)(const ClipBox& box, uint32_t count, const PacketLines& lines);
// Starts the walks of rays 0 .. count - 1 (set_ray'd): for each, what start_walk gives
// (false for an invalid ray or one that misses the box) and its kind. Returns the rays that
// start a walk.
using StartRays = uint64_t (*)(const ClipBox& box, uint32_t count, PacketLines& lines);
// The rays of `rays`, all of one kind whose kernel axes are axes[0..2] (kx, ky, kz), in the
// forms the leaf kernel (PreparedRay) and the box test (RayBoxes, box_test_start/end of
// their stop distance) read, each as the single-ray walk sets them up; and their stop
// distances from their tmax.
using PrepareRays = void (*)(PacketLines& lines, uint64_t rays, const int axes[3],
                             RayLanes& kernel_lanes, RayBoxLanes& box_lanes);

// Whether the rays of `rays` search a run of `run` boxes of a leaf, of which the packet's
// bounds leave `boxes`, faster one at a time than together, with box tests `width` floats
// wide (Kernel::box_lanes). Together, each box takes a wide test per lane group holding
// one of the rays, and each triangle a ray crosses is tested with the rays in lanes; alone,
// a ray takes a wide test per `width` boxes of the run (the single walk's leaf filter) and
// tests its triangles in lanes. A few rays spread over the packet's groups in a leaf of
// many small triangles (a dense mesh reached by part of a tile, shadow rays that diverge)
// go faster alone.
inline bool searches_alone(uint64_t rays, uint64_t boxes, uint32_t run, uint32_t width) {
  const uint64_t group = (uint64_t{2} << (width - 1)) - 1;
  uint32_t groups = 0;
  for (uint64_t left = rays; left != 0; ++groups)
    left &= ~(group << (uint32_t(std::countr_zero(left)) & ~(width - 1)));
  // A ray alone also sets itself up (its box lanes, kernel figures, a kernel call of its
  // own): about three wide tests' worth, as measured on the bench scenes.
  constexpr uint32_t kSetUp = 3;
  return count_ones(rays) * ((run + width - 1) / width + kSetUp) < groups * count_ones(boxes);
}

struct PacketLaneOps {
  TurnedAway turned_away;
  StartRays start;
  PrepareRays prepare;
};
PacketLaneOps packet_lane_ops(Isa isa);

// Per instruction set (packet_lanes*.cpp): 2 (SSE2), 4 (AVX2) and 8 (AVX-512) lanes.
PacketLaneOps packet_lane_ops_sse2();
PacketLaneOps packet_lane_ops_avx2();
PacketLaneOps packet_lane_ops_avx512();

}  // namespace gs
