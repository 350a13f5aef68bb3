// The uniform grid the paper compares with (Jevans 1990 §7; Fujimoto et al. 1986): the
// scene box cut into equal cells, about cbrt(N) per side for N triangles (the paper's
// setting), or density * N cells in all with --density. Cells are as cubic as the box's
// aspect allows. Traversal is the 3D DDA of Cleary & Wyvill (1988) / Amanatides & Woo
// (1987) with ray-id mailboxing. Flat storage: per-cell offsets into one triangle index
// list (CSR).
#pragma once
#include <array>
#include <vector>

#include "core/accel/accelerator.h"
#include "core/geometry/leaf_test.h"
#include "core/geometry/kernel.h"

namespace gs {

class UniformGrid final : public Accelerator {
 public:
  explicit UniformGrid(const AccelParams& params) : params_(params) {}

  std::string name() const override { return "uniform"; }
  void build(const Scene& scene) override;
  Box bounds() const override { return bounds_; }
  std::unique_ptr<ThreadContext> make_context() const override;
  Hit intersect(const Ray& ray, ThreadContext& context) const override;
  Hit any_hit(const Ray& ray, ThreadContext& context) const override;
  // nodes = leaves = cells; voxels_subdivided = 0 (one level, nothing is cut further);
  // traversal_states = null (the paper's term for grid1d's shared states);
  // voxels_over_budget = the cells the resolution asked for but the memory budget (or
  // 32-bit reference counts) did not allow: the grid then has fewer cells per side.
  StructureStats stats() const override;

  // Read access for tests.
  std::array<uint32_t, 3> resolution() const { return {n_[0], n_[1], n_[2]}; }
  uint64_t cell_count() const { return uint64_t(n_[0]) * n_[1] * n_[2]; }
  uint64_t references() const { return tris_.size(); }

 private:
  template <bool AnyHit>
  Hit trace(const Ray& ray, MailboxContext& context) const;
  void choose_resolution(size_t triangles);
  void shrink_to(double cells);
  uint64_t grid_bytes(uint64_t refs) const;
  void fit_budget(const std::vector<uint32_t>& usable);
  void set_walls();
  uint32_t locate(int axis, double p) const;
  void cell_range(int axis, double lo, double hi, uint32_t& first, uint32_t& last) const;
  uint64_t sort_into_cells(const std::vector<uint32_t>& usable, bool fill);

  AccelParams params_;
  std::vector<TriangleVerts> triangles_;
  std::vector<double> tri_box_;  // per triangle lo.xyz, hi.xyz padded by the ClipBox padding
  Box bounds_;
  ClipBox box_;  // the grid's box: the padded scene box every ray is clipped to
  uint32_t n_[3] = {1, 1, 1};
  std::vector<double> walls_[3];   // n + 1 walls per axis: lo + extent * (i / n), exact
  double scale_[3] = {0, 0, 0};    // cells per unit length, to locate a point
  std::vector<uint32_t> offsets_;  // cell c holds tris_[offsets_[c] .. offsets_[c + 1])
  std::vector<uint32_t> tris_;
  size_t degenerate_ = 0;
  uint64_t cells_over_budget_ = 0;
  double build_seconds_ = 0.0;
};

}  // namespace gs
