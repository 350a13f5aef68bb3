#include "app/view/overlay_cache.h"

#include <algorithm>
#include <cstdio>
#include <string>

#include "app/view/state.h"
#include "core/accel/grid1d/grid1d.h"

namespace gs::app {

const std::vector<uint8_t>& HeatMap::rgba(const ProgressiveFrame& frame, HeatKind kind) {
  if (!stale_ && frame.generation == generation_ && frame.pass == pass_) return rgba_;
  stale_ = false;
  ++images_made_;
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
  const bool chosen = state.overlays_stale;
  if (!chosen && !(grown && seconds_since(read_time_) >= kOverlayInterval)) return;
  read_time_ = Clock::now();
  read_nodes_ = nodes;
  state.session.with_structure_paused(
      [&](const Accelerator& accel) { read_structure(state, accel); });
  state.overlays_stale = false;
  if (chosen) log_coverage();
}

// What a choice of overlays shows (and what the cap left out), on stderr for logs and
// scripts, once per change: not as the structure grows, which would repeat it every refresh.
void OverlayCache::log_coverage() {
  std::string text;
  for (const LineSet& set : structure_lines_)
    text += (text.empty() ? "" : "; ") + set.coverage.describe();
  if (!text.empty() && text != logged_coverage_)
    std::fprintf(stderr, "gridscope view: overlays: %s\n", text.c_str());
  logged_coverage_ = text;
}

void OverlayCache::read_structure(ViewState& state, const Accelerator& accel) {
  structure_lines_.clear();
  states_.clear();
  state.picked.cost.reset();
  const Grid1D* grid = accel.grid1d();
  nodes_built_ = grid ? grid->voxel_count() : 0;
  if (!grid) return;
  const OverlaySelection& shown = state.overlays;
  const VoxelFilter filter{.depths = shown.depths,
                           .near_walk = shown.near_walk,
                           .walk = state.picked.walk ? &*state.picked.walk : nullptr};
  if (shown.cells)
    structure_lines_.push_back(
        cell_lines(*grid, state.colour_by_axis ? CellColoring::axis : CellColoring::depth, filter));
  if (shown.states) structure_lines_.push_back(state_lines(*grid, filter));
  states_ = state_table(*grid);
  if (state.picked.walk)
    state.picked.cost = parent_voxel_cost(*grid, *state.picked.walk, state.picked.cell);
}

}  // namespace gs::app
