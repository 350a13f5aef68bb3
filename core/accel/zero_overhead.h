// The paper's zero-overhead method (Jevans 1990 §7, docs/design.md §1): given the hit file of an
// earlier run over the same rays, each ray is tested against exactly the one triangle it
// hit (a miss tests nothing). No acceleration structure can do less work, so its time is
// the floor the others are measured against.
//
// The oracle is keyed by ThreadContext::ray_index: a ray's position in the ray file for
// `trace`, the ray's key (render_ray_key: pixel, sample, bounce, kind) for a render, so a
// recorded render (`render --record-hits`) replays exactly. A ray traced without a key is a
// UsageError rather than a silent wrong answer. The test is brute's own (clip box,
// prepared ray, watertight kernel), so on the rays brute answered it gives brute's hits
// bit for bit.
#pragma once
#include <string>
#include <vector>

#include "core/accel/accelerator.h"
#include "core/geometry/kernel.h"
#include "core/geometry/triangles.h"

namespace gs {

class ZeroOverhead final : public Accelerator {
 public:
  // Throws UsageError when params.oracle_path is empty.
  explicit ZeroOverhead(const AccelParams& params);
  // An oracle already in memory (the benchmark's own recorded run); oracle_path() is
  // "(memory)".
  explicit ZeroOverhead(std::vector<Hit> oracle);
  std::string name() const override { return "zero"; }
  // Reads the oracle (unless it is in memory); throws InputError naming it when it cannot
  // be read, is malformed or names a triangle the scene does not have.
  void build(const Scene& scene) override;
  Box bounds() const override { return bounds_; }
  std::unique_ptr<ThreadContext> make_context() const override;
  Hit intersect(const Ray& ray, ThreadContext& context) const override;
  // The same one test: the recorded triangle blocks the ray or nothing does.
  Hit any_hit(const Ray& ray, ThreadContext& context) const override;
  StructureStats stats() const override;

  const std::string& oracle_path() const { return oracle_path_; }
  size_t oracle_size() const { return oracle_.size(); }
  // Throws InputError naming the oracle unless it holds exactly `keys` hits, one per `what`
  // (a ray, or a render's ray key). Call after build().
  void check_ray_keys(size_t keys, const std::string& what) const override;

 private:
  std::string oracle_path_;
  bool oracle_in_memory_ = false;
  std::vector<Hit> oracle_;
  std::vector<TriangleVerts> triangles_;
  Box bounds_;
  ClipBox clip_box_;
  double build_seconds_ = 0.0;
};

}  // namespace gs
