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
#include <charconv>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <set>

#include "core/base/error.h"
#include "core/base/hash.h"
#include "core/base/text.h"

namespace gs {

namespace {

const glm::vec4 kSceneBoxColor{0.6f, 0.6f, 0.6f, 1.0f};
// Six colours that stay apart on a dark image, cycled by depth. No magenta, pink or violet:
// those belong to the walk (kWalkColor).
const glm::vec4 kDepthPalette[] = {{1.00f, 0.35f, 0.35f, 1.0f}, {1.00f, 0.65f, 0.20f, 1.0f},
                                   {0.95f, 0.95f, 0.30f, 1.0f}, {0.40f, 0.90f, 0.40f, 1.0f},
                                   {0.30f, 0.85f, 0.95f, 1.0f}, {0.40f, 0.55f, 1.00f, 1.0f}};
const glm::vec4 kAxisColors[3] = {
    {0.95f, 0.25f, 0.25f, 1.0f}, {0.30f, 0.90f, 0.30f, 1.0f}, {0.30f, 0.50f, 1.00f, 1.0f}};
const char* const kAxisNames[3] = {"x", "y", "z"};
// State colours take hues from red through blue-violet only, short of the walk's magenta.
constexpr float kStateHueSpan = 0.72f;
const glm::vec4 kCurrentColor{1.0f, 0.72f, 1.0f, 1.0f};  // the walk's, lighter
constexpr float kCurrentFillAlpha = 0.3f;
// Depth fading: each level below the first shown loses this much opacity, down to a floor
// at which the deepest walls still show.
constexpr float kDepthFadeStep = 0.2f, kMinDepthAlpha = 0.3f;
constexpr size_t kBoxSegments = 12, kWallSegments = 4;

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

// The box's six faces as two triangles each, into lines.fill.
void add_filled_box(LineSet& lines, const double lo[3], const double hi[3], glm::vec4 color) {
  for (int axis = 0; axis < 3; ++axis) {
    const int b = (axis + 1) % 3, c = (axis + 2) % 3;
    for (const double* side : {lo, hi}) {
      glm::vec3 quad[4];
      for (int k = 0; k < 4; ++k) {
        double p[3];
        p[axis] = side[axis];
        p[b] = (k == 1 || k == 2) ? hi[b] : lo[b];  // lo,hi,hi,lo around
        p[c] = k >= 2 ? hi[c] : lo[c];
        quad[k] = point(p[0], p[1], p[2]);
      }
      for (const int k : {0, 1, 2, 0, 2, 3}) lines.fill.push_back({quad[k], color});
    }
  }
}

// The centres of the walk's cells: a voxel holds one of the cells exactly when it holds
// its centre, since cells nest inside their ancestors' boxes.
std::vector<glm::dvec3> cell_centres(const Walk& walk) {
  std::vector<glm::dvec3> centres;
  for (const WalkCell& cell : walk.cells)
    centres.push_back(0.5 * (glm::dvec3(cell.lo[0], cell.lo[1], cell.lo[2]) +
                             glm::dvec3(cell.hi[0], cell.hi[1], cell.hi[2])));
  return centres;
}

bool holds_any(const DBox& box, const std::vector<glm::dvec3>& points) {
  return std::any_of(points.begin(), points.end(), [&](const glm::dvec3& p) {
    for (int a = 0; a < 3; ++a)
      if (p[a] < box.lo[a] || p[a] > box.hi[a]) return false;
    return true;
  });
}

// Calls visit(id, voxel, depth) for every subdivided voxel `filter` lets through, breadth
// first from the root: level by level, so that a cap keeps the shallow levels whole. Depth
// is not public on Grid1D; counting levels on the way down gives it. The walk down stops
// below the range's last level and, near the walk, at voxels holding none of its cells
// (their children cannot hold one either).
template <class Visit>
void for_each_split(const Grid1D& grid, const VoxelFilter& filter, Visit&& visit) {
  if (grid.voxel_count() == 0) return;  // not built
  if (filter.near_walk && !filter.walk) return;
  const std::vector<glm::dvec3> centres =
      filter.near_walk ? cell_centres(*filter.walk) : std::vector<glm::dvec3>{};
  std::vector<std::pair<uint32_t, uint32_t>> queue{{0, 0}};
  for (size_t i = 0; i < queue.size(); ++i) {
    const auto [id, depth] = queue[i];
    const Grid1D::Voxel& voxel = grid.voxel(id);
    if (voxel.status.load(std::memory_order_acquire) != Grid1D::kSplit) continue;
    if (filter.near_walk && !holds_any(box_of(grid, id), centres)) continue;
    if (filter.depths.contains(depth)) visit(id, voxel, depth);
    if (depth >= filter.depths.last) continue;
    for (uint32_t k = 0; k < voxel.granularity; ++k)
      queue.emplace_back(voxel.first_child + k, depth + 1);
  }
}

// Admits items of `segments` lines each into `lines` while the cap allows, and counts per
// depth what was admitted and what there was (lines.coverage).
class Budget {
 public:
  Budget(LineSet& lines, size_t max_segments) : lines_(lines), max_segments_(max_segments) {}
  bool admit(uint32_t depth, size_t segments) {
    Coverage& c = lines_.coverage;
    if (c.total_by_depth.size() <= depth) {
      c.total_by_depth.resize(depth + 1, 0);
      c.shown_by_depth.resize(depth + 1, 0);
    }
    ++c.total_by_depth[depth];
    if (lines_.vertices.size() / 2 + segments > max_segments_) return false;
    ++c.shown_by_depth[depth];
    return true;
  }

 private:
  LineSet& lines_;
  size_t max_segments_;
};

glm::vec4 faded(glm::vec4 color, uint32_t depth, const DepthRange& range) {
  color.a *= alpha_for_depth(depth, range.first);
  return color;
}

// "level 3" or "levels 3-5".
std::string levels(uint32_t first, uint32_t last) {
  return first == last ? "level " + std::to_string(first)
                       : "levels " + std::to_string(first) + "-" + std::to_string(last);
}

// The levels of `depths` (ascending) as "levels 0-3", or empty for none.
std::string level_span(const std::vector<uint32_t>& depths) {
  return depths.empty() ? "" : levels(depths.front(), depths.back());
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
  return bright_hue(float(mix_bits(state) >> 8) * (kStateHueSpan / 16777216.0f));
}

std::string state_label(const StateRow& row) {
  return std::string(kAxisNames[row.axis]) + " G=" + std::to_string(row.absolute_granularity);
}

// How far the drawn ray goes: to its hit, or for a miss to where it leaves the scene box
// (no further than tmax); +inf when it never enters the box.
double ray_end(const Walk& walk) { return walk.hit.found() ? walk.hit.t : walk.t_leave; }

// A depth level: digits only, no more than kMaxDepth.
std::optional<uint32_t> parse_level(const std::string& text) {
  uint32_t value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || error != std::errc() || end != text.data() + text.size() ||
      value > uint32_t(kMaxDepth))
    return std::nullopt;
  return value;
}

// "A-B" or "A" (A..A); none when malformed or B < A.
std::optional<DepthRange> parse_depth_range(const std::string& text) {
  const size_t dash = text.find('-');
  const std::optional<uint32_t> first = parse_level(text.substr(0, dash));
  const std::optional<uint32_t> last =
      dash == std::string::npos ? first : parse_level(text.substr(dash + 1));
  if (!first || !last || *last < *first) return std::nullopt;
  return DepthRange{*first, *last};
}

uint8_t to_byte(double c) { return uint8_t(std::clamp(c, 0.0, 1.0) * 255.0 + 0.5); }

}  // namespace

const glm::vec4 kWalkColor{1.0f, 0.15f, 0.85f, 1.0f};

uint64_t Coverage::shown() const {
  return std::accumulate(shown_by_depth.begin(), shown_by_depth.end(), uint64_t(0));
}

uint64_t Coverage::total() const {
  return std::accumulate(total_by_depth.begin(), total_by_depth.end(), uint64_t(0));
}

std::string Coverage::describe() const {
  std::vector<uint32_t> present, complete, partly, left_out;
  for (uint32_t d = 0; d < total_by_depth.size(); ++d) {
    if (total_by_depth[d] == 0) continue;
    present.push_back(d);
    const uint64_t shown_here = shown_by_depth[d];
    (shown_here == total_by_depth[d] ? complete : shown_here > 0 ? partly : left_out).push_back(d);
  }
  if (present.empty()) return overlay + ": no " + item;
  if (shown() == total())
    return overlay + ": " + count_text(double(total())) + " " + item + ", " + level_span(present);
  std::vector<std::string> parts;
  if (!complete.empty()) parts.push_back(level_span(complete) + " complete");
  if (!partly.empty()) parts.push_back(level_span(partly) + " partly");
  if (!left_out.empty()) parts.push_back(level_span(left_out) + " left out");
  std::string text = overlay + ": showing " + count_text(double(shown())) + " of " +
                     count_text(double(total())) + " " + item + ":";
  for (size_t i = 0; i < parts.size(); ++i) text += (i ? ", " : " ") + parts[i];
  return text + "; narrow the depth range or use near-walk";
}

float alpha_for_depth(uint32_t depth, uint32_t first) {
  const float below = depth > first ? float(depth - first) : 0.0f;
  return std::max(kMinDepthAlpha, 1.0f - kDepthFadeStep * below);
}

LineSet cell_lines(const Grid1D& grid, CellColoring coloring, const VoxelFilter& filter) {
  LineSet lines;
  lines.coverage.overlay = "cells", lines.coverage.item = "walls";
  // Near no walk, not even the scene box: the image stays clear until a click.
  if (grid.voxel_count() == 0 || (filter.near_walk && !filter.walk)) return lines;
  const DBox root = box_of(grid, 0);
  add_box(lines, root.lo, root.hi, kSceneBoxColor);
  Budget budget(lines, filter.max_segments);
  for_each_split(grid, filter, [&](uint32_t id, const Grid1D::Voxel& voxel, uint32_t depth) {
    const int axis = voxel.axis;
    const glm::vec4 color =
        faded(coloring == CellColoring::axis ? kAxisColors[axis]
                                             : kDepthPalette[depth % std::size(kDepthPalette)],
              depth, filter.depths);
    const DBox box = box_of(grid, id);
    // Each wall is the next cell's low bound, computed as the traversal computes it.
    for (uint32_t k = 1; k < voxel.granularity; ++k)
      if (budget.admit(depth, kWallSegments))
        add_wall(lines, axis, box_of(grid, voxel.first_child + k).lo[axis], box, color);
  });
  lines.legend.push_back({"scene box", kSceneBoxColor});
  if (coloring == CellColoring::axis) {
    for (int a = 0; a < 3; ++a) lines.legend.push_back({kAxisNames[a], kAxisColors[a]});
  } else {
    const std::vector<uint64_t>& shown = lines.coverage.shown_by_depth;
    for (uint32_t d = 0; d < shown.size(); ++d)
      if (shown[d] > 0)
        lines.legend.push_back(
            {"depth " + std::to_string(d), kDepthPalette[d % std::size(kDepthPalette)]});
  }
  return lines;
}

std::vector<StateRow> state_table(const Grid1D& grid) {
  std::map<uint32_t, uint64_t> counts;  // state -> subdivided voxels
  for_each_split(grid, VoxelFilter{},
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

LineSet state_lines(const Grid1D& grid, const VoxelFilter& filter) {
  LineSet lines;
  lines.coverage.overlay = "states", lines.coverage.item = "voxels";
  Budget budget(lines, filter.max_segments);
  std::set<uint32_t> drawn;  // states with a box drawn: the legend lists only those
  for_each_split(grid, filter, [&](uint32_t id, const Grid1D::Voxel& voxel, uint32_t depth) {
    if (!budget.admit(depth, kBoxSegments)) return;
    const DBox box = box_of(grid, id);
    add_box(lines, box.lo, box.hi, faded(state_color(voxel.state), depth, filter.depths));
    drawn.insert(voxel.state);
  });
  for (const StateRow& row : state_table(grid))
    if (drawn.count(row.state)) lines.legend.push_back({state_label(row), state_color(row.state)});
  return lines;
}

LineSet walk_lines(const Walk& walk, int highlight) {
  LineSet lines;
  lines.emphasised = true;
  const double end = ray_end(walk);
  if (std::isfinite(end)) {
    // In double, then rounded once: the end lands where the hit's t puts it.
    glm::dvec3 origin(walk.ray.origin), dir(walk.ray.dir);
    add_segment(lines, glm::vec3(origin), glm::vec3(origin + end * dir), kWalkColor);
  }
  const int cells = int(walk.cells.size());
  for (int i = 0; i < cells; ++i)
    if (i != highlight) add_box(lines, walk.cells[i].lo, walk.cells[i].hi, kWalkColor);
  // Last, so that where its edges coincide with a neighbour's it is drawn on top.
  if (highlight >= 0 && highlight < cells) {
    const WalkCell& current = walk.cells[highlight];
    add_box(lines, current.lo, current.hi, kCurrentColor);
    add_filled_box(lines, current.lo, current.hi,
                   glm::vec4(glm::vec3(kWalkColor), kCurrentFillAlpha));
  }
  lines.legend = {
      {"ray", kWalkColor}, {"visited cell", kWalkColor}, {"current cell", kCurrentColor}};
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

OverlaySelection parse_overlays(const std::string& list, const std::string& source) {
  OverlaySelection selection;
  bool depth_given = false;
  const auto fail = [&](const std::string& problem) {
    throw UsageError(source + " '" + list + "': " + problem);
  };
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
    } else if (name == "near-walk") {
      selection.near_walk = true;
    } else if (name.starts_with("depth:")) {
      if (depth_given) fail("only one depth:A-B at a time");
      const std::optional<DepthRange> range = parse_depth_range(name.substr(6));
      if (!range)
        fail("'" + name +
             "': expected depth:A-B or depth:A with 0 <= A <= B <= " + std::to_string(kMaxDepth));
      selection.depths = *range;
      depth_given = true;
    } else if (heat != HeatKind::none) {
      if (selection.heat != HeatKind::none && selection.heat != heat)
        fail("only one heat:KIND at a time");
      selection.heat = heat;
    } else {
      fail("unknown overlay '" + name +
           "' (expected cells, states, walk, near-walk, depth:A-B, heat:steps, heat:tests, "
           "heat:built)");
    }
    begin = end + 1;
  }
  if ((depth_given || selection.near_walk) && !selection.cells && !selection.states)
    fail("depth:A-B and near-walk choose what cells and states draw: add cells or states");
  return selection;
}

std::string format_overlays(const OverlaySelection& selection) {
  std::vector<std::string> words;
  if (selection.cells) words.push_back("cells");
  if (selection.states) words.push_back("states");
  if (selection.walk) words.push_back("walk");
  // The filter words only with something to filter, as parse_overlays requires.
  const bool filtered = selection.cells || selection.states;
  if (filtered && selection.near_walk) words.push_back("near-walk");
  if (filtered && !selection.depths.everything())
    words.push_back("depth:" + std::to_string(selection.depths.first) + "-" +
                    std::to_string(selection.depths.last));
  if (selection.heat != HeatKind::none)
    words.push_back(std::string("heat:") + heat_name(selection.heat));
  std::string list;
  for (const std::string& word : words) list += (list.empty() ? "" : ",") + word;
  return list;
}

}  // namespace gs
