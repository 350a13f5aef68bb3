// The uniform grid the paper compares with (Jevans 1990 §7; Fujimoto et al. 1986): the
// scene box cut into equal cells, about cbrt(N) per side for N triangles (the paper's
// setting), or density * N cells in all with --density. Cells are as cubic as the box's
// aspect allows. Traversal is the 3D DDA of Cleary & Wyvill (1988) / Amanatides & Woo
// (1987) with ray-id mailboxing. Flat storage: per cell the handle of its leaf (its
// triangles in the kernel's form, core/geometry/leaf.h), or none for an empty cell.
#pragma once
#include <array>
#include <vector>

#include "core/accel/accelerator.h"
#include "core/geometry/leaf.h"
#include "core/geometry/triangles.h"

namespace gs {

class UniformGrid final : public Accelerator {
 public:
  explicit UniformGrid(const AccelParams& params);

  std::string name() const override { return "uniform"; }
  void build(const Scene& scene) override;
  Box bounds() const override { return input_.bounds; }
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
  uint64_t references() const { return references_; }

 private:
  template <bool AnyHit>
  Hit trace(const Ray& ray, MailboxContext& context) const;
  void choose_resolution(size_t triangles);
  void shrink_to(double cells);
  uint64_t grid_bytes(const std::vector<uint32_t>& counts) const;
  void fit_budget();
  void set_walls();
  uint32_t locate(int axis, double p) const;
  void cell_range(int axis, double lo, double hi, uint32_t& first, uint32_t& last) const;
  template <class Visit>
  void each_cell(uint32_t id, Visit&& visit) const;
  std::vector<uint32_t> count_references() const;
  void fill_cells();

  AccelParams params_;
  Kernel kernel_;
  BuildInput input_;  // its clip box is the grid's box
  uint32_t n_[3] = {1, 1, 1};
  std::vector<double> walls_[3];     // n + 1 walls per axis: lo + extent * (i / n), exact
  double scale_[3] = {0, 0, 0};      // cells per unit length, to locate a point
  std::vector<uint32_t> cell_leaf_;  // per cell its leaf's handle, kEmptyCell for none
  static constexpr uint32_t kEmptyCell = LeafStore::kFull;
  LeafStore leaves_;
  uint64_t references_ = 0;
  uint64_t cells_over_budget_ = 0;
  double build_seconds_ = 0.0;
};

}  // namespace gs
