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
#include "core/render/render.h"
#include "core/accel/walk.h"

namespace gs {

struct LineVertex {
  glm::vec3 position;
  glm::vec4 color;  // RGBA in 0..1
};

struct LegendEntry {
  std::string label;
  glm::vec4 color;
};

// Line segments: vertices[2k], vertices[2k + 1] form segment k.
struct LineSet {
  std::vector<LineVertex> vertices;
  std::vector<LegendEntry> legend;
};

enum class CellColoring { depth, axis };

// The walls of every 1D subdivision built so far: for each subdivided voxel, the g - 1
// inner walls between its cells, each drawn as the rectangle where the wall meets the voxel.
LineSet cell_lines(const Grid1D& grid, CellColoring coloring);

// The voxels that share each traversal state (axis, absolute granularity), each state in its
// own colour (the 12 box edges of every subdivided voxel); legend: one entry per state.
LineSet state_lines(const Grid1D& grid);

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

// A recorded walk: the ray from its origin to its hit (or to where it leaves the last cell),
// and the 12 edges of every cell it visited; the cell `highlight` (an index into walk.cells,
// or -1 for none) in a highlight colour.
LineSet walk_lines(const Walk& walk, int highlight = -1);

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
  bool needs_grid() const { return cells || states || walk; }
};
// "cells,states,walk,heat:steps|tests|built" (any subset, one heat at most). Throws
// UsageError for an unknown name or two heat kinds.
OverlaySelection parse_overlays(const std::string& list);

// The turbo colour map (Mikhail, Google 2019), x in 0..1 (clamped), as 8-bit RGB.
std::array<uint8_t, 3> turbo(float x);

// values (width * height, row-major from the top-left) mapped through turbo over [lo, hi]
// into RGBA8 with alpha 255.
std::vector<uint8_t> heat_image(const std::vector<float>& values, float lo, float hi);

}  // namespace gs
