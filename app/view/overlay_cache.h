// What the overlays draw, rebuilt only when it would change: the structure's line sets
// (cells, states), its states table and the inspected cell's cost, all read from the 1D grid
// while the workers are paused; and the heatmap image of the shown frame.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "core/base/timing.h"
#include "core/render/overlay.h"
#include "core/render/progressive.h"

namespace gs::app {

struct ViewState;

constexpr double kOverlayInterval = 1.0;  // seconds between refreshes while the structure grows

// The heatmap shown in place of the render: one figure per pixel of the shown frame, through
// turbo over a range that is 0..max (automatic) or set by hand.
class HeatMap {
 public:
  bool auto_range = true;
  float lo = 0.0f, hi = 1.0f;

  // The kind or the range changed: the next image is computed anew.
  void invalidate() { stale_ = true; }
  // The image of `frame`'s figures of this kind: computed again for a new frame or after
  // invalidate(), when an automatic range is also set again.
  const std::vector<uint8_t>& rgba(const ProgressiveFrame& frame, HeatKind kind);
  // The last image's figures per pixel and per sample, and their maximum.
  const std::vector<float>& values() const { return values_; }
  float max() const { return max_; }
  // How many images rgba has computed: a new count is a new image.
  uint64_t images_made() const { return images_made_; }

 private:
  bool stale_ = true;
  uint64_t images_made_ = 0;
  uint64_t generation_ = 0;  // the frame the image is of
  int pass_ = 0;
  std::vector<float> values_;
  float max_ = 0.0f;
  std::vector<uint8_t> rgba_;
};

class OverlayCache {
 public:
  // Reading the structure pauses the workers, so it is read again only when the overlays are
  // stale (a toggle, a pick, a new structure) or once a second while it grows. Also
  // sets the picked walk's cost. Cells and states are filtered as state.overlays says (depth
  // range, near the picked walk) and capped at kMaxOverlaySegments each.
  void refresh(ViewState& state);

  const std::vector<LineSet>& structure_lines() const { return structure_lines_; }
  const std::vector<StateRow>& states() const { return states_; }
  size_t nodes_built() const { return nodes_built_; }
  HeatMap& heat() { return heat_; }

 private:
  void read_structure(ViewState& state, const Accelerator& accel);
  void log_coverage();

  std::vector<LineSet> structure_lines_;
  std::vector<StateRow> states_;
  size_t nodes_built_ = 0;
  Clock::time_point read_time_{};
  uint64_t read_nodes_ = 0;  // the nodes the frame reported at that time
  std::string logged_coverage_;
  HeatMap heat_;
};

}  // namespace gs::app
