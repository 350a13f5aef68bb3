// A/B comparison of two runs over the same camera (`shot --compare`, the viewer's A/B): the totals
// side by side, and per-pixel figures (a heatmap's steps or tests) of both runs on one scale with
// the difference B - A beside them. No OpenGL: the app draws the images.
#pragma once
#include <array>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/render/progressive.h"

namespace gs {

// One run's totals as the table shows them; a figure the structure cannot measure (Embree's
// tests and steps) is absent, never a made-up 0.
struct CompareTotals {
  std::string label;  // "A: grid1d"
  double rays_per_second = 0.0;
  std::optional<double> tests_per_ray, steps_per_ray;
  std::optional<uint64_t> nodes;
  uint64_t memory_bytes = 0;
  double build_seconds = 0.0;  // up-front and lazy
};

// From a viewer frame: its last finished pass's rate and counters, its structure's figures.
CompareTotals compare_totals(const std::string& label, const ProgressiveFrame& frame);

// From a run's statistics (run_stats: rays, intersection_tests, traversal_steps, nodes,
// memory_bytes, build_seconds, rays_per_second).
CompareTotals compare_totals(const std::string& label, const nlohmann::json& stats);

// One figure of the two runs as text, and B / A ("" when either is missing or A's is 0).
struct TotalsRow {
  std::string figure, a, b, ratio;
};
// rays/s, tests per ray, steps per ray, nodes, memory MB, build s.
std::vector<TotalsRow> totals_rows(const CompareTotals& a, const CompareTotals& b);

// The two runs' labels, a line each, then their totals as a table, one figure a row, with
// B's ratio to A where both exist:
//   A: grid1d
//   B: bvh
//   figure                        A              B    B / A
//   rays/s                 1.23e+06       2.46e+06     2.00
std::string totals_table(const CompareTotals& a, const CompareTotals& b);

// The scale both heatmaps share: 0 to the larger of the two maxima (at least 1, so that two
// all-zero maps still have a range).
float shared_heat_max(const std::vector<float>& a, const std::vector<float>& b);

// A diverging colour map for x in -1..1 (clamped; NaN as 0): blue where B has less, white
// where A and B are equal, red where B has more. Symmetric, so that equal magnitudes of
// either sign read as equally strong.
std::array<uint8_t, 3> diverging(float x);

// The difference b - a per pixel through `diverging` over [-range, range] as RGBA8 (alpha
// 255), range = difference_range(a, b). Throws std::invalid_argument when the sizes differ.
std::vector<uint8_t> difference_image(const std::vector<float>& a, const std::vector<float>& b);
// The 99th percentile of the nonzero |b - a| (at least 1): a few outliers (one pixel's ray
// grazing a dense leaf) saturate instead of washing every other difference out to white.
float difference_range(const std::vector<float>& a, const std::vector<float>& b);

}  // namespace gs
