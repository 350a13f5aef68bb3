#include "bench/report.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <nlohmann/json.hpp>
#include <set>

#include "core/accel/registry.h"
#include "core/base/text.h"

namespace gs {

using json = nlohmann::json;

namespace {

constexpr const char* kNotRun = "—";
constexpr const char* kNotMeasured = "n/a";
constexpr const char* kCapMark = "†";
constexpr const char* kLoadMark = "‡";

// The structures the paper compared the 1D grid with (§7); its claim is about these.
std::vector<std::string_view> paper_rivals() {
  std::vector<std::string_view> rivals = structure_names(StructureGroup::paper);
  std::erase(rivals, "grid1d");
  return rivals;
}
// The scenes of the paper's Figure 12 (§7.1); bench scenes stand for them through "role".
constexpr std::array<const char*, 5> kPaperScenes = {"pyramid", "lumpy", "drum", "trike", "car"};
// Warm medians on a shared machine still move by a few percent: within this the discussion
// calls two times a tie (the targets' verdicts stay strict).
constexpr double kTie = 0.03;
// Per-ray counts closer than this are "similar" when the discussion looks for the why.
constexpr double kCountMargin = 0.10;

// ---- Reading records -------------------------------------------------------------------

std::optional<double> trace_time(const json* record) {
  return record ? record_number(*record, "trace_seconds") : std::nullopt;
}

// Two records' times to compare (of one scene, workload and thread count): their times
// relative to zero-overhead where both have one, else their warm trace seconds. The bench
// divides each warm render by a render of the zero-overhead replay taken right after it, so
// the first cancels most of the machine's drift between two figures taken minutes apart.
std::optional<std::pair<double, double>> compared_times(const json* a, const json* b) {
  for (const char* key : {"relative_to_zero", "trace_seconds"}) {
    const auto ta = a ? record_number(*a, key) : std::nullopt;
    const auto tb = b ? record_number(*b, key) : std::nullopt;
    if (ta && tb) return std::pair{*ta, *tb};
  }
  return std::nullopt;
}

// The faster of two records (compared_times); one without a time loses.
const json* faster(const json* a, const json* b) {
  if (!trace_time(b)) return a ? a : b;
  if (!trace_time(a)) return b;
  const auto times = compared_times(a, b);
  return times && times->second < times->first ? b : a;
}

// A structure "at its best setting": the faster of its default record and its best sweep
// point (re-measured at full protocol: primary_shadow, 1 thread); the default when no sweep
// ran.
const json* best_record(const json& records, const std::string& scene, std::string_view accel) {
  return faster(find_record(records, {scene, accel}),
                find_record(records, {scene, accel, "primary_shadow", "best"}));
}

// The fastest of `accels` at their best settings on one scene, or nullptr.
const json* fastest_best(const json& records, const std::string& scene,
                         const std::vector<std::string_view>& accels) {
  const json* winner = nullptr;
  for (std::string_view accel : accels) winner = faster(winner, best_record(records, scene, accel));
  return winner;
}

struct SceneInfo {
  std::string role;
  bool varying = false;
  std::optional<double> triangles;
};

SceneInfo scene_info(const json& records, const std::string& scene) {
  for (const json& record : records)
    if (record.is_object() && record_text(record, "scene") == scene)
      return {record_text(record, "role"), record_flag(record, "varying_complexity"),
              record_number(record, "triangles")};
  return {};
}

// Structures with at least one record, in report order.
std::vector<std::string_view> structures_run(const json& records) {
  std::vector<std::string_view> run;
  for (std::string_view accel : report_structures())
    for (const json& record : records)
      if (record.is_object() && record_text(record, "accel") == accel) {
        run.push_back(accel);
        break;
      }
  return run;
}

bool was_run(const json& records, std::string_view accel) {
  return std::ranges::count(structures_run(records), accel) > 0;
}

bool has_records(const json& records, std::string_view workload, std::string_view setting = "",
                 int threads = 0) {
  for (const json& record : records) {
    if (!record.is_object() || record_text(record, "workload") != workload) continue;
    if (!setting.empty() && record_text(record, "setting") != setting) continue;
    if (threads && record_number(record, "threads") != double(threads)) continue;
    return true;
  }
  return false;
}

// Thread counts above one among the default primary_shadow records, ascending.
std::vector<int> multi_thread_counts(const json& records) {
  std::set<int> counts;
  for (const json& record : records)
    if (record.is_object() && record_text(record, "workload") == "primary_shadow" &&
        record_text(record, "setting") == "default")
      if (const auto threads = record_number(record, "threads"); threads && *threads > 1)
        counts.insert(int(*threads));
  return {counts.begin(), counts.end()};
}

const json* calibration_record(const json& records) {
  for (const json& record : records)
    if (record.is_object() && record_text(record, "accel") == "calibration") return &record;
  return nullptr;
}

// ---- Formatting ------------------------------------------------------------------------

std::string format(const char* spec, double value) {
  char text[64];
  std::snprintf(text, sizeof text, spec, value);
  return text;
}

std::string fixed2(double value) { return format("%.2f", value); }

// The marks a figure carries: † estimated over the time cap, ‡ taken under load.
std::string figure_marks(const json& record) {
  return std::string(record_flag(record, "over_time_cap") ? kCapMark : "") +
         (record_flag(record, "under_load") ? kLoadMark : "");
}

// A figure of a record as a table cell: "—" without a record, "n/a" for null.
std::string cell(const json* record, const char* key,
                 const std::function<std::string(double)>& show) {
  if (!record) return kNotRun;
  const auto value = record_number(*record, key);
  return value ? show(*value) : kNotMeasured;
}

std::string relative_cell(const json* record) {
  const std::string text = cell(record, "relative_to_zero", fixed2);
  return record && text != kNotMeasured ? text + figure_marks(*record) : text;
}

// A record's speed in prose: relative to zero when known, else its seconds. The targets'
// lines take 3 decimals so that a figure just short of a bound never prints as the bound.
std::string speed_text(const json& record, const char* spec = "%.2f") {
  if (const auto relative = record_number(record, "relative_to_zero"))
    return format(spec, *relative) + "×" + figure_marks(record);
  if (const auto seconds = record_number(record, "trace_seconds"))
    return format("%.3g s", *seconds) + figure_marks(record);
  return kNotMeasured;
}

std::string named_speed(const json& record) {
  std::string text = record_text(record, "accel") + " " + speed_text(record, "%.3f");
  if (record_text(record, "setting") == "best") text += " (best setting)";
  return text;
}

// A parameter or constant as written in prose: strings bare, reals to 4 digits.
std::string value_text(const json& value) {
  if (value.is_string()) return value.get<std::string>();
  if (value.is_number_float()) return format("%.4g", value.get<double>());
  return value.dump();
}

std::string join(const std::vector<std::string>& parts, const std::string& separator) {
  std::string out;
  for (const std::string& part : parts) out += (out.empty() ? "" : separator) + part;
  return out;
}

// The scene's label in a table (a user's path may hold '|', which would split the cell).
std::string scene_cell(const json& records, const std::string& scene) {
  std::string label;
  for (char c : scene) label += c == '|' ? "\\|" : std::string(1, c);
  const std::string role = scene_info(records, scene).role;
  return role.empty() || role == scene ? label : label + " (as " + role + ")";
}

struct Table {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
};

std::string markdown(const Table& table) {
  std::string out = "| " + join(table.header, " | ") + " |\n|---|";
  for (size_t i = 1; i < table.header.size(); ++i) out += "--:|";
  out += "\n";
  for (const auto& row : table.rows) out += "| " + join(row, " | ") + " |\n";
  return out + "\n";
}

std::string triangles_cell(const json& records, const std::string& scene) {
  const auto triangles = scene_info(records, scene).triangles;
  return triangles ? count_text(*triangles) : kNotMeasured;
}

// The index of the record with the lowest relative_to_zero (the row's fastest), or npos.
size_t lowest_relative(const std::vector<const json*>& picked) {
  size_t lowest = std::string::npos;
  double lowest_value = INFINITY;
  for (size_t i = 0; i < picked.size(); ++i)
    if (const auto value = picked[i] ? record_number(*picked[i], "relative_to_zero") : std::nullopt;
        value && *value < lowest_value)
      lowest = i, lowest_value = *value;
  return lowest;
}

// ---- Figure 12 tables ------------------------------------------------------------------

using Pick = std::function<const json*(const std::string& scene, std::string_view accel)>;
using Suffix = std::function<std::string(const std::string& scene, std::string_view accel)>;

// Rows scenes, columns structures, cells time relative to the zero-overhead method (the
// layout of Figure 12), then zero's own seconds. With `packets`, a column "<structure>
// packets" follows the structures for each that has packet records. `suffix` adds to each
// single-ray cell (speed-ups).
std::string relative_table(const json& records, std::string_view workload, int threads,
                           const Pick& pick, const Pick& packets = nullptr,
                           const Suffix& suffix = nullptr) {
  struct Column {
    std::string_view label, accel;
    const Pick& pick;
  };
  const std::vector<std::string> scenes = record_scenes(records);
  std::vector<Column> columns;
  for (std::string_view accel : structures_run(records)) columns.push_back({accel, accel, pick});
  for (std::string_view label : packets ? packet_columns() : std::vector<std::string_view>{}) {
    const std::string_view accel = *packet_column_structure(label);
    if (std::ranges::any_of(scenes, [&](const std::string& s) { return packets(s, accel); }))
      columns.push_back({label, accel, packets});
  }
  Table table{{"scene", "triangles"}, {}};
  for (const Column& column : columns) table.header.emplace_back(column.label);
  table.header.emplace_back("zero (s)");
  for (const std::string& scene : scenes) {
    std::vector<const json*> picked;
    for (const Column& column : columns) picked.push_back(column.pick(scene, column.accel));
    if (std::ranges::count(picked, nullptr) == std::ssize(picked)) continue;
    const size_t fastest = lowest_relative(picked);
    std::vector<std::string> row{scene_cell(records, scene), triangles_cell(records, scene)};
    for (size_t i = 0; i < picked.size(); ++i) {
      const std::string text = relative_cell(picked[i]);
      row.push_back(i == fastest ? "**" + text + "**" : text);
      if (suffix && &columns[i].pick == &pick) row.back() += suffix(scene, columns[i].accel);
    }
    const json* zero = find_record(records, {scene, "zero", workload, "default", threads});
    row.push_back(cell(zero, "trace_seconds", [](double s) { return format("%.3g", s); }));
    table.rows.push_back(row);
  }
  if (table.rows.empty()) return "Not run: no " + std::string(workload) + " records.\n\n";
  return markdown(table);
}

Pick setting_pick(const json& records, std::string_view workload, std::string_view setting,
                  int threads) {
  return [&records, workload, setting, threads](const std::string& scene, std::string_view accel) {
    return find_record(records, {scene, accel, workload, setting, threads});
  };
}

Pick default_pick(const json& records, std::string_view workload, int threads) {
  return setting_pick(records, workload, "default", threads);
}

Pick packets_pick(const json& records, std::string_view workload, int threads) {
  return setting_pick(records, workload, "packets", threads);
}

// "max_granularity 32 (default 20)" for every parameter where best differs from default.
std::vector<std::string> parameter_changes(const json& best, const json* standard) {
  std::vector<std::string> changes;
  const auto params = best.find("params");
  if (params == best.end() || !params->is_object()) return changes;
  const json* standard_params = nullptr;
  if (standard)
    if (const auto it = standard->find("params"); it != standard->end() && it->is_object())
      standard_params = &*it;
  for (const auto& [name, value] : params->items()) {
    const bool known = standard_params && standard_params->contains(name);
    if (known && (*standard_params)[name] == value) continue;
    // 0 in a structure's own limits means "the structure's default" (AccelParams).
    const bool own_default = known && (*standard_params)[name] == 0;
    changes.push_back(name + " " + value_text(value) +
                      (own_default ? " (default: the structure's own)"
                       : known     ? " (default " + value_text((*standard_params)[name]) + ")"
                                   : ""));
  }
  return changes;
}

std::string best_settings_list(const json& records) {
  std::vector<std::string> lines;
  for (const std::string& scene : record_scenes(records))
    for (std::string_view accel : report_structures()) {
      const json* best = best_record(records, scene, accel);
      if (!best || record_text(*best, "setting") != "best") continue;
      const auto changes = parameter_changes(*best, find_record(records, {scene, accel}));
      lines.push_back("- " + scene + ", " + std::string(accel) + ": " +
                      (changes.empty() ? "the default parameters" : join(changes, ", ")));
    }
  if (lines.empty())
    return has_records(records, "primary_shadow", "best")
               ? "No sweep point beat a default setting.\n\n"
               : "No sweep ran: every structure is at its default setting.\n\n";
  return "Best settings (where a sweep point beat the default):\n\n" + join(lines, "\n") + "\n\n";
}

std::string speedup_suffix(const json& records, int threads, const std::string& scene,
                           std::string_view accel) {
  const json* many = find_record(records, {scene, accel, "primary_shadow", "default", threads});
  const auto speedup =
      many ? record_speedup(find_record(records, {scene, accel}), *many) : std::nullopt;
  return speedup ? " (" + fixed2(*speedup) + "×)" : "";
}

std::string figure12_section(const json& records) {
  std::string out =
      "## Time relative to the zero-overhead method (Figure 12)\n\n"
      "Rows are scenes, columns structures, as in the paper's Figure 12: each warm render "
      "(tracing and shading, the structure already built) divided by a render of the "
      "zero-overhead method on the same rays (§7) taken right after it, median of the "
      "repetitions' ratios (the machine's speed drifts over minutes), so 1.00 is the floor; "
      "the structures of a row take their warm renders in rounds, one of each per round, so "
      "that they are timed in the same minutes. "
      "— not run, n/a not measured, † over the time cap (one pass over a subset of the rows, "
      "its time scaled up: an estimate, not a warm median), ‡ taken while other processes kept "
      "more than a quarter of a core busy (`others_busy_cores`), "
      "**bold** the fastest in its row. `bvh` is our plain scalar traversal (one ray at a "
      "time, no SIMD, no packets); `embree` is Intel Embree's SIMD BVH. Every column traces "
      "one ray at a time but the \"packets\" ones: the primary rays of 8x8 pixel blocks, then "
      "their shadow rays, walked together (grid1d's packet walk, Embree's rtcIntersect16 / "
      "rtcOccluded16); bounces stay single rays.\n\n"
      "### Primary and shadow rays, 1 thread, default settings\n\n" +
      relative_table(records, "primary_shadow", 1, default_pick(records, "primary_shadow", 1),
                     packets_pick(records, "primary_shadow", 1)) +
      "### Primary and shadow rays, 1 thread, each structure at its best setting\n\n" +
      relative_table(records, "primary_shadow", 1,
                     [&records](const std::string& scene, std::string_view accel) {
                       return best_record(records, scene, accel);
                     }) +
      best_settings_list(records) + "### Diffuse rays, 1 thread, default settings\n\n" +
      relative_table(records, "diffuse", 1, default_pick(records, "diffuse", 1),
                     packets_pick(records, "diffuse", 1));
  for (int threads : multi_thread_counts(records))
    out += "### Primary and shadow rays, " + std::to_string(threads) +
           " threads, default settings (speed-up over 1 thread)\n\n" +
           relative_table(records, "primary_shadow", threads,
                          default_pick(records, "primary_shadow", threads),
                          packets_pick(records, "primary_shadow", threads),
                          [&records, threads](const std::string& scene, std::string_view accel) {
                            return speedup_suffix(records, threads, scene, accel);
                          });
  return out;
}

// ---- Targets ---------------------------------------------------------------------------

struct SceneCheck {
  std::string scene;
  std::optional<bool> met;  // nullopt: not measurable on this scene
  std::string detail;
};

// "- **met** (2 of 2 scenes): TARGET. scene: detail; ..."
std::string verdict(const std::string& target, const std::vector<SceneCheck>& checks,
                    const std::string& if_unchecked) {
  int checked = 0, met = 0;
  std::vector<std::string> details;
  for (const SceneCheck& check : checks) {
    checked += check.met.has_value();
    met += check.met.value_or(false);
    const std::string mark = !check.met ? "" : *check.met ? " (met)" : " (missed)";
    details.push_back(check.scene + ": " + check.detail + mark);
  }
  if (checked == 0)
    return "- **not checked**: " + target + ". " +
           (details.empty() ? if_unchecked : join(details, "; ")) + ".\n";
  return "- **" + std::string(met == checked ? "met" : "missed") + "** (" + std::to_string(met) +
         " of " + std::to_string(checked) + " scenes): " + target + ". " + join(details, "; ") +
         ".\n";
}

SceneCheck paper_claim_check(const json& records, const std::string& scene) {
  const json* grid = best_record(records, scene, "grid1d");
  const json* rival = fastest_best(records, scene, paper_rivals());
  if (!trace_time(grid)) return {scene, std::nullopt, "grid1d not measured"};
  if (!trace_time(rival)) return {scene, std::nullopt, "none of uniform, octree, grid3d measured"};
  const auto times = compared_times(grid, rival);
  return {scene, times && times->first <= times->second,
          named_speed(*grid) + " vs " + named_speed(*rival)};
}

std::string mrays(double rate) { return format("%.2f", rate / 1e6); }

// grid1d's speed over Embree's on the same rays (Embree's time over grid1d's, compared_times),
// when both are measured.
std::optional<double> embree_ratio(const json* grid, const json* embree) {
  const auto rate = [](const json* record) {
    return record ? record_number(*record, "rays_per_second").value_or(0) : 0.0;
  };
  const auto times = compared_times(grid, embree);
  if (rate(grid) <= 0 || rate(embree) <= 0 || !times || times->first <= 0) return std::nullopt;
  return times->second / times->first;
}

SceneCheck embree_check(const json& records, const std::string& scene) {
  const json* grid = find_record(records, {scene, "grid1d"});
  const json* embree = find_record(records, {scene, "embree"});
  const auto ratio = embree_ratio(grid, embree);
  if (!ratio) return {scene, std::nullopt, embree ? "rays/s not measured" : "embree not run"};
  return {scene, *ratio >= kEmbreeTarget,
          cell(grid, "rays_per_second", mrays) + " vs " + cell(embree, "rays_per_second", mrays) +
              " Mrays/s = " + format("%.3f", *ratio)};
}

// grid1d against our scalar BVH, each at its best setting.
SceneCheck bvh_check(const json& records, const std::string& scene) {
  const json* grid = best_record(records, scene, "grid1d");
  const json* bvh = best_record(records, scene, "bvh");
  const auto times = compared_times(grid, bvh);
  if (!trace_time(grid) || !trace_time(bvh) || !times)
    return {scene, std::nullopt, bvh ? "grid1d not measured" : "bvh not run"};
  return {scene, times->first < times->second, named_speed(*grid) + " vs " + named_speed(*bvh)};
}

// From a loaded scene to its first image: the structure's build (grid1d's with its sampling
// pass) and its first render (grid1d's with its lazy build), default settings, 1 thread.
std::optional<double> answer_seconds(const json* record) {
  if (!record) return std::nullopt;
  const auto build = record_number(*record, "build_seconds");
  const auto first = record_number(*record, "first_pass_seconds");
  if (!build || !first) return std::nullopt;
  return *build + *first;
}

// On `threads` threads for both structures' builds and first renders.
SceneCheck answer_time_check(const json& records, const std::string& scene, int threads) {
  const json* embree =
      find_record(records, {scene, "embree", "primary_shadow", "default", threads});
  const auto grid_seconds =
      answer_seconds(find_record(records, {scene, "grid1d", "primary_shadow", "default", threads}));
  const auto embree_seconds = answer_seconds(embree);
  if (!grid_seconds || !embree_seconds)
    return {scene, std::nullopt, embree ? "build or first render not measured" : "embree not run"};
  return {scene, *grid_seconds <= *embree_seconds,
          format("%.3f", *grid_seconds) + " s vs " + format("%.3f", *embree_seconds) + " s"};
}

// " (active 0.63, fallback 2.1%)": why a packet record gained what it did.
std::string packet_figures(const json& record) {
  const auto active = record_number(record, "packet_active_fraction");
  const auto fallback = record_number(record, "packet_fallback_fraction");
  if (!active && !fallback) return "";
  return " (" + (active ? "active " + fixed2(*active) : std::string("active n/a")) +
         (fallback ? format(", fallback %.1f%%", 100.0 * *fallback) : "") + ")";
}

SceneCheck packet_gain_check(const json& records, const std::string& scene) {
  const json* single = find_record(records, {scene, "grid1d"});
  const json* packets = find_record(records, {scene, "grid1d", "primary_shadow", "packets"});
  const auto times = compared_times(single, packets);
  if (!times || times->second <= 0) return {scene, std::nullopt, "not measured with and without"};
  const double gain = times->first / times->second;
  return {scene, gain >= kPacketGainTarget, format("%.3f", gain) + "×" + packet_figures(*packets)};
}

SceneCheck packet_embree_check(const json& records, const std::string& scene) {
  const json* grid = find_record(records, {scene, "grid1d", "primary_shadow", "packets"});
  const json* embree = find_record(records, {scene, "embree", "primary_shadow", "packets"});
  const auto ratio = embree_ratio(grid, embree);
  if (!ratio) return {scene, std::nullopt, embree ? "rays/s not measured" : "embree not run"};
  return {scene, *ratio >= kPacketEmbreeTarget,
          cell(grid, "rays_per_second", mrays) + " vs " + cell(embree, "rays_per_second", mrays) +
              " Mrays/s = " + format("%.3f", *ratio)};
}

SceneCheck packet_bounce_check(const json& records, const std::string& scene) {
  const json* single = find_record(records, {scene, "grid1d", "diffuse"});
  const json* packets = find_record(records, {scene, "grid1d", "diffuse", "packets"});
  const auto times = compared_times(single, packets);
  if (!times || times->first <= 0) return {scene, std::nullopt, "not measured with and without"};
  return {scene, times->second <= kPacketBounceSlowdown * times->first,
          "packets / single time " + format("%.3f", times->second / times->first) +
              packet_figures(*packets)};
}

// " (1.97 cores busy)": thread CPU time over wall time while a record's warm renders ran.
std::string cores_used(const json& record) {
  const auto cpu = record_number(record, "cpu_seconds");
  const auto wall = record_number(record, "wall_seconds");
  return cpu && wall && *wall > 0 ? format(" (%.2f cores busy)", *cpu / *wall) : "";
}

SceneCheck speedup_check(const json& records, const std::string& scene) {
  const json* one = find_record(records, {scene, "grid1d"});
  const json* two = find_record(records, {scene, "grid1d", "primary_shadow", "default", 2});
  const auto speedup = one && two ? record_speedup(one, *two) : std::nullopt;
  if (!speedup) return {scene, std::nullopt, "not measured at 1 and 2 threads"};
  return {
      scene, *speedup >= kSpeedupTarget,
      format("%.3f", *speedup) + "×" + figure_marks(*one) + figure_marks(*two) + cores_used(*two)};
}

SceneCheck calibration_check(const json& records, const std::string& scene) {
  const json* standard = find_record(records, {scene, "grid1d"});
  const json* calibrated = find_record(records, {scene, "grid1d", "primary_shadow", "calibrated"});
  const auto times = compared_times(calibrated, standard);
  if (!times) return {scene, std::nullopt, "not measured with both"};
  return {scene, times->first <= times->second,
          "calibrated " + speed_text(*calibrated, "%.3f") + " vs default " +
              speed_text(*standard, "%.3f")};
}

std::vector<SceneCheck> checks_for(
    const json& records, bool varying_only,
    const std::function<SceneCheck(const json&, const std::string&)>& check) {
  std::vector<SceneCheck> checks;
  for (const std::string& scene : record_scenes(records))
    if (!varying_only || scene_info(records, scene).varying)
      checks.push_back(check(records, scene));
  return checks;
}

// Time to the answer: the build (grid1d's with its sampling pass) and the first render (grid1d's
// with its lazy build), both structures building and tracing on `threads` threads.
std::string answer_time_verdict(const json& records, int threads) {
  return verdict(
      "grid1d's time to the answer, its build, sampling pass and first render (lazy build "
      "included), at most Embree's build and first render (" +
          std::to_string(threads) + (threads == 1 ? " thread" : " threads") +
          " for both builds and renders, default settings; seconds)",
      was_run(records, "embree") ? checks_for(records, false,
                                              [threads](const json& all, const std::string& scene) {
                                                return answer_time_check(all, scene, threads);
                                              })
                                 : std::vector<SceneCheck>{},
      "embree not run (not in this build or not asked for)");
}

// One time-to-the-answer verdict per thread count the run has: 1, then the multi-thread ones.
std::string answer_time_verdicts(const json& records) {
  std::string out = answer_time_verdict(records, 1);
  for (const int threads : multi_thread_counts(records))
    out += answer_time_verdict(records, threads);
  return out;
}

std::string targets_section(const json& records) {
  return "## Targets\n\n" +
         verdict(
             "grid1d at least as fast as the best of uniform, octree and grid3d, each "
             "at its best setting, on every scene with varying local complexity (the "
             "paper's claim, §7.1; time relative to zero-overhead)",
             checks_for(records, true, paper_claim_check),
             "no scene with varying local complexity was run") +
         verdict("grid1d at least " + fixed2(kEmbreeTarget) +
                     " of Embree's single-thread speed on every scene (primary and shadow "
                     "rays; rays/s, then the ratio of their times relative to zero-overhead)",
                 was_run(records, "embree") ? checks_for(records, false, embree_check)
                                            : std::vector<SceneCheck>{},
                 "embree not run (not in this build or not asked for)") +
         answer_time_verdicts(records) +
         verdict(
             "grid1d faster than our scalar BVH on every scene, each at its best setting "
             "(time relative to zero-overhead)",
             was_run(records, "bvh") ? checks_for(records, false, bvh_check)
                                     : std::vector<SceneCheck>{},
             "bvh not run") +
         verdict("grid1d with packets at least " + fixed2(kPacketGainTarget) +
                     "× its own single rays (primary and shadow rays, 1 thread; single-ray "
                     "time / packet time, then the packets' active fraction and fallbacks)",
                 has_records(records, "primary_shadow", "packets")
                     ? checks_for(records, false, packet_gain_check)
                     : std::vector<SceneCheck>{},
                 "no packet runs") +
         verdict("grid1d with packets at least " + fixed2(kPacketEmbreeTarget) +
                     " of Embree's packets' rays/s (primary and shadow rays, 1 thread; ratio)",
                 has_records(records, "primary_shadow", "packets") && was_run(records, "embree")
                     ? checks_for(records, false, packet_embree_check)
                     : std::vector<SceneCheck>{},
                 "no packet runs of both") +
         verdict("grid1d's diffuse bounces with packets on at most " +
                     format("%.0f%%", 100.0 * (kPacketBounceSlowdown - 1.0)) +
                     " slower than with single rays (1 thread)",
                 has_records(records, "diffuse", "packets")
                     ? checks_for(records, false, packet_bounce_check)
                     : std::vector<SceneCheck>{},
                 "no diffuse packet runs") +
         verdict("grid1d's 2-thread speed-up at least " + fixed2(kSpeedupTarget) +
                     "× on warm runs (1-thread time / 2-thread time)",
                 has_records(records, "primary_shadow", "default", 2)
                     ? checks_for(records, false, speedup_check)
                     : std::vector<SceneCheck>{},
                 "no 2-thread runs") +
         verdict(
             "grid1d with calibrated cost constants (`gridscope calibrate`) at least as "
             "fast as with the default constants",
             has_records(records, "primary_shadow", "calibrated")
                 ? checks_for(records, false, calibration_check)
                 : std::vector<SceneCheck>{},
             "no calibrated runs") +
         "\n";
}

// ---- Other tables ----------------------------------------------------------------------

std::string embree_section(const json& records) {
  std::string out = "## grid1d against Embree (primary and shadow rays, 1 thread)\n\n";
  if (!was_run(records, "embree"))
    return out + "Not run: embree (not in this build or not asked for).\n\n";
  Table table{{"scene", "grid1d Mrays/s", "embree Mrays/s", "grid1d / embree", "grid1d × zero",
               "embree × zero", "grid1d packets Mrays/s", "embree packets Mrays/s",
               "packets: grid1d / embree"},
              {}};
  const auto ratio_cell = [](const json* grid, const json* embree) {
    const auto ratio = embree_ratio(grid, embree);
    return ratio ? fixed2(*ratio) : std::string(kNotMeasured);
  };
  for (const std::string& scene : record_scenes(records)) {
    const json* grid = find_record(records, {scene, "grid1d"});
    const json* embree = find_record(records, {scene, "embree"});
    if (!grid && !embree) continue;
    const json* grid_packets = find_record(records, {scene, "grid1d", "primary_shadow", "packets"});
    const json* embree_packets =
        find_record(records, {scene, "embree", "primary_shadow", "packets"});
    table.rows.push_back(
        {scene_cell(records, scene), cell(grid, "rays_per_second", mrays),
         cell(embree, "rays_per_second", mrays), ratio_cell(grid, embree), relative_cell(grid),
         relative_cell(embree), cell(grid_packets, "rays_per_second", mrays),
         cell(embree_packets, "rays_per_second", mrays), ratio_cell(grid_packets, embree_packets)});
  }
  return out + markdown(table);
}

std::string build_cell(const json* record, const std::optional<double>& triangles) {
  if (!record) return kNotRun;
  std::string text = cell(record, "build_seconds", [](double s) { return format("%.3g", s); });
  if (const auto lazy = record_number(*record, "lazy_build_seconds"); lazy && *lazy > 0)
    text += "+" + format("%.3g", *lazy);
  text += " s, ";
  const auto bytes = record_number(*record, "memory_bytes");
  return text + (bytes && triangles && *triangles > 0 ? format("%.0f B", *bytes / *triangles)
                                                      : std::string(kNotMeasured));
}

// The structures that ran but brute force (it builds nothing and is the reference), also
// appended to the table's header.
std::vector<std::string_view> structure_columns(const json& records, Table& table) {
  std::vector<std::string_view> structures;
  for (std::string_view accel : structures_run(records))
    if (accel != "brute") structures.push_back(accel), table.header.emplace_back(accel);
  return structures;
}

std::string build_section(const json& records) {
  Table table{{"scene", "triangles"}, {}};
  const std::vector<std::string_view> structures = structure_columns(records, table);
  for (const std::string& scene : record_scenes(records)) {
    const auto triangles = scene_info(records, scene).triangles;
    std::vector<std::string> row{scene_cell(records, scene), triangles_cell(records, scene)};
    for (std::string_view accel : structures)
      row.push_back(build_cell(find_record(records, {scene, accel}), triangles));
    table.rows.push_back(row);
  }
  return "## Build time and memory (default settings)\n\n"
         "Per cell: build seconds (up-front build and sampling pass, + lazy building during "
         "the first render), then memory in bytes per triangle.\n\n" +
         markdown(table);
}

std::string references_of(const json& records, const std::string& scene) {
  std::set<std::string> names;
  for (const json& record : records)
    if (record.is_object() && record_text(record, "scene") == scene &&
        record_text(record, "workload") == "primary_shadow" && record.contains("reference") &&
        record_number(record, "disagreeing_rays"))
      names.insert(record["reference"].is_string() ? record["reference"].get<std::string>()
                                                   : "none");
  return names.empty() ? std::string(kNotMeasured)
                       : join(std::vector<std::string>(names.begin(), names.end()), ", ");
}

std::string agreement_section(const json& records) {
  Table table{{"scene", "reference"}, {}};
  const std::vector<std::string_view> structures = structure_columns(records, table);
  // The packet measurements answer for the same rays: their columns follow.
  std::vector<std::string_view> packet_structures;
  for (std::string_view label : packet_columns())
    if (has_records(records, "primary_shadow", "packets") &&
        was_run(records, *packet_column_structure(label)))
      packet_structures.push_back(*packet_column_structure(label)),
          table.header.emplace_back(label);
  const auto agreement = [](const json* record) {
    const std::string rays = cell(record, "disagreeing_rays", count_text),
                      rmse = cell(record, "image_rmse", fixed2);
    return rays == rmse ? rays : rays + " / " + rmse;  // "—" or "n/a" once
  };
  for (const std::string& scene : record_scenes(records)) {
    std::vector<std::string> row{scene_cell(records, scene), references_of(records, scene)};
    for (std::string_view accel : structures)
      row.push_back(agreement(find_record(records, {scene, accel})));
    for (std::string_view accel : packet_structures)
      row.push_back(agreement(find_record(records, {scene, accel, "primary_shadow", "packets"})));
    table.rows.push_back(row);
  }
  return "## Agreement with the reference (primary and shadow rays, default settings)\n\n"
         "Per cell: rays whose answer differs from the reference's, then the image's RMSE "
         "against the reference image (0..255). The reference column names what they were "
         "compared with: brute force, or bvh (which answers exactly what brute force answers "
         "and is far faster on large scenes).\n\n" +
         markdown(table);
}

std::string calibration_section(const json& records) {
  std::string out = "## Calibrated cost constants (§6.2)\n\n";
  const json* calibration = calibration_record(records);
  if (!calibration) return out + "Not run: no calibration record.\n\n";
  const auto object = [&](const char* key) {
    const auto it = calibration->find(key);
    return it != calibration->end() && it->is_object() ? *it : json::object();
  };
  const json constants = object("constants"), defaults = object("defaults");
  Table table{{"constant", "calibrated", "default"}, {}};
  std::set<std::string> names;
  for (const auto& [name, value] : constants.items()) names.insert(name);
  for (const auto& [name, value] : defaults.items()) names.insert(name);
  for (const std::string& name : names)
    table.rows.push_back({name, constants.contains(name) ? value_text(constants[name]) : kNotRun,
                          defaults.contains(name) ? value_text(defaults[name]) : kNotRun});
  return out + markdown(table);
}

// ---- Discussion --------------------------------------------------------------------------

struct CountComparison {
  std::string what;
  double grid = 0, other = 0;
  int direction = 0;  // -1 grid1d lower, +1 higher, 0 similar
};

std::vector<CountComparison> compare_counts(const json& grid, const json& other) {
  std::vector<CountComparison> out;
  for (const auto& [key, what] : {std::pair{"tests_per_ray", "triangle tests per ray"},
                                  std::pair{"steps_per_ray", "cell steps per ray"}}) {
    const auto g = record_number(grid, key), o = record_number(other, key);
    if (!g || !o) continue;
    const int direction = *g < *o * (1 - kCountMargin) ? -1 : *g > *o * (1 + kCountMargin) ? 1 : 0;
    out.push_back({what, *g, *o, direction});
  }
  return out;
}

std::string count_phrase(const CountComparison& c) {
  return std::string(c.direction < 0   ? "fewer "
                     : c.direction > 0 ? "more "
                                       : "similar ") +
         c.what + " (" + format("%.1f", c.grid) + " against " + format("%.1f", c.other) + ")";
}

// Why grid1d won (outcome -1) or lost (+1) against `other`, from the per-ray counts.
std::string why_sentence(const json& grid, const json& other, int outcome) {
  const std::vector<CountComparison> counts = compare_counts(grid, other);
  if (counts.empty()) return "No per-ray counts to compare.";
  std::vector<std::string> because, despite, all;
  for (const CountComparison& c : counts) {
    all.push_back(count_phrase(c));
    if (c.direction != 0 && c.direction == outcome) because.push_back(count_phrase(c));
    if (c.direction != 0 && c.direction == -outcome) despite.push_back(count_phrase(c));
  }
  if (outcome == 0) return "It makes " + join(all, " and ") + ".";
  if (because.empty())
    return "The per-ray counts do not explain it: " + join(all, " and ") +
           ". The difference lies in what each step or test costs, likely " +
           (outcome > 0 ? "descending into voxels and updating traversal states (§5.2)."
                        : "its cheap steps on shared 1D traversal states (§5.2).");
  return "Likely why: " + join(because, " and ") +
         (despite.empty() ? "" : ", despite " + join(despite, " and ")) + ".";
}

std::string build_phrase(const json& record) {
  std::string text = format("%.3g s", record_number(record, "build_seconds").value_or(0));
  if (const auto lazy = record_number(record, "lazy_build_seconds"); lazy && *lazy > 0)
    text += format(" (+%.3g s lazily)", *lazy);
  return text;
}

std::string cost_sentence(const json& grid, const json& other, const SceneInfo& info) {
  std::string out;
  if (record_number(grid, "build_seconds") && record_number(other, "build_seconds"))
    out += " It builds in " + build_phrase(grid) + " against " + build_phrase(other) + ".";
  const auto gm = record_number(grid, "memory_bytes"), om = record_number(other, "memory_bytes");
  if (gm && om && info.triangles && *info.triangles > 0)
    out += " Memory: " + format("%.0f", *gm / *info.triangles) + " against " +
           format("%.0f", *om / *info.triangles) + " bytes per triangle.";
  return out;
}

std::string outcome_sentence(const json& grid, const json& rival, int outcome, double ratio) {
  const std::string rival_name = record_text(rival, "accel");
  const std::string figures = speed_text(grid) + " against " + speed_text(rival) + " for " +
                              rival_name + ", the fastest of uniform, octree and grid3d";
  if (outcome < 0)
    return "grid1d wins: " + figures + " (" + format("%.0f", (1 - ratio) * 100) + "% less time).";
  if (outcome > 0)
    return "grid1d loses: " + figures + " (" + format("%.0f", (ratio - 1) * 100) + "% more time).";
  return "grid1d ties: " + figures + " (within " + format("%.0f", kTie * 100) + "%).";
}

std::string modern_sentence(const json& records, const std::string& scene, const json& grid) {
  std::vector<std::string> parts;
  for (std::string_view accel : structure_names(StructureGroup::modern)) {
    const json* record = best_record(records, scene, accel);
    const auto times = compared_times(record, &grid);
    if (!times) continue;
    parts.push_back(std::string(accel) + " " + speed_text(*record) + " (" +
                    (times->first < times->second ? "faster" : "slower") + ")");
  }
  return parts.empty() ? "" : " Modern references: " + join(parts, ", ") + ".";
}

bool is_paper_role(const std::string& role) { return std::ranges::count(kPaperScenes, role) > 0; }

std::string discuss_scene(const json& records, const std::string& scene) {
  const SceneInfo info = scene_info(records, scene);
  std::string out = "- **" + scene + "**";
  if (is_paper_role(info.role))
    out += " (the paper's " + info.role + ")";
  else if (!info.role.empty())
    out += " (role: " + info.role + ")";
  out += ": ";
  const json* grid = best_record(records, scene, "grid1d");
  const json* rival = fastest_best(records, scene, paper_rivals());
  if (!trace_time(grid)) return out + "grid1d not measured.\n";
  const auto times = compared_times(grid, rival);
  if (!trace_time(rival) || !times) {
    out += "none of uniform, octree, grid3d measured.";
  } else {
    const double ratio = times->first / times->second;
    const int outcome = ratio < 1 - kTie ? -1 : ratio > 1 + kTie ? 1 : 0;
    out += outcome_sentence(*grid, *rival, outcome, ratio) + " " +
           why_sentence(*grid, *rival, outcome) + cost_sentence(*grid, *rival, info);
  }
  out += modern_sentence(records, scene, *grid);
  if (!info.varying)
    out +=
        " No varying local complexity here: the paper found the methods alike on such a "
        "scene (§7.1, pyramid).";
  return out + "\n";
}

std::string discussion_section(const json& records) {
  std::string out =
      "## Discussion\n\n"
      "Generated from the numbers above (primary and shadow rays, 1 thread, each structure at "
      "its best setting): per scene, grid1d against the fastest of the paper's other "
      "structures, what the per-ray counts say about why, and what it costs to build.\n\n";
  for (const std::string& scene : record_scenes(records)) out += discuss_scene(records, scene);
  return out + "\n";
}

// ---- Header and what did not run ---------------------------------------------------------

// The first record that carries `key`, preferring primary_shadow ones (the calibration
// record has no image).
const json* first_with(const json& records, const char* key) {
  const json* any = nullptr;
  for (const json& record : records)
    if (record.is_object() && record.contains(key)) {
      if (record_text(record, "workload") == "primary_shadow") return &record;
      if (!any) any = &record;
    }
  return any;
}

std::string header(const json& records) {
  std::string out = "# gridscope benchmark report\n\n";
  const json* first = first_with(records, "machine");
  if (!first) return out + "No measurements: results.json holds no records.\n\n";
  const json machine = (*first)["machine"].is_object() ? (*first)["machine"] : json::object();
  const auto field = [](const json& object, const char* key) {
    const auto it = object.find(key);
    return it == object.end() || it->is_null() ? std::string(kNotMeasured) : value_text(*it);
  };
  out += "Machine: " + field(machine, "cpu") + ", " + field(machine, "cores") + " cores, " +
         field(machine, "os") + ", " + field(machine, "compiler") + ". Commit `" +
         field(*first, "commit") + "`, seed " + field(*first, "seed") + ", " +
         field(*first, "repetitions") + " warm repetitions per figure (median). Images " +
         field(*first, "width") + "x" + field(*first, "height") + ", " + field(*first, "spp") +
         " spp.\n\n";
  if (record_flag(*first, "quick"))
    out +=
        "**Quick run** (`--quick`): small images and few repetitions; the figures show "
        "that the benchmark works, not what this machine can do.\n\n";
  return out;
}

std::string not_run_section(const json& records) {
  std::vector<std::string> lines;
  for (std::string_view accel : report_structures())
    if (!was_run(records, accel))
      lines.push_back(
          "- structure " + std::string(accel) +
          (accel == "embree" ? ": not in this build or not asked for" : ": not asked for"));
  std::set<std::string> roles;
  for (const json& record : records)
    if (record.is_object()) roles.insert(record_text(record, "role"));
  for (const char* role : kPaperScenes)
    if (!roles.contains(role))
      lines.push_back(std::string("- the paper's ") + role +
                      " scene: no scene stands for it (not asked for, or its mesh is not in "
                      "assets/: scripts/fetch-assets.sh)");
  for (const auto& [workload, what] :
       {std::pair{"diffuse", "diffuse rays"}, std::pair{"sweep", "parameter sweeps"},
        std::pair{"convergence", "convergence (RMSE against time)"}})
    if (!has_records(records, workload)) lines.push_back(std::string("- ") + what);
  if (multi_thread_counts(records).empty()) lines.push_back("- runs with more than 1 thread");
  if (lines.empty()) return "";
  return "## Not run\n\n" + join(lines, "\n") + "\n\n";
}

std::string plots_section(const std::vector<std::string>& plots) {
  if (plots.empty()) return "";
  std::string out = "## Plots\n\n";
  for (const std::string& plot : plots) out += "![" + plot + "](" + plot + ")\n\n";
  return out;
}

}  // namespace

// ---- Public ------------------------------------------------------------------------------

std::optional<double> record_number(const json& record, const char* key) {
  if (!record.is_object()) return std::nullopt;
  const auto it = record.find(key);
  if (it == record.end() || !it->is_number()) return std::nullopt;
  const double value = it->get<double>();
  return std::isfinite(value) ? std::optional(value) : std::nullopt;
}

std::optional<double> record_speedup(const json* one_thread, const json& many_threads) {
  if (const auto paired = record_number(many_threads, "speedup")) return paired;
  const auto one = one_thread ? record_number(*one_thread, "trace_seconds") : std::nullopt;
  const auto many = record_number(many_threads, "trace_seconds");
  if (!one || !many || *many <= 0) return std::nullopt;
  return *one / *many;
}

bool record_flag(const json& record, const char* key) {
  if (!record.is_object()) return false;
  const auto it = record.find(key);
  return it != record.end() && it->is_boolean() && it->get<bool>();
}

std::string record_text(const json& record, const char* key) {
  if (!record.is_object()) return "";
  const auto it = record.find(key);
  return it != record.end() && it->is_string() ? it->get<std::string>() : "";
}

const json* find_record(const json& records, const RecordKey& key) {
  if (!records.is_array()) return nullptr;
  for (const json& record : records)
    if (record.is_object() && record_text(record, "scene") == key.scene &&
        record_text(record, "accel") == key.accel &&
        record_text(record, "workload") == key.workload &&
        record_text(record, "setting") == key.setting &&
        record_number(record, "threads") == double(key.threads))
      return &record;
  return nullptr;
}

const std::vector<std::string_view>& report_structures() {
  static const std::vector<std::string_view> names = [] {
    std::vector<std::string_view> list;
    for (const Structure& structure : structures())
      if (!structure.needs_oracle) list.push_back(structure.name);
    return list;
  }();
  return names;
}

const std::vector<std::string_view>& packet_columns() {
  static const std::vector<std::string> labels = [] {
    std::vector<std::string> list;
    for (std::string_view accel : report_structures())
      if (find_structure(accel)->traces_packets) list.push_back(std::string(accel) + " packets");
    return list;
  }();
  static const std::vector<std::string_view> views(labels.begin(), labels.end());
  return views;
}

std::optional<std::string_view> packet_column_structure(std::string_view column) {
  constexpr std::string_view kSuffix = " packets";
  if (std::ranges::count(packet_columns(), column) == 0) return std::nullopt;
  return column.substr(0, column.size() - kSuffix.size());
}

std::vector<std::string> record_scenes(const json& records) {
  std::vector<std::string> scenes;
  if (!records.is_array()) return scenes;
  for (const json& record : records) {
    const std::string scene = record_text(record, "scene");
    if (!scene.empty() && std::ranges::count(scenes, scene) == 0) scenes.push_back(scene);
  }
  return scenes;
}

std::string bench_report_markdown(const json& records, const std::vector<std::string>& plots) {
  // Everything below iterates the records; anything but an array reads as no records.
  static const json no_records = json::array();
  const json& list = records.is_array() ? records : no_records;
  return header(list) + targets_section(list) + not_run_section(list) + figure12_section(list) +
         embree_section(list) + build_section(list) + agreement_section(list) +
         calibration_section(list) + discussion_section(list) + plots_section(plots);
}

}  // namespace gs
