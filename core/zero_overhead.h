// The paper's zero-overhead method (Jevans 1990 §7, DESIGN.md §1): given the hit file of an
// earlier run over the same rays, each ray is tested against exactly the one triangle it
// hit (a miss tests nothing). No acceleration structure can do less work, so its time is
// the floor the others are measured against.
//
// The oracle is keyed by the ray's position in the ray file, which intersect() reads from
// ThreadContext::ray_index (run_trace sets it; see accelerator.h). A ray traced without an
// index (a render, the viewer) is a UsageError rather than a silent wrong answer: keying
// renders by (pixel, sample, bounce, kind) is not done yet. The test is brute's own (clip
// box, prepared ray, watertight kernel), so on the rays brute answered it gives brute's
// hits bit for bit.
#pragma once
#include <string>
#include <vector>

#include "core/accelerator.h"
#include "core/geometry.h"

namespace gs {

class ZeroOverhead final : public Accelerator {
 public:
  // Throws UsageError when params.oracle_path is empty.
  explicit ZeroOverhead(const AccelParams& params);
  std::string name() const override { return "zero"; }
  // Reads the oracle; throws InputError naming it when it cannot be read, is malformed or
  // names a triangle the scene does not have.
  void build(const Scene& scene) override;
  Box bounds() const override { return bounds_; }
  std::unique_ptr<ThreadContext> make_context() const override;
  Hit intersect(const Ray& ray, ThreadContext& context) const override;
  // The same one test: the recorded triangle blocks the ray or nothing does.
  Hit any_hit(const Ray& ray, ThreadContext& context) const override;
  StructureStats stats() const override;

  const std::string& oracle_path() const { return oracle_path_; }
  size_t oracle_size() const { return oracle_.size(); }
  // Throws InputError naming the oracle unless it holds exactly `rays` hits.
  void check_ray_count(size_t rays) const;

 private:
  std::string oracle_path_;
  std::vector<Hit> oracle_;
  std::vector<TriangleVerts> triangles_;
  Box bounds_;
  ClipBox clip_box_;
  double build_seconds_ = 0.0;
};

}  // namespace gs
