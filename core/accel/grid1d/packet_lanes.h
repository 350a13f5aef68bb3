// The packet walk's per-ray arithmetic (packet.cpp), a packet's rays several at a time in
// SIMD lanes: where each ray lies in a node's array, and which rays step into a cell
// between its walls. Every lane performs the scalar operations in the same order (no fused
// multiply-adds), so each ray's figures do not depend on the instruction set. One template
// (packet_lanes_impl.h) compiled per instruction set, picked with the leaf kernel's
// instruction set (core/geometry/leaf.h).
#pragma once
#include <cstdint>

#include "core/geometry/clip_box.h"
#include "core/geometry/leaf.h"

namespace gs {

// Arrays indexed by a ray's number in the packet, padded so that the widest lanes (8)
// read from any ray on stay inside.
inline constexpr uint32_t kPacketLanes = 64 + 8;

// The packet's rays' walk lines (WalkLine), structure of arrays, and each ray's stop
// distance (WalkLine::stop of its nearest hit so far).
struct PacketLines {
  alignas(64) double origin[3][kPacketLanes] = {}, dir[3][kPacketLanes] = {},
                     inv_dir[3][kPacketLanes] = {};
  alignas(64) double slack[kPacketLanes] = {}, stop[kPacketLanes] = {};

  void set(uint32_t lane, const WalkLine& line) {
    for (int a = 0; a < 3; ++a) {
      origin[a][lane] = line.origin[a], dir[a][lane] = line.dir[a];
      inv_dir[a][lane] = line.inv_dir[a];
    }
    slack[lane] = line.slack;
  }
};

// A node's cells on the global grid of its traversal state: wall I of the grid lies at
// origin + I * width; the node's cell c is the grid's slab first + c, c in 0 .. last.
struct NodeCells {
  int axis;
  double origin, scale, width;
  double first, last;
};

// Where the rays are in a node: per ray the distance to the grid's wall 0 and between walls
// (as the single walk's traversal state has them), and the cells lo .. hi its segment
// covers, one more each side (point location rounds; the walls decide).
struct PacketCover {
  alignas(64) double t_origin[kPacketLanes], t_width[kPacketLanes];
  alignas(64) int32_t lo[kPacketLanes], hi[kPacketLanes];
  int32_t cover_lo, cover_hi;  // the union of the rays' lo .. hi
};

// Fills `cover` for the rays of `rays` (bits), each inside the node from t_in to t_out on
// its line. Reads and writes whole lane groups that hold one of them.
using CoverCells = void (*)(const PacketLines& lines, const NodeCells& node, uint64_t rays,
                            const double* t_in, const double* t_out, PacketCover& cover);
// Of `rays`, those whose segment t_in .. t_out crosses the cell between walls `wall` and
// `wall` + 1 of the cover's grid (widened by the ray's slack) before the ray's stop
// distance; their part of the segment in child_in .. child_out.
using EnterCell = uint64_t (*)(const PacketLines& lines, int axis, const PacketCover& cover,
                               double wall, uint64_t rays, const double* t_in, const double* t_out,
                               double* child_in, double* child_out);

struct PacketLaneOps {
  CoverCells cover;
  EnterCell enter;
};
PacketLaneOps packet_lane_ops(Isa isa);

// Per instruction set (packet_lanes*.cpp): 2 (SSE2), 4 (AVX2) and 8 (AVX-512) lanes.
PacketLaneOps packet_lane_ops_sse2();
PacketLaneOps packet_lane_ops_avx2();
PacketLaneOps packet_lane_ops_avx512();

}  // namespace gs
