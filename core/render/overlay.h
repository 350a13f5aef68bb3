// What the viewer and `gridscope shot` draw over the rendered image, computed here (no
// OpenGL): line sets in world space with colours and a legend, and false-colour images of
// per-pixel statistics. The app only uploads and draws them.
#pragma once
#include <array>
#include <cstdint>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <string>
#include <vector>

#include "core/accel/grid1d/grid1d.h"
#include "core/accel/params.h"
#include "core/accel/walk.h"
#include "core/render/render.h"

namespace gs {

struct LineVertex {
  glm::vec3 position;
  glm::vec4 color;  // RGBA in 0..1
};

struct LegendEntry {
  std::string label;
  glm::vec4 color;
};

// How much of a structure overlay the line cap let through, per depth level: items are
// walls (cells) or voxels (states). Levels are filled shallow first, so the items left out
// are always the deepest ones.
struct Coverage {
  std::string overlay;  // "cells" or "states"
  std::string item;     // "walls" or "voxels"
  std::vector<uint64_t> shown_by_depth, total_by_depth;
  uint64_t shown() const;
  uint64_t total() const;
  // One line: "cells: 1,204 walls, levels 0-3", or when the cap left some out "cells: showing
  // 5,000 of 45,853 walls: levels 0-3 complete, level 4 partly, levels 5-9 left out; narrow
  // the depth range or use near-walk".
  std::string describe() const;
};

// Line segments: vertices[2k], vertices[2k + 1] form segment k.
struct LineSet {
  std::vector<LineVertex> vertices;
  std::vector<LineVertex> fill;  // triangles drawn translucent beneath the lines
  std::vector<LegendEntry> legend;
  // Drawn last, thick and at full strength wherever it is: the walk, which must stand out
  // from the structure around it. Other sets are thin and fade with distance.
  bool emphasised = false;
  Coverage coverage;  // cells and states only
};

enum class CellColoring { depth, axis };

// Levels first..last of the tree (the root is level 0), both included.
struct DepthRange {
  uint32_t first = 0;
  uint32_t last = kMaxDepth;
  bool contains(uint32_t depth) const { return depth >= first && depth <= last; }
  bool everything() const { return first == 0 && last == kMaxDepth; }
};

// Lines drawn at once at most by one structure overlay. On lumpy's close-up at 1280x800
// this keeps levels 0-7 whole and the image and the walk still readable behind them.
constexpr size_t kMaxOverlaySegments = 6000;

// Which subdivided voxels the cells and states overlays draw.
struct VoxelFilter {
  DepthRange depths{};
  // Only the voxels the walk went through: those holding one of its cells (its cells'
  // ancestors). With no walk, none, and cells draw no scene box either.
  bool near_walk = false;
  const Walk* walk = nullptr;
  size_t max_segments = kMaxOverlaySegments;  // for cells, the scene box's 12 included
};

// The walls of the 1D subdivisions built so far that `filter` lets through: for each
// subdivided voxel, the g - 1 inner walls between its cells, each drawn as the rectangle
// where the wall meets the voxel; and the scene box. Shallow levels first up to the cap;
// deeper levels fade (alpha_for_depth).
LineSet cell_lines(const Grid1D& grid, CellColoring coloring, const VoxelFilter& filter = {});

// The voxels that share each traversal state (axis, absolute granularity), each state in its
// own colour (the 12 box edges of every subdivided voxel `filter` lets through); legend: one
// entry per state drawn.
LineSet state_lines(const Grid1D& grid, const VoxelFilter& filter = {});

// The opacity of a structure line at `depth` when the shown range starts at `first`: falls
// level by level, so that deep walls recede behind the shallow ones that frame them.
float alpha_for_depth(uint32_t depth, uint32_t first);

// One row of the states table: a state, how many subdivided voxels share it, and how many
// rays used it (Grid1D::state_rays: counted when tracing threads finish).
struct StateRow {
  uint32_t state;
  int axis;
  uint64_t absolute_granularity;
  uint64_t voxels;
  uint64_t rays;
};
std::vector<StateRow> state_table(const Grid1D& grid);

// A recorded walk, emphasised and in kWalkColor's family (no structure palette uses it): the
// ray from its origin to its hit (or to where it leaves the last cell), and the 12 edges of
// every cell it visited; the cell `highlight` (an index into walk.cells, or -1 for none) in
// a lighter shade and filled translucently.
LineSet walk_lines(const Walk& walk, int highlight = -1);
// The walk's magenta: no depth, axis or state colour comes near it.
extern const glm::vec4 kWalkColor;

// The per-pixel figures a heatmap can show (PixelRecord).
enum class HeatKind { none, steps, tests, built };
const char* heat_name(HeatKind kind);
// Each pixel's figure per sample (records are sums over `samples` samples).
std::vector<float> heat_values(const std::vector<PixelRecord>& pixels, HeatKind kind, int samples);

// Which overlays to draw; `shot --overlay` and `view --overlay` take the same list.
struct OverlaySelection {
  bool cells = false;
  bool states = false;
  bool walk = false;
  HeatKind heat = HeatKind::none;
  DepthRange depths{};     // of cells and states
  bool near_walk = false;  // cells and states only around the walk
  bool needs_grid() const { return cells || states || walk; }
};
// "cells,states,walk,heat:KIND,depth:A-B,near-walk" in any order, any subset: KIND steps,
// tests or built (one at most); depth:A-B (or depth:A) keeps levels A..B of cells and
// states, 0 <= A <= B <= kMaxDepth; near-walk keeps only the voxels the walk went through.
// Throws UsageError "SOURCE 'LIST': problem": an unknown word, two heat kinds or depth
// ranges, a malformed range, or depth: or near-walk with neither cells nor states to apply to.
OverlaySelection parse_overlays(const std::string& list, const std::string& source = "--overlay");
// The list parse_overlays reads back as `selection` (the panel's "as --overlay" line); the
// depth range and near-walk only with cells or states.
std::string format_overlays(const OverlaySelection& selection);

// The turbo colour map (Mikhail, Google 2019), x in 0..1 (clamped), as 8-bit RGB.
std::array<uint8_t, 3> turbo(float x);

// values (width * height, row-major from the top-left) mapped through turbo over [lo, hi]
// into RGBA8 with alpha 255.
std::vector<uint8_t> heat_image(const std::vector<float>& values, float lo, float hi);

}  // namespace gs
