#include "core/render/compare.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace gs {

namespace {

std::optional<double> per_ray(const nlohmann::json& stats, const char* key) {
  const nlohmann::json& value = stats.at(key);
  const double rays = stats.at("rays").get<double>();
  if (value.is_null() || rays <= 0.0) return std::nullopt;
  return value.get<double>() / rays;
}

// One row: A's and B's figures in `format`, and B / A when both exist and A's is not 0.
TotalsRow row(const char* name, const std::optional<double>& a, const std::optional<double>& b,
              const char* format) {
  const auto text = [format](const std::optional<double>& value) {
    char cell[32] = "n/a";
    if (value) std::snprintf(cell, sizeof cell, format, *value);
    return std::string(cell);
  };
  char ratio[32] = "";
  if (a && b && *a != 0.0) std::snprintf(ratio, sizeof ratio, "%.2f", *b / *a);
  return {name, text(a), text(b), ratio};
}

std::optional<double> as_double(const std::optional<uint64_t>& value) {
  return value ? std::optional<double>(double(*value)) : std::nullopt;
}

}  // namespace

CompareTotals compare_totals(const std::string& label, const ProgressiveFrame& frame) {
  const StructureStats& s = frame.structure;
  const double rays = double(frame.pass_rays);
  CompareTotals totals;
  totals.label = label;
  totals.rays_per_second = frame.rays_per_second;
  if (s.counts_tests && rays > 0.0)
    totals.tests_per_ray = double(frame.counters.intersection_tests) / rays;
  if (s.counts_steps && rays > 0.0)
    totals.steps_per_ray = double(frame.counters.traversal_steps) / rays;
  totals.nodes = s.nodes;
  totals.memory_bytes = s.memory_bytes;
  totals.build_seconds = s.build_seconds;
  return totals;
}

CompareTotals compare_totals(const std::string& label, const nlohmann::json& stats) {
  CompareTotals totals;
  totals.label = label;
  totals.rays_per_second = stats.at("rays_per_second").get<double>();
  totals.tests_per_ray = per_ray(stats, "intersection_tests");
  totals.steps_per_ray = per_ray(stats, "traversal_steps");
  if (!stats.at("nodes").is_null()) totals.nodes = stats.at("nodes").get<uint64_t>();
  totals.memory_bytes = stats.at("memory_bytes").get<uint64_t>();
  totals.build_seconds = stats.at("build_seconds").get<double>();
  return totals;
}

std::vector<TotalsRow> totals_rows(const CompareTotals& a, const CompareTotals& b) {
  return {row("rays/s", a.rays_per_second, b.rays_per_second, "%.4g"),
          row("tests per ray", a.tests_per_ray, b.tests_per_ray, "%.3f"),
          row("steps per ray", a.steps_per_ray, b.steps_per_ray, "%.3f"),
          row("nodes", as_double(a.nodes), as_double(b.nodes), "%.0f"),
          row("memory MB", a.memory_bytes / 1e6, b.memory_bytes / 1e6, "%.3f"),
          row("build s", a.build_seconds, b.build_seconds, "%.4f")};
}

std::string totals_table(const CompareTotals& a, const CompareTotals& b) {
  std::string table = a.label + "\n" + b.label + "\n";
  char line[160];
  std::snprintf(line, sizeof line, "%-16s %14s %14s %8s\n", "figure", "A", "B", "B / A");
  table += line;
  for (const TotalsRow& r : totals_rows(a, b)) {
    std::snprintf(line, sizeof line, "%-16s %14s %14s %8s\n", r.figure.c_str(), r.a.c_str(),
                  r.b.c_str(), r.ratio.c_str());
    table += line;
  }
  return table;
}

float shared_heat_max(const std::vector<float>& a, const std::vector<float>& b) {
  float most = 1.0f;
  for (const std::vector<float>* values : {&a, &b})
    for (const float v : *values)
      if (v > most) most = v;  // NaN compares false: skipped
  return most;
}

std::array<uint8_t, 3> diverging(float x) {
  const float t = std::isnan(x) ? 0.0f : std::clamp(x, -1.0f, 1.0f);
  // From white toward a saturated blue (t < 0) or red (t > 0): the other channels fall.
  const auto fall = [](float s) { return uint8_t(std::lround(255.0f * (1.0f - s))); };
  const float s = std::fabs(t);
  if (t < 0.0f) return {fall(0.85f * s), fall(0.55f * s), 255};
  return {255, fall(0.55f * s), fall(0.85f * s)};
}

float difference_range(const std::vector<float>& a, const std::vector<float>& b) {
  if (a.size() != b.size()) throw std::invalid_argument("difference of maps of different sizes");
  std::vector<float> magnitudes;
  for (size_t i = 0; i < a.size(); ++i)
    if (const float d = std::fabs(b[i] - a[i]); d > 0.0f) magnitudes.push_back(d);  // NaN: out
  if (magnitudes.empty()) return 1.0f;
  const auto at = magnitudes.begin() + ptrdiff_t((magnitudes.size() - 1) * 99 / 100);
  std::nth_element(magnitudes.begin(), at, magnitudes.end());
  return std::max(*at, 1.0f);
}

std::vector<uint8_t> difference_image(const std::vector<float>& a, const std::vector<float>& b) {
  const float range = difference_range(a, b);
  std::vector<uint8_t> rgba(a.size() * 4, 255);
  for (size_t i = 0; i < a.size(); ++i) {
    const std::array<uint8_t, 3> c = diverging((b[i] - a[i]) / range);
    std::copy(c.begin(), c.end(), rgba.begin() + ptrdiff_t(4 * i));
  }
  return rgba;
}

}  // namespace gs
