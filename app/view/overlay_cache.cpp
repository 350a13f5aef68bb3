#include "app/view/overlay_cache.h"

#include <algorithm>

#include "app/view/state.h"
#include "core/accel/grid1d/grid1d.h"

namespace gs::app {

const std::vector<uint8_t>& HeatMap::rgba(const ProgressiveFrame& frame, HeatKind kind) {
  if (!stale_ && frame.generation == generation_ && frame.pass == pass_) return rgba_;
  stale_ = false;
  generation_ = frame.generation, pass_ = frame.pass;
  values_ = heat_values(frame.pixels, kind, frame.spp);
  max_ = values_.empty() ? 0.0f : *std::max_element(values_.begin(), values_.end());
  if (auto_range) lo = 0.0f, hi = std::max(max_, 1.0f);
  rgba_ = heat_image(values_, lo, std::max(hi, lo + 1e-6f));
  return rgba_;
}

void OverlayCache::refresh(ViewState& state) {
  const uint64_t nodes = state.session.frame().structure.nodes.value_or(0);
  const bool grown = nodes != read_nodes_;
  if (!state.overlays_stale && !(grown && seconds_since(read_time_) >= kOverlayInterval)) return;
  read_time_ = Clock::now();
  read_nodes_ = nodes;
  state.session.with_structure_paused(
      [&](const Accelerator& accel) { read_structure(state, accel); });
  state.overlays_stale = false;
}

void OverlayCache::read_structure(ViewState& state, const Accelerator& accel) {
  structure_lines_.clear();
  states_.clear();
  state.picked.cost.reset();
  const Grid1D* grid = accel.grid1d();
  nodes_built_ = grid ? grid->voxel_count() : 0;
  if (!grid) return;
  if (state.overlays.cells)
    structure_lines_.push_back(
        cell_lines(*grid, state.colour_by_axis ? CellColoring::axis : CellColoring::depth));
  if (state.overlays.states) structure_lines_.push_back(state_lines(*grid));
  states_ = state_table(*grid);
  if (state.picked.walk)
    state.picked.cost = parent_voxel_cost(*grid, *state.picked.walk, state.picked.cell);
}

}  // namespace gs::app
