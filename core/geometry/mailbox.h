// Ray-id mailboxing (Amanatides & Woo 1987; Jevans 1990 §6.4): a triangle that lies in
// several cells is tested once per ray. Kept per thread in a small direct-mapped table
// instead of a stamp per triangle: the paper's per-object stamp would race between threads
// (docs/design.md §5), and the table stays in L1 whatever the scene's size. A collision only
// costs a repeated test, whose answer is the same. Ray ids are 64 bits: they never wrap.
#pragma once
#include <cstddef>
#include <cstdint>

namespace gs {

class Mailbox {
 public:
  // 512 slots of 12 bytes: 6 KiB, which stays in L1 beside a walk's other per-thread data.
  // A ray's tested triangles lie in a few neighbouring cells, and a mesh's neighbouring
  // triangles have nearby ids, so they fall in different slots; more slots were measured
  // to change nothing.
  static constexpr size_t kSlots = 512;
  static_assert((kSlots & (kSlots - 1)) == 0, "slots are picked by masking the id");

  uint64_t next_ray() { return ++ray_id_; }
  uint64_t current_ray() const { return ray_id_; }
  // True when `triangle` was already tested by `ray`; otherwise records it as tested.
  bool already_tested(uint32_t triangle, uint64_t ray) {
    const size_t slot = triangle & (kSlots - 1);
    if (ray_[slot] == ray && triangle_[slot] == triangle) return true;
    ray_[slot] = ray, triangle_[slot] = triangle;
    return false;
  }

 private:
  uint64_t ray_id_ = 0;
  uint64_t ray_[kSlots] = {};
  uint32_t triangle_[kSlots] = {};
};

// The mailbox of a packet of up to 64 rays walked together (docs/design.md §6.9): per slot a
// triangle, the packet and which of its rays tested it. A Mailbox slot per (ray, triangle)
// would thrash, the packet's rays testing the same triangles one after another.
class PacketMailbox {
 public:
  static constexpr size_t kSlots = Mailbox::kSlots;

  uint64_t next_packet() { return ++packet_id_; }
  // Of `rays` (bits of packet `packet`'s rays), those that already tested `triangle`; all of
  // them are recorded as having tested it.
  uint64_t mark(uint32_t triangle, uint64_t packet, uint64_t rays) {
    const size_t slot = triangle & (kSlots - 1);
    if (packet_[slot] != packet || triangle_[slot] != triangle) {
      packet_[slot] = packet, triangle_[slot] = triangle, rays_[slot] = rays;
      return 0;
    }
    const uint64_t already = rays_[slot] & rays;
    rays_[slot] |= rays;
    return already;
  }

 private:
  uint64_t packet_id_ = 0;
  uint64_t packet_[kSlots] = {};
  uint64_t rays_[kSlots] = {};
  uint32_t triangle_[kSlots] = {};
};

}  // namespace gs
