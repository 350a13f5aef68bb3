// The benchmark's report: `gridscope bench` measures, writes results.json (a list of
// records, one per scene x structure x setting x workload x threads) and turns the same
// records into report.md. Everything here is a pure function of the records: no I/O, no
// clock, so the report can be regenerated from a results.json and checked in tests.
//
// The reading is lenient by design: a record or field of the wrong type counts as missing,
// a null figure prints "n/a", a structure or scene without records prints "—" and is named
// under "Not run". A results.json from a partial or interrupted bench still gives a report.
#pragma once
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace gs {

// The structures in the order tables and plots show them, the registry's
// (core/accel/registry.h): the paper's four (§7), then the modern ones, then brute force; not
// the zero-overhead method, the floor every time is divided by.
const std::vector<std::string_view>& report_structures();

// The targets: grid1d at least this fraction of Embree's single-thread speed, and
// at least this speed-up on 2 threads.
inline constexpr double kEmbreeTarget = 1.0;
inline constexpr double kSpeedupTarget = 1.85;
// Packets (setting "packets"): grid1d's at least this many times its own single rays' speed
// and at least this fraction of Embree's packets' rays/s on primary and shadow rays; on
// diffuse bounces no more than this factor slower than single rays.
inline constexpr double kPacketGainTarget = 3.0;
inline constexpr double kPacketEmbreeTarget = 1.0;
inline constexpr double kPacketBounceSlowdown = 1.05;

// The packet measurements' columns in tables and plots, "<structure> packets", one per
// structure that traces packets, in report order.
const std::vector<std::string_view>& packet_columns();
// The structure of a packet column, or nullopt for any other name.
std::optional<std::string_view> packet_column_structure(std::string_view column);

// One measurement's identity. Setting "default" is the structure's paper or default
// parameters, "best" its best sweep point, "calibrated" grid1d with calibrated constants,
// "packets" the default parameters with primary and shadow rays traced by packets (every
// other setting traces one ray at a time).
struct RecordKey {
  std::string_view scene, accel, workload = "primary_shadow", setting = "default";
  int threads = 1;
};

// The first record with this identity, or nullptr.
const nlohmann::json* find_record(const nlohmann::json& records, const RecordKey& key);
// A numeric field, or nullopt when the record lacks it, it is null or it is not a number.
std::optional<double> record_number(const nlohmann::json& record, const char* key);
// A multi-thread record's speed-up over one thread: its "speedup" (each warm render paired with
// a 1-thread render of the same structure), else `one_thread`'s trace seconds over its own.
std::optional<double> record_speedup(const nlohmann::json* one_thread,
                                     const nlohmann::json& many_threads);
// True only when the field is the boolean true.
bool record_flag(const nlohmann::json& record, const char* key);
// A string field, or "" when absent or not a string.
std::string record_text(const nlohmann::json& record, const char* key);
// Scene labels in the order they first appear among the records.
std::vector<std::string> record_scenes(const nlohmann::json& records);

// report.md: header (machine, commit, seed, repetitions), the targets' verdicts, tables in
// the layout of the paper's Figure 12 (rows scenes, columns structures, time relative to the
// zero-overhead method), grid1d against Embree, build time and memory, agreement with the
// reference, calibration and a discussion generated from the numbers. `plots` are image
// file names (beside report.md) to show under "Plots".
std::string bench_report_markdown(const nlohmann::json& records,
                                  const std::vector<std::string>& plots = {});

}  // namespace gs
