// The reference every test compares with: every ray against every triangle, through the same
// float kernel the structures use, so that answers can be compared bit for bit.
#pragma once
#include <vector>

#include "core/accel/accelerator.h"
#include "core/geometry/kernel.h"
#include "core/geometry/triangles.h"

namespace gs {

class BruteForce final : public Accelerator {
 public:
  std::string name() const override { return "brute"; }
  void build(const Scene& scene) override;
  Box bounds() const override { return bounds_; }
  std::unique_ptr<ThreadContext> make_context() const override;
  Hit intersect(const Ray& ray, ThreadContext& context) const override;
  Hit any_hit(const Ray& ray, ThreadContext& context) const override;
  StructureStats stats() const override;
  // The same search with the kernel instantiated for long double, one step wider than the
  // kernel's own arithmetic: checks the kernel itself.
  Hit intersect_long_double(const Ray& ray) const;

 private:
  template <class Real, bool AnyHit>
  Hit trace(const Ray& ray, ThreadContext* context) const;

  std::vector<TriangleVerts> triangles_;
  std::vector<uint32_t> usable_;  // ids of the non-degenerate triangles
  Box bounds_;
  ClipBox clip_box_;
  double build_seconds_ = 0.0;
};

}  // namespace gs
