// The bottom panel's states tab: the traversal states the 1D grid made (one per axis and
// absolute granularity G, shared between voxels: paper §5.2), as a table sortable by any
// column.
#pragma once
#include <vector>

#include "core/render/overlay.h"

namespace gs::app {

enum class StateColumn { state, axis, granularity, voxels, rays };

// Sorts by the column, ties by state number, so that equal keys keep a stable order.
void sort_state_rows(std::vector<StateRow>& rows, StateColumn column, bool descending);

class StatesTable {
 public:
  // The overlay cache's rows, sorted as the header was last clicked.
  void draw(const std::vector<StateRow>& rows);

 private:
  void sort_if_needed(const std::vector<StateRow>& rows);

  std::vector<StateRow> shown_;     // sorted
  std::vector<StateRow> unsorted_;  // the rows shown_ was sorted from
};

}  // namespace gs::app
