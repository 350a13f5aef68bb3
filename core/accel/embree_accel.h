// Intel Embree 3 as a reference structure (docs/design.md §3 `embree`; compiled only when CMake
// finds embree 3, which defines GRIDSCOPE_HAVE_EMBREE). One triangle geometry holds the
// scene's triangles in id order, so Embree's primID is our triangle id; degenerate
// triangles keep their slot with all three corners on their first vertex, which Embree
// skips. The scene is built with RTC_SCENE_FLAG_ROBUST (watertight-leaning traversal and
// test) at Embree's default build quality.
//
// Answers: intersect is rtcIntersect1: id = primID, t = tfar, u and v = Embree's u and v,
// which are, as ours, the weights of the triangle's second and third vertex. Embree does
// not promise the lowest id among hits at exactly equal t, and its float arithmetic is not
// our kernel's: on rays that graze an edge or a vertex it may answer another of the
// triangles meeting there, and t agrees to a few float ulps, not bit for bit.
// any_hit is rtcOccluded1, which answers only a boolean, with an occlusion filter on the
// geometry that records the hit it accepts (the first one Embree finds): so --occluded is
// as fast as Embree's occlusion query and still names a blocking triangle with its t, u, v.
// Invalid rays (ray_is_valid) are misses and never reach Embree. trace_packet is Embree's
// packet mode, 16 rays at a time, with the coherent-rays hint: faster here than 8 at a time
// by 12-26% on camera rays (README, Performance).
//
// Threads: the device builds with all cores (TBB) unless AccelParams::build_threads > 0
// (`--build-threads N`, Embree's "threads=N" device setting); tracing threads are the
// caller's. Stats: Embree exposes no node counts or per-ray work, so nodes, leaves,
// voxels, states are null and StructureStats says tests and steps are not counted (null
// in the stats file). memory_bytes is what Embree's device memory monitor reports still
// allocated after the build (scene, geometry buffers, BVH).
#pragma once
#include <atomic>
#include <cstdint>

#include "core/accel/accelerator.h"

struct RTCDeviceTy;
struct RTCSceneTy;

namespace gs {

class EmbreeAccel final : public Accelerator {
 public:
  explicit EmbreeAccel(const AccelParams& params);
  ~EmbreeAccel() override;
  EmbreeAccel(const EmbreeAccel&) = delete;
  EmbreeAccel& operator=(const EmbreeAccel&) = delete;

  std::string name() const override { return "embree"; }
  // Creates the device and commits the scene. Throws InputError ("embree: ...") when
  // Embree reports an error.
  void build(const Scene& scene) override;
  Box bounds() const override { return bounds_; }
  std::unique_ptr<ThreadContext> make_context() const override;
  Hit intersect(const Ray& ray, ThreadContext& context) const override;
  Hit any_hit(const Ray& ray, ThreadContext& context) const override;
  // rtcIntersect16 / rtcOccluded16 with the coherent-rays hint: Embree's packet mode.
  void trace_packet(std::span<const Ray> rays, std::span<const uint64_t> keys, std::span<Hit> hits,
                    bool any_hit, ThreadContext& context) const override;
  bool traces_packets() const override { return true; }
  StructureStats stats() const override;

 private:
  void release();

  int build_threads_ = 0;
  RTCDeviceTy* device_ = nullptr;
  RTCSceneTy* scene_ = nullptr;
  Box bounds_;
  double build_seconds_ = 0.0;
  std::atomic<int64_t> memory_bytes_{0};  // the device memory monitor's running total
};

}  // namespace gs
