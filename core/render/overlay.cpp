// Overlays computed from the grid's published voxels and from recorded walks.
//
// Threads: the grid functions read voxels that tracing threads may still be cutting, so they
// must be called while no thread traces (the viewer pauses its workers first). Even so they
// read a voxel's fields only after an acquire load of its status shows kSplit, and reach
// voxels only by walking down from the root through published cuts, so a voxel appended by
// a cut that was never published (one over the memory budget) is never read.
#include "core/render/overlay.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <map>

#include "core/base/error.h"
#include "core/base/hash.h"

namespace gs {

namespace {

const glm::vec4 kSceneBoxColor{0.6f, 0.6f, 0.6f, 1.0f};
// Eight colours that stay apart on a dark image, cycled by depth.
const glm::vec4 kDepthPalette[] = {{1.00f, 0.35f, 0.35f, 1.0f}, {1.00f, 0.65f, 0.20f, 1.0f},
                                   {0.95f, 0.95f, 0.30f, 1.0f}, {0.40f, 0.90f, 0.40f, 1.0f},
                                   {0.30f, 0.85f, 0.95f, 1.0f}, {0.40f, 0.55f, 1.00f, 1.0f},
                                   {0.80f, 0.45f, 1.00f, 1.0f}, {1.00f, 0.50f, 0.80f, 1.0f}};
const glm::vec4 kAxisColors[3] = {
    {0.95f, 0.25f, 0.25f, 1.0f}, {0.30f, 0.90f, 0.30f, 1.0f}, {0.30f, 0.50f, 1.00f, 1.0f}};
const char* const kAxisNames[3] = {"x", "y", "z"};
const glm::vec4 kRayColor{1.0f, 1.0f, 1.0f, 1.0f};
const glm::vec4 kVisitedColor{0.50f, 0.58f, 0.70f, 1.0f};
const glm::vec4 kCurrentColor{1.0f, 0.92f, 0.10f, 1.0f};

struct DBox {
  double lo[3], hi[3];
};

DBox box_of(const Grid1D& grid, uint32_t id) {
  DBox box;
  grid.voxel_box(id, box.lo, box.hi);
  return box;
}

glm::vec3 point(double x, double y, double z) { return {float(x), float(y), float(z)}; }

void add_segment(LineSet& lines, glm::vec3 a, glm::vec3 b, glm::vec4 color) {
  lines.vertices.push_back({a, color});
  lines.vertices.push_back({b, color});
}

// The 12 edges: for each axis, the four edges parallel to it.
void add_box(LineSet& lines, const double lo[3], const double hi[3], glm::vec4 color) {
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    for (int corner = 0; corner < 4; ++corner) {
      double p[3], q[3];
      p[a] = lo[a], q[a] = hi[a];
      p[b] = q[b] = (corner & 1) ? hi[b] : lo[b];
      p[c] = q[c] = (corner & 2) ? hi[c] : lo[c];
      add_segment(lines, point(p[0], p[1], p[2]), point(q[0], q[1], q[2]), color);
    }
  }
}

// The rectangle where the plane `axis` = `wall` meets the box: four edges.
void add_wall(LineSet& lines, int axis, double wall, const DBox& box, glm::vec4 color) {
  const int b = (axis + 1) % 3, c = (axis + 2) % 3;
  double corners[4][3];
  for (int k = 0; k < 4; ++k) {
    corners[k][axis] = wall;
    corners[k][b] = (k == 1 || k == 2) ? box.hi[b] : box.lo[b];  // lo,hi,hi,lo around
    corners[k][c] = k >= 2 ? box.hi[c] : box.lo[c];
  }
  for (int k = 0; k < 4; ++k) {
    const double* p = corners[k];
    const double* q = corners[(k + 1) % 4];
    add_segment(lines, point(p[0], p[1], p[2]), point(q[0], q[1], q[2]), color);
  }
}

// Calls visit(id, voxel, depth) for every subdivided voxel, breadth first from the root.
// Depth is not public on Grid1D; counting levels on the way down gives it.
template <class Visit>
void for_each_split(const Grid1D& grid, Visit&& visit) {
  if (grid.voxel_count() == 0) return;  // not built
  std::vector<std::pair<uint32_t, uint32_t>> queue{{0, 0}};
  for (size_t i = 0; i < queue.size(); ++i) {
    const auto [id, depth] = queue[i];
    const Grid1D::Voxel& voxel = grid.voxel(id);
    if (voxel.status.load(std::memory_order_acquire) != Grid1D::kSplit) continue;
    visit(id, voxel, depth);
    for (uint32_t k = 0; k < voxel.granularity; ++k)
      queue.emplace_back(voxel.first_child + k, depth + 1);
  }
}

// Fully saturated-ish, full-value colour of a hue in 0..1: bright on a dark image.
glm::vec4 bright_hue(float hue) {
  const float s = 0.75f, h6 = hue * 6.0f;
  const int sector = int(h6) % 6;
  const float f = h6 - std::floor(h6);
  const float p = 1.0f - s, q = 1.0f - s * f, t = 1.0f - s * (1.0f - f);
  const glm::vec3 rgb[6] = {{1, t, p}, {q, 1, p}, {p, 1, t}, {p, q, 1}, {t, p, 1}, {1, p, q}};
  return glm::vec4(rgb[sector], 1.0f);
}

glm::vec4 state_color(uint32_t state) {
  return bright_hue(float(mix_bits(state) >> 8) * (1.0f / 16777216.0f));
}

std::string state_label(const StateRow& row) {
  return std::string(kAxisNames[row.axis]) + " G=" + std::to_string(row.absolute_granularity);
}

// How far the drawn ray goes: to its hit, or for a miss to where it leaves the scene box
// (no further than tmax); +inf when it never enters the box.
double ray_end(const Walk& walk) { return walk.hit.found() ? walk.hit.t : walk.t_leave; }

uint8_t to_byte(double c) { return uint8_t(std::clamp(c, 0.0, 1.0) * 255.0 + 0.5); }

}  // namespace

LineSet cell_lines(const Grid1D& grid, CellColoring coloring) {
  LineSet lines;
  if (grid.voxel_count() == 0) return lines;
  const DBox root = box_of(grid, 0);
  add_box(lines, root.lo, root.hi, kSceneBoxColor);
  uint32_t max_depth = 0;
  bool any_split = false;
  for_each_split(grid, [&](uint32_t id, const Grid1D::Voxel& voxel, uint32_t depth) {
    const int axis = voxel.axis;
    const glm::vec4 color = coloring == CellColoring::axis
                                ? kAxisColors[axis]
                                : kDepthPalette[depth % std::size(kDepthPalette)];
    const DBox box = box_of(grid, id);
    // Each wall is the next cell's low bound, computed as the traversal computes it.
    for (uint32_t k = 1; k < voxel.granularity; ++k)
      add_wall(lines, axis, box_of(grid, voxel.first_child + k).lo[axis], box, color);
    max_depth = std::max(max_depth, depth);
    any_split = true;
  });
  lines.legend.push_back({"scene box", kSceneBoxColor});
  if (coloring == CellColoring::axis) {
    for (int a = 0; a < 3; ++a) lines.legend.push_back({kAxisNames[a], kAxisColors[a]});
  } else if (any_split) {
    for (uint32_t d = 0; d <= max_depth; ++d)
      lines.legend.push_back(
          {"depth " + std::to_string(d), kDepthPalette[d % std::size(kDepthPalette)]});
  }
  return lines;
}

std::vector<StateRow> state_table(const Grid1D& grid) {
  std::map<uint32_t, uint64_t> counts;  // state -> subdivided voxels
  for_each_split(grid,
                 [&](uint32_t, const Grid1D::Voxel& voxel, uint32_t) { ++counts[voxel.state]; });
  std::vector<StateRow> rows;
  for (const auto& [state, voxels] : counts) {
    const Grid1D::StateInfo& info = grid.state_info(state);
    rows.push_back({state, int(info.axis), info.granularity, voxels, grid.state_rays(state)});
  }
  std::sort(rows.begin(), rows.end(), [](const StateRow& a, const StateRow& b) {
    return a.axis != b.axis ? a.axis < b.axis : a.absolute_granularity < b.absolute_granularity;
  });
  return rows;
}

LineSet state_lines(const Grid1D& grid) {
  LineSet lines;
  for_each_split(grid, [&](uint32_t id, const Grid1D::Voxel& voxel, uint32_t) {
    const DBox box = box_of(grid, id);
    add_box(lines, box.lo, box.hi, state_color(voxel.state));
  });
  for (const StateRow& row : state_table(grid))
    lines.legend.push_back({state_label(row), state_color(row.state)});
  return lines;
}

LineSet walk_lines(const Walk& walk, int highlight) {
  LineSet lines;
  const double end = ray_end(walk);
  if (std::isfinite(end)) {
    // In double, then rounded once: the end lands where the hit's t puts it.
    glm::dvec3 origin(walk.ray.origin), dir(walk.ray.dir);
    add_segment(lines, glm::vec3(origin), glm::vec3(origin + end * dir), kRayColor);
  }
  const int cells = int(walk.cells.size());
  for (int i = 0; i < cells; ++i)
    if (i != highlight) add_box(lines, walk.cells[i].lo, walk.cells[i].hi, kVisitedColor);
  // Last, so that where its edges coincide with a neighbour's it is drawn on top.
  if (highlight >= 0 && highlight < cells)
    add_box(lines, walk.cells[highlight].lo, walk.cells[highlight].hi, kCurrentColor);
  lines.legend = {
      {"ray", kRayColor}, {"visited cell", kVisitedColor}, {"current cell", kCurrentColor}};
  return lines;
}

// Ruofei Du's degree-5 polynomial fit to Mikhailov's turbo table (Google, 2019), as
// published with the colour map; coefficients of 1, x, ..., x^5 per channel. It is within
// about 1/8 of full scale of the table near the ends (turbo(0) is (35, 23, 27) here, (48,
// 18, 59) in the table) and much closer in between.
std::array<uint8_t, 3> turbo(float x) {
  static constexpr double kCoefficients[3][6] = {
      {0.13572138, 4.61539260, -42.66032258, 132.13108234, -152.94239396, 59.28637943},
      {0.09140261, 2.19418839, 4.84296658, -14.18503333, 4.27729857, 2.82956604},
      {0.10667330, 12.64194608, -60.58204836, 110.36276771, -89.90310912, 27.34824973}};
  const double t = std::isnan(x) ? 0.0 : std::clamp(double(x), 0.0, 1.0);
  std::array<uint8_t, 3> rgb;
  for (int c = 0; c < 3; ++c) {
    double value = 0.0;
    for (int k = 5; k >= 0; --k) value = value * t + kCoefficients[c][k];  // Horner
    rgb[c] = to_byte(value);
  }
  return rgb;
}

std::vector<uint8_t> heat_image(const std::vector<float>& values, float lo, float hi) {
  std::vector<uint8_t> rgba(values.size() * 4, 255);
  // In double: hi - lo cannot overflow. An empty or reversed range (or NaN bounds) maps
  // everything to the low end rather than dividing by zero.
  const double range = double(hi) - double(lo);
  const bool usable = range > 0.0;
  for (size_t i = 0; i < values.size(); ++i) {
    uint8_t* pixel = &rgba[4 * i];
    if (std::isnan(values[i])) {
      pixel[0] = pixel[1] = pixel[2] = 0;
      continue;
    }
    const double x = usable ? (double(values[i]) - double(lo)) / range : 0.0;
    const std::array<uint8_t, 3> rgb = turbo(float(x));
    std::copy(rgb.begin(), rgb.end(), pixel);
  }
  return rgba;
}

const char* heat_name(HeatKind kind) {
  switch (kind) {
    case HeatKind::steps:
      return "steps";
    case HeatKind::tests:
      return "tests";
    case HeatKind::built:
      return "built";
    case HeatKind::none:
      break;
  }
  return "none";
}

std::vector<float> heat_values(const std::vector<PixelRecord>& pixels, HeatKind kind, int samples) {
  std::vector<float> values(pixels.size(), 0.0f);
  const float per = 1.0f / float(std::max(samples, 1));
  for (size_t i = 0; i < pixels.size(); ++i) {
    const PixelRecord& p = pixels[i];
    const uint32_t figure = kind == HeatKind::steps   ? p.steps
                            : kind == HeatKind::tests ? p.tests
                            : kind == HeatKind::built ? p.built
                                                      : 0;
    values[i] = float(figure) * per;
  }
  return values;
}

OverlaySelection parse_overlays(const std::string& list) {
  OverlaySelection selection;
  size_t begin = 0;
  while (begin <= list.size()) {
    const size_t end = std::min(list.find(',', begin), list.size());
    const std::string name = list.substr(begin, end - begin);
    const HeatKind heat = name == "heat:steps"   ? HeatKind::steps
                          : name == "heat:tests" ? HeatKind::tests
                          : name == "heat:built" ? HeatKind::built
                                                 : HeatKind::none;
    if (name == "cells") {
      selection.cells = true;
    } else if (name == "states") {
      selection.states = true;
    } else if (name == "walk") {
      selection.walk = true;
    } else if (heat != HeatKind::none) {
      if (selection.heat != HeatKind::none && selection.heat != heat)
        throw UsageError("--overlay '" + list + "': only one heat:KIND at a time");
      selection.heat = heat;
    } else {
      throw UsageError("--overlay '" + list + "': unknown overlay '" + name +
                       "' (expected cells, states, walk, heat:steps, heat:tests, heat:built)");
    }
    begin = end + 1;
  }
  return selection;
}

}  // namespace gs
