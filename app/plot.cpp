#include "app/plot.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>

#include "app/gl/frame.h"
#include "app/gl/headless.h"
#include "app/gl/imgui_renderer.h"
#include "bench/report.h"
#include "core/accel/registry.h"
#include "core/render/render.h"

namespace gs::app {

using json = nlohmann::json;

namespace {

constexpr ImU32 kPaper = IM_COL32(255, 255, 255, 255);
constexpr ImU32 kInk = IM_COL32(25, 25, 25, 255);
constexpr ImU32 kMuted = IM_COL32(110, 110, 110, 255);
constexpr ImU32 kGridLine = IM_COL32(228, 228, 228, 255);
constexpr ImU32 kAlarm = IM_COL32(200, 0, 0, 255);

ImU32 colour_of(std::string_view accel) {
  const auto [r, g, b] = structure_colour(accel);
  return IM_COL32(r, g, b, 255);
}

std::string format(const char* spec, double value) {
  char text[64];
  std::snprintf(text, sizeof text, spec, value);
  return text;
}

// ---- Canvas ------------------------------------------------------------------------------

// An ImGui context of its own for one image; never writes imgui.ini.
struct ImGuiScope {
  explicit ImGuiScope(ImVec2 size) {
    ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;
    io.LogFilename = nullptr;
    io.DisplaySize = size;
    io.DeltaTime = 1.0f / 60.0f;
  }
  ~ImGuiScope() { ImGui::DestroyContext(); }
  ImGuiScope(const ImGuiScope&) = delete;
  ImGuiScope& operator=(const ImGuiScope&) = delete;
};

// An image drawn through ImGui: a headless GL context of the image's size and an ImGui frame
// whose background draw list is the canvas, white to start with. Members are destroyed in
// reverse order: the renderer while its ImGui and GL contexts still exist.
class Canvas {
 public:
  Canvas(int width, int height)
      : context_(width, height), imgui_(ImVec2(float(width), float(height))) {
    ImGui::NewFrame();
    list().AddRectFilled(ImVec2(0, 0), ImGui::GetIO().DisplaySize, kPaper);
  }

  ImDrawList& list() { return *ImGui::GetBackgroundDrawList(); }

  void write(const std::string& path) {
    ImGui::Render();
    renderer_.draw(ImGui::GetDrawData());
    write_png(path, context_.width(), context_.height(),
              gl::read_pixels(context_.width(), context_.height()));
  }

 private:
  gl::HeadlessContext context_;
  ImGuiScope imgui_;
  gl::ImGuiRenderer renderer_;
};

float text_width(const std::string& text) { return ImGui::CalcTextSize(text.c_str()).x; }

// `text` cut to `width` pixels, keeping its end (scene paths differ at the end).
std::string fit(const std::string& text, float width) {
  if (text_width(text) <= width) return text;
  for (size_t cut = 1; cut < text.size(); ++cut) {
    const std::string shorter = ".." + text.substr(cut);
    if (text_width(shorter) <= width) return shorter;
  }
  return "";
}

enum class Align { left, centre, right };

void draw_text(ImDrawList& list, ImVec2 at, ImU32 colour, const std::string& text,
               Align align = Align::left) {
  const float width = text_width(text);
  if (align == Align::centre) at.x -= width / 2;
  if (align == Align::right) at.x -= width;
  list.AddText(ImVec2(std::round(at.x), std::round(at.y)), colour, text.c_str());
}

void dashed_line(ImDrawList& list, ImVec2 from, ImVec2 to, ImU32 colour) {
  constexpr float kDash = 6;
  const float length = std::hypot(to.x - from.x, to.y - from.y);
  for (float s = 0; s < length; s += 2 * kDash) {
    const float e = std::min(s + kDash, length);
    list.AddLine(
        ImVec2(from.x + (to.x - from.x) * s / length, from.y + (to.y - from.y) * s / length),
        ImVec2(from.x + (to.x - from.x) * e / length, from.y + (to.y - from.y) * e / length),
        colour, 1.5f);
  }
}

// One row of colour swatches and names from `at`; returns where the row ends.
float draw_legend(ImDrawList& list, ImVec2 at, const std::vector<std::string_view>& structures) {
  for (std::string_view accel : structures) {
    list.AddRectFilled(at, ImVec2(at.x + 12, at.y + 12), colour_of(accel));
    const std::string name(accel);
    draw_text(list, ImVec2(at.x + 17, at.y), kInk, name);
    at.x += 17 + text_width(name) + 18;
  }
  return at.x;
}

// ---- Axes --------------------------------------------------------------------------------

// 1-2-5 steps: the largest of 1, 2, 5 x 10^k not above v, the smallest not below v.
double nice_below(double v) {
  const double decade = std::pow(10.0, std::floor(std::log10(v)));
  for (double m : {5.0, 2.0, 1.0})
    if (m * decade <= v) return m * decade;
  return decade;
}
double nice_above(double v) {
  const double decade = std::pow(10.0, std::floor(std::log10(v)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * decade >= v * (1 - 1e-12)) return m * decade;
  return 10 * decade;
}

struct Axis {
  double lo = 0, hi = 1;
  bool log = false;
  double step = 0;  // linear axes: the distance between ticks

  // 0 at lo, 1 at hi; values beyond the axis (or not positive on a log axis) are clamped.
  double fraction(double v) const {
    if (log) v = std::max(v, lo);
    const double f = log ? std::log(v / lo) / std::log(hi / lo) : (v - lo) / (hi - lo);
    return std::clamp(f, 0.0, 1.0);
  }

  // Log axes: 1, 2, 5 per decade, or only the 1s when that would be more than `most`
  // ticks; linear: every step.
  std::vector<double> ticks(size_t most) const {
    std::vector<double> out;
    if (!log) {
      if (step <= 0) return out;
      for (int i = int(std::ceil(lo / step - 1e-9)); i * step <= hi + step * 1e-9; ++i)
        out.push_back(i * step);
      return out;
    }
    for (bool decades_only : {false, true}) {
      out.clear();
      for (int k = int(std::floor(std::log10(lo))); k <= int(std::ceil(std::log10(hi))); ++k)
        for (double m : {1.0, 2.0, 5.0}) {
          const double tick = m * std::pow(10.0, k);
          if ((m == 1.0 || !decades_only) && tick >= lo * 0.9999 && tick <= hi * 1.0001)
            out.push_back(tick);
        }
      if (out.size() <= most) break;
    }
    return out;
  }
};

// A log axis with room around [min, max] (both positive).
Axis log_axis(double min, double max) {
  return {nice_below(min * 0.9), nice_above(max * 1.1), true};
}
// A linear axis from min (or 0) to a whole number of 1-2-5 steps past max.
Axis linear_axis(double min, double max) {
  const double lo = std::min(min, 0.0);
  if (max <= lo) max = lo + 1;
  const double step = nice_above((max - lo) / 5);
  return {lo, std::ceil(max * 1.02 / step) * step, false, step};
}

// A value axis fitted to positive data: log when it spans a decade or more.
Axis fitted_axis(double min, double max) {
  return min > 0 && max / min >= 10 ? log_axis(min, max) : linear_axis(min, max);
}

// The inner rectangle of a chart and its two axes.
struct Panel {
  ImVec2 min, max;
  Axis x, y;

  float x_at(double v) const { return min.x + float(x.fraction(v)) * (max.x - min.x); }
  float y_at(double v) const { return max.y - float(y.fraction(v)) * (max.y - min.y); }
  ImVec2 at(double vx, double vy) const { return ImVec2(x_at(vx), y_at(vy)); }
};

std::string tick_text(double v) { return format("%g", v); }

constexpr float kTickSpacing = 22;

// Grid lines, tick labels on the left and the axis name above the axis.
void draw_y_axis(ImDrawList& list, const Panel& panel, const std::string& name) {
  // Tick labels at least kTickSpacing pixels apart.
  for (double tick : panel.y.ticks(size_t((panel.max.y - panel.min.y) / kTickSpacing))) {
    const float y = panel.y_at(tick);
    list.AddLine(ImVec2(panel.min.x, y), ImVec2(panel.max.x, y), kGridLine);
    draw_text(list, ImVec2(panel.min.x - 6, y - 7), kMuted, tick_text(tick), Align::right);
  }
  draw_text(list, ImVec2(panel.min.x - 40, panel.min.y - 20), kInk, name);
}

void draw_x_axis(ImDrawList& list, const Panel& panel, const std::string& name) {
  for (double tick : panel.x.ticks(size_t((panel.max.x - panel.min.x) / (2 * kTickSpacing)))) {
    const float x = panel.x_at(tick);
    list.AddLine(ImVec2(x, panel.min.y), ImVec2(x, panel.max.y), kGridLine);
    draw_text(list, ImVec2(x, panel.max.y + 4), kMuted, tick_text(tick), Align::centre);
  }
  draw_text(list, ImVec2((panel.min.x + panel.max.x) / 2, panel.max.y + 20), kInk, name,
            Align::centre);
}

void draw_box(ImDrawList& list, const Panel& panel) { list.AddRect(panel.min, panel.max, kInk); }

// Cell `index` of a grid of `columns` cells of `size`, the first row starting at `top`.
ImVec2 cell_origin(size_t index, size_t columns, ImVec2 size, float top) {
  return ImVec2(float(index % columns) * size.x, top + float(index / columns) * size.y);
}

// ---- Bars --------------------------------------------------------------------------------

struct Bar {
  std::optional<double> value;  // nullopt: the record holds null ("n/a")
  bool capped = false;          // over the time cap: an estimate from part of one pass
};
struct BarGroup {
  std::string label;
  std::vector<std::optional<Bar>> bars;  // one per structure of the chart; nullopt: not run
};
// A labelled dashed horizontal line across a bar chart.
struct Reference {
  double value;
  ImU32 colour;
  std::string label;
};
struct BarChart {
  std::string title, y_name;
  double base = 0;  // bars grow from here (1 = the zero-overhead floor)
  std::vector<Reference> references;
  std::vector<std::string_view> structures = {};  // filled from the records
  std::vector<BarGroup> groups = {};
  Axis y = {};
};

std::string bar_label(const Bar& bar) {
  const double value = bar.value.value_or(0);
  return format(std::fabs(value) >= 100 ? "%.0f" : "%.3g", value) + (bar.capped ? "*" : "");
}

// Values go above the bars only when every one fits its bar (the report has the numbers).
bool labels_fit(const BarChart& chart, float bar_width) {
  for (const BarGroup& group : chart.groups)
    for (const auto& bar : group.bars)
      if (bar && bar->value && text_width(bar_label(*bar)) > bar_width + 4) return false;
  return true;
}

constexpr float kMinBarHeight = 3.0f;  // pixels

void draw_bar(ImDrawList& list, const Panel& panel, float left, float width, const Bar& bar,
              double base, ImU32 colour, bool label) {
  const float centre = left + width / 2;
  if (!bar.value) {
    draw_text(list, ImVec2(centre, panel.y_at(base) - 16), kMuted, "n/a", Align::centre);
    return;
  }
  const float y0 = panel.y_at(base);
  // A bar at its base (a structure as fast as zero-overhead) would have no height: it keeps
  // a sliver on its side of the base, so that it reads as measured, not as missing.
  const float sliver = *bar.value < base ? kMinBarHeight : -kMinBarHeight;
  const float y_value = panel.y_at(*bar.value);
  const float y1 = std::fabs(y_value - y0) < kMinBarHeight ? y0 + sliver : y_value;
  list.AddRectFilled(ImVec2(std::round(left), std::round(std::min(y0, y1))),
                     ImVec2(std::round(left + width), std::round(std::max(y0, y1))), colour);
  if (label || bar.capped)
    draw_text(list, ImVec2(centre, std::min(y0, y1) - 15), kInk, label ? bar_label(bar) : "*",
              Align::centre);
}

void draw_references(ImDrawList& list, const Panel& panel, ImVec2 legend_at,
                     const std::vector<Reference>& references) {
  for (const Reference& line : references) {
    const float y = panel.y_at(line.value);
    dashed_line(list, ImVec2(panel.min.x, y), ImVec2(panel.max.x, y), line.colour);
    dashed_line(list, ImVec2(legend_at.x, legend_at.y + 6),
                ImVec2(legend_at.x + 24, legend_at.y + 6), line.colour);
    draw_text(list, ImVec2(legend_at.x + 30, legend_at.y), line.colour, line.label);
    legend_at.x += 30 + text_width(line.label) + 18;
  }
}

void draw_bar_chart(const BarChart& chart, const std::string& path) {
  Canvas canvas(kPlotWidth, kBarPlotHeight);
  ImDrawList& list = canvas.list();
  const Panel panel{ImVec2(80, 70), ImVec2(kPlotWidth - 20, kBarPlotHeight - 50), {}, chart.y};
  draw_text(list, ImVec2(20, 10), kInk, chart.title);
  const float legend_end = draw_legend(list, ImVec2(20, 28), chart.structures);
  draw_y_axis(list, panel, chart.y_name);
  const float group_width = (panel.max.x - panel.min.x) / float(chart.groups.size());
  // Bars side by side, centred in their scene's group, no wider than kMaxSlot.
  constexpr float kMaxSlot = 70;
  const float slot = std::min(group_width * 0.85f / float(chart.structures.size()), kMaxSlot);
  const bool labels = labels_fit(chart, slot * 0.8f);
  for (size_t g = 0; g < chart.groups.size(); ++g) {
    const float centre = panel.min.x + (float(g) + 0.5f) * group_width;
    const float left = centre - slot * float(chart.structures.size()) / 2;
    for (size_t s = 0; s < chart.structures.size(); ++s)
      if (const auto& bar = chart.groups[g].bars[s])
        draw_bar(list, panel, left + float(s) * slot + slot * 0.1f, slot * 0.8f, *bar, chart.base,
                 colour_of(chart.structures[s]), labels);
    draw_text(list, ImVec2(centre, panel.max.y + 8), kInk,
              fit(chart.groups[g].label, group_width - 8), Align::centre);
  }
  draw_references(list, panel, ImVec2(legend_end + 12, 28), chart.references);
  draw_box(list, panel);
  canvas.write(path);
}

using BarValue = std::function<std::optional<Bar>(const std::string&, std::string_view)>;

// The smallest and largest bar values; min > max when there are none.
std::pair<double, double> value_range(const BarChart& chart) {
  double min = INFINITY, max = -INFINITY;
  for (const BarGroup& group : chart.groups)
    for (const auto& bar : group.bars)
      if (bar && bar->value) min = std::min(min, *bar->value), max = std::max(max, *bar->value);
  return {min, max};
}

// Groups per scene, a bar per structure that ran on some scene (n/a where its figure is
// null); false when no bar has a value.
bool fill_bars(const json& records, const BarValue& bar_of, BarChart& chart) {
  const std::vector<std::string> scenes = record_scenes(records);
  std::vector<std::string_view> series = report_structures();
  series.insert(series.end(), packet_columns().begin(), packet_columns().end());
  for (std::string_view accel : series)
    if (std::ranges::any_of(scenes,
                            [&](const std::string& s) { return bar_of(s, accel).has_value(); }))
      chart.structures.push_back(accel);
  for (const std::string& scene : scenes) {
    BarGroup group{scene, {}};
    for (std::string_view accel : chart.structures) group.bars.push_back(bar_of(scene, accel));
    chart.groups.push_back(group);
  }
  const auto [min, max] = value_range(chart);
  return min <= max;
}

bool relative_plot(const json& records, const std::string& path) {
  BarChart chart{.title =
                     "Time relative to the zero-overhead method: primary + shadow rays, "
                     "1 thread, default settings (log scale; * over the time cap: an estimate)",
                 .y_name = "time / zero-overhead time",
                 .base = 1.0,
                 .references = {{1.0, kInk, "zero-overhead = 1"}}};
  const BarValue bar_of = [&](const std::string& scene, std::string_view column) {
    const auto packets = packet_column_structure(column);
    const json* record = packets
                             ? find_record(records, {scene, *packets, "primary_shadow", "packets"})
                             : find_record(records, {scene, column});
    if (!record) return std::optional<Bar>();
    const auto value = record_number(*record, "relative_to_zero");
    return std::optional(
        Bar{value && *value > 0 ? value : std::nullopt, record_flag(*record, "over_time_cap")});
  };
  if (!fill_bars(records, bar_of, chart)) return false;
  const auto [min, max] = value_range(chart);
  chart.y = log_axis(std::min(min, 1.0), std::max(max, 1.0));
  draw_bar_chart(chart, path);
  return true;
}

bool speedup_plot(const json& records, const std::string& path) {
  BarChart chart{.title =
                     "Speed-up with 2 threads over 1 thread: warm runs, primary + shadow "
                     "rays, default settings",
                 .y_name = "1-thread time / 2-thread time",
                 .base = 0.0,
                 .references = {{2.0, kInk, "ideal 2x"},
                                {kSpeedupTarget, kAlarm, format("target %.2fx", kSpeedupTarget)}}};
  const BarValue bar_of = [&](const std::string& scene, std::string_view column) {
    const auto packets = packet_column_structure(column);
    const std::string_view accel = packets.value_or(column);
    const std::string_view setting = packets ? "packets" : "default";
    const json* one = find_record(records, {scene, accel, "primary_shadow", setting});
    const json* two = find_record(records, {scene, accel, "primary_shadow", setting, 2});
    if (!one || !two) return std::optional<Bar>();
    return std::optional(Bar{record_speedup(one, *two), record_flag(*one, "over_time_cap") ||
                                                            record_flag(*two, "over_time_cap")});
  };
  if (!fill_bars(records, bar_of, chart)) return false;
  chart.y = linear_axis(0, std::max(value_range(chart).second, 2.2));
  draw_bar_chart(chart, path);
  return true;
}

// ---- Line panels -------------------------------------------------------------------------

struct Series {
  std::string_view accel;
  int marker = -1;  // -1: a line only; else a marker shape per point
  std::vector<std::pair<double, double>> points;
};

void draw_marker(ImDrawList& list, ImVec2 c, int shape, ImU32 colour) {
  constexpr float r = 4.5f;
  switch (shape % 6) {
    case 0:
      list.AddCircleFilled(c, r, colour);
      break;
    case 1:
      list.AddRectFilled(ImVec2(c.x - r, c.y - r), ImVec2(c.x + r, c.y + r), colour);
      break;
    case 2:
      list.AddTriangleFilled(ImVec2(c.x, c.y - r - 1), ImVec2(c.x - r - 1, c.y + r),
                             ImVec2(c.x + r + 1, c.y + r), colour);
      break;
    case 3:
      list.AddQuadFilled(ImVec2(c.x, c.y - r - 1), ImVec2(c.x + r + 1, c.y),
                         ImVec2(c.x, c.y + r + 1), ImVec2(c.x - r - 1, c.y), colour);
      break;
    case 4:
      list.AddLine(ImVec2(c.x - r, c.y - r), ImVec2(c.x + r, c.y + r), colour, 2.5f);
      list.AddLine(ImVec2(c.x - r, c.y + r), ImVec2(c.x + r, c.y - r), colour, 2.5f);
      break;
    default:
      list.AddCircle(c, r, colour, 0, 2.0f);
      break;
  }
}

// Axes fitted to every point of every series: x linear from 0 or log, y as `log_y` says.
Panel fitted_panel(ImVec2 min, ImVec2 max, const std::vector<Series>& series, bool log_y,
                   bool x_from_zero) {
  double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
  for (const Series& s : series)
    for (const auto& [x, y] : s.points) {
      x0 = std::min(x0, x), x1 = std::max(x1, x);
      if (!log_y || y > 0) y0 = std::min(y0, y), y1 = std::max(y1, y);
    }
  if (!(y0 <= y1)) y0 = 1, y1 = 1;  // no drawable y at all
  const Axis x = x_from_zero ? linear_axis(0, x1) : fitted_axis(x0, x1);
  const Axis y = log_y ? log_axis(y0, y1) : linear_axis(0, y1);
  return {min, max, x, y};
}

void draw_series(ImDrawList& list, const Panel& panel, const Series& series) {
  std::vector<ImVec2> points;
  for (const auto& [x, y] : series.points) points.push_back(panel.at(x, y));
  const ImU32 colour = colour_of(series.accel);
  if (points.size() > 1) list.AddPolyline(points.data(), int(points.size()), colour, 0, 2.0f);
  if (series.marker >= 0)
    for (const ImVec2& p : points) draw_marker(list, p, series.marker, colour);
}

// A scene's convergence record for one structure, whatever its thread count (the
// progressive renderer runs on every core).
const json* convergence_record(const json& records, const std::string& scene,
                               std::string_view accel) {
  for (const json& r : records)
    if (record_text(r, "workload") == "convergence" && record_text(r, "scene") == scene &&
        record_text(r, "accel") == accel)
      return &r;
  return nullptr;
}

// Points [[seconds, rmse], ...] of a convergence record, skipping malformed pairs.
std::vector<std::pair<double, double>> convergence_points(const json& record) {
  std::vector<std::pair<double, double>> out;
  const auto it = record.find("points");
  if (it == record.end() || !it->is_array()) return out;
  for (const json& p : *it)
    if (p.is_array() && p.size() == 2 && p[0].is_number() && p[1].is_number() &&
        std::isfinite(p[0].get<double>()) && std::isfinite(p[1].get<double>()))
      out.emplace_back(p[0].get<double>(), p[1].get<double>());
  return out;
}

constexpr size_t kColumns = 3;
constexpr float kTop = 50;  // title and legend above the panels

bool rmse_plot(const json& records, const std::string& path) {
  std::vector<std::pair<std::string, std::vector<Series>>> scenes;
  std::vector<std::string_view> structures;
  for (const std::string& scene : record_scenes(records)) {
    std::vector<Series> lines;
    for (std::string_view accel : report_structures())
      if (const json* r = convergence_record(records, scene, accel))
        if (auto points = convergence_points(*r); !points.empty())
          lines.push_back({accel, -1, std::move(points)});
    for (const Series& s : lines)
      if (std::ranges::count(structures, s.accel) == 0) structures.push_back(s.accel);
    if (!lines.empty()) scenes.emplace_back(scene, std::move(lines));
  }
  if (scenes.empty()) return false;
  std::ranges::sort(structures, {}, [](std::string_view a) {
    return std::ranges::find(report_structures(), a) - report_structures().begin();
  });
  const ImVec2 cell(float(kPlotWidth) / kColumns, 330);
  const int rows = int((scenes.size() + kColumns - 1) / kColumns);
  Canvas canvas(kPlotWidth, int(kTop + float(rows) * cell.y));
  ImDrawList& list = canvas.list();
  draw_text(list, ImVec2(20, 8), kInk,
            "Image RMSE against a converged reference over wall time (from the start of the "
            "build), progressive renderer; log RMSE");
  draw_legend(list, ImVec2(20, 26), structures);
  for (size_t i = 0; i < scenes.size(); ++i) {
    const ImVec2 o = cell_origin(i, kColumns, cell, kTop);
    const Panel panel =
        fitted_panel(ImVec2(o.x + 70, o.y + 45), ImVec2(o.x + cell.x - 15, o.y + cell.y - 45),
                     scenes[i].second, true, true);
    draw_text(list, ImVec2((panel.min.x + panel.max.x) / 2, o.y + 6), kInk,
              fit(scenes[i].first, cell.x - 20), Align::centre);
    draw_y_axis(list, panel, "RMSE (0..255)");
    draw_x_axis(list, panel, "wall time (s)");
    for (const Series& s : scenes[i].second) draw_series(list, panel, s);
    draw_box(list, panel);
  }
  canvas.write(path);
  return true;
}

// One sweep: a structure and the parameter it varied, one series per scene.
struct Sweep {
  std::string_view accel;
  std::string parameter;
  std::vector<Series> time, memory;
  std::vector<std::string> scenes;  // the scene of each series, for the legend
};

std::vector<Sweep> collect_sweeps(const json& records) {
  std::vector<Sweep> sweeps;
  std::map<std::pair<std::string, std::string>, size_t> index;  // (accel, parameter) -> sweep
  const std::vector<std::string> all_scenes = record_scenes(records);
  for (const json& r : records) {
    const auto value = record_number(r, "sweep_value");
    const std::string accel = record_text(r, "accel"), parameter = record_text(r, "sweep_param");
    const auto known = std::ranges::find(report_structures(), accel);
    if (record_text(r, "workload") != "sweep" || !value || known == report_structures().end())
      continue;
    auto [it, fresh] = index.try_emplace({accel, parameter}, sweeps.size());
    if (fresh) sweeps.push_back({*known, parameter, {}, {}, {}});
    Sweep& sweep = sweeps[it->second];
    const std::string scene = record_text(r, "scene");
    auto at = std::ranges::find(sweep.scenes, scene);
    if (at == sweep.scenes.end()) {
      const int marker = int(std::ranges::find(all_scenes, scene) - all_scenes.begin());
      sweep.scenes.push_back(scene);
      sweep.time.push_back({*known, marker, {}});
      sweep.memory.push_back({*known, marker, {}});
      at = sweep.scenes.end() - 1;
    }
    const size_t s = size_t(at - sweep.scenes.begin());
    if (const auto t = record_number(r, "trace_seconds"))
      sweep.time[s].points.emplace_back(*value, *t);
    if (const auto m = record_number(r, "memory_bytes"))
      sweep.memory[s].points.emplace_back(*value, *m / 1e6);
  }
  for (Sweep& sweep : sweeps)
    for (auto* list : {&sweep.time, &sweep.memory})
      for (Series& s : *list) std::ranges::sort(s.points);
  return sweeps;
}

void draw_sweep_panel(ImDrawList& list, ImVec2 min, ImVec2 max, const std::vector<Series>& series,
                      const std::string& x_name, const std::string& y_name) {
  const Panel panel = fitted_panel(min, max, series, true, false);
  draw_y_axis(list, panel, y_name);
  draw_x_axis(list, panel, x_name);
  for (const Series& s : series) draw_series(list, panel, s);
  draw_box(list, panel);
}

void draw_scene_markers(ImDrawList& list, ImVec2 at, const Sweep& sweep, float width) {
  for (size_t i = 0; i < sweep.scenes.size(); ++i) {
    draw_marker(list, ImVec2(at.x + 5, at.y + 7), sweep.time[i].marker, kInk);
    const std::string name = fit(sweep.scenes[i], width / float(sweep.scenes.size()) - 24);
    draw_text(list, ImVec2(at.x + 13, at.y), kInk, name);
    at.x += 13 + text_width(name) + 12;
  }
}

bool sweep_plot(const json& records, const std::string& path) {
  const std::vector<Sweep> sweeps = collect_sweeps(records);
  if (sweeps.empty()) return false;
  const ImVec2 cell(float(kPlotWidth) / kColumns, 560);
  const int rows = int((sweeps.size() + kColumns - 1) / kColumns);
  Canvas canvas(kPlotWidth, int(kTop + float(rows) * cell.y));
  ImDrawList& list = canvas.list();
  draw_text(list, ImVec2(20, 8), kInk,
            "Parameter sweeps: warm trace time (top) and memory (bottom) against the swept "
            "parameter; one marker shape per scene; log y, log x where the values span a decade");
  for (size_t i = 0; i < sweeps.size(); ++i) {
    const Sweep& sweep = sweeps[i];
    const ImVec2 o = cell_origin(i, kColumns, cell, kTop);
    draw_text(list, ImVec2(o.x + 20, o.y + 4), colour_of(sweep.accel),
              std::string(sweep.accel) + ": " + sweep.parameter);
    draw_scene_markers(list, ImVec2(o.x + 20, o.y + 22), sweep, cell.x - 40);
    draw_sweep_panel(list, ImVec2(o.x + 70, o.y + 70), ImVec2(o.x + cell.x - 15, o.y + 270),
                     sweep.time, sweep.parameter, "trace time (s)");
    draw_sweep_panel(list, ImVec2(o.x + 70, o.y + 330), ImVec2(o.x + cell.x - 15, o.y + 520),
                     sweep.memory, sweep.parameter, "memory (MB)");
  }
  canvas.write(path);
  return true;
}

}  // namespace

std::array<uint8_t, 3> structure_colour(std::string_view accel) {
  // A packet column: its structure's colour, halfway to white.
  if (const auto packets = packet_column_structure(accel)) {
    std::array<uint8_t, 3> colour = structure_colour(*packets);
    for (uint8_t& c : colour) c = uint8_t((c + 255) / 2);
    return colour;
  }
  const Structure* structure = find_structure(accel);
  return structure ? structure->colour : std::array<uint8_t, 3>{127, 127, 127};
}

std::vector<std::string> write_bench_plots(const json& records, const std::string& out_dir) {
  static const json no_records = json::array();
  const json& list = records.is_array() ? records : no_records;
  std::vector<std::string> written;
  for (const auto& [name, plot] :
       {std::pair{"relative_to_zero.png", &relative_plot}, std::pair{"speedup.png", &speedup_plot},
        std::pair{"rmse_vs_time.png", &rmse_plot}, std::pair{"sweep.png", &sweep_plot}})
    if (plot(list, out_dir + "/" + name)) written.emplace_back(name);
  return written;
}

}  // namespace gs::app
