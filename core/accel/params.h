// Every structure parameter (AccelParams) and the table that describes each one once: its
// flag, its field, the kind of value it takes, its range and its help line. The command line
// parses and range-checks from this table, check_params (accelerator.h) checks with the same
// ranges whoever set the values, and AccelParams::to_json and the help text are generated from
// it. Which structures read a parameter, and each one's default, are in the registry
// (registry.h).
#pragma once
#include <cstdint>
#include <nlohmann/json_fwd.hpp>
#include <span>
#include <string>
#include <string_view>
#include <variant>

namespace gs {

enum class AxisRule { alternate, cost };

// Parameter ranges (README "Limits"). Granularity times depth cannot explode: grid1d caps
// each axis's absolute granularity (the product of the g's above a voxel) at 2^50, the octree's
// depth at 20 (2^20 finest cells per side) and grid3d's at 16 (the registry holds each
// structure's cap), and every structure's memory is bounded by memory_budget.
inline constexpr int kMaxGranularity = 4096;  // cells one voxel is cut into
inline constexpr int kMaxDepth = 64;          // tree depth; a structure's own cap may be lower
inline constexpr int kMaxLeafSize = 1 << 20;
// Lazy structures reserve (never commit) address space for several arrays of up to the
// budget each; 1 TiB keeps that within the 128 TiB of an x86-64 process.
inline constexpr uint64_t kMaxMemoryBudget = uint64_t{1} << 40;

// Every structure parameter, named after the paper (§6.2) where the paper names it.
// Each run echoes these into its stats.
struct AccelParams {
  // Section 6.2 code timings, relative units: `gridscope calibrate` on the development
  // machine (AVX-512 kernel; README "Calibration" gives the runs) measured, in units of a
  // searched leaf's triangle (0.6-1.0 ns: its box test, and a real test for the 14% of them
  // whose box real rays cross), repcost 0.85-1.8, travcost 24-25 (a cell crossed: passed by,
  // or for the 30% of them real rays search, stepped into), vertcost 21-40, subcost 37-80:
  // the defaults are the medians of three runs.
  double intcost = 1.0;    // one triangle of a cell the ray searches
  double repcost = 1.75;   // a mailbox-rejected repeat
  double travcost = 25.0;  // a cell the walk crosses
  double vertcost = 33.0;  // initialising a ray in a subdivided voxel
  double subcost = 60.0;   // sorting one triangle into a voxel's cells
  int max_granularity = 20;
  // The root's own cap, below max_granularity. The paper caps g "to encourage recursive
  // subdivision at higher levels of the tree, where scene distribution is unlikely to be
  // uniform" (§6.5); the root, which holds the whole scene, is where that holds most, and
  // where the test term (N k / g tests for cells that will be cut again) overprices its cells
  // most. 10 measured best over the twelve callgrind sets (README "Performance").
  int max_root_granularity = 10;
  AxisRule axis = AxisRule::alternate;
  // Each structure's own limits; 0 means the structure's default (the registry lists them).
  int max_depth = 0;     // tree depth cap
  int leaf_size = 0;     // triangles a node may hold before it is split (octree, grid3d, bvh)
  double density = 0.0;  // uniform grid: cells per triangle (0: the paper's cbrt(N) per side)
  uint64_t memory_budget = uint64_t{8} << 30;  // bytes of structure, reserved not committed
  // Sampling pass (§6.5): one sample ray per this many rays of the run.
  int sample_every = 64;
  // embree: threads its device builds with (0: all cores). Tracing threads are --threads.
  int build_threads = 0;
  // zero: the hit file of an earlier run over the same rays (required by "zero").
  std::string oracle_path;

  nlohmann::json to_json() const;
  int depth_or(int fallback) const { return max_depth > 0 ? max_depth : fallback; }
  int leaf_size_or(int fallback) const { return leaf_size > 0 ? leaf_size : fallback; }
};

// One row of the table per AccelParams field.
enum class Param {
  intcost,
  repcost,
  travcost,
  vertcost,
  subcost,
  max_granularity,
  max_root_granularity,
  axis,
  max_depth,
  leaf_size,
  density,
  memory_budget,
  sample_every,
  build_threads,
  oracle,
};

// The five §6.2 constants, which `--costs FILE.json` sets together.
inline constexpr Param kCostParams[] = {Param::intcost, Param::repcost, Param::travcost,
                                        Param::vertcost, Param::subcost};

enum class ParamKind {
  number,   // a finite real number (the cost constants, the density)
  integer,  // a whole number in lo..hi
  bytes,    // a byte count with an optional binary suffix K, M or G, at most hi
  choice,   // one of the words of value_name, "alternate|cost": the enum's values in order
  path,     // a file
};

using ParamField = std::variant<double AccelParams::*, int AccelParams::*, uint64_t AccelParams::*,
                                AxisRule AccelParams::*, std::string AccelParams::*>;

struct ParamSpec {
  Param param;
  std::string_view flag;  // "--max-depth"
  // Its name in AccelParams::to_json, in stats files and in the bench's sweep records.
  std::string_view key;
  ParamField field;
  ParamKind kind;
  std::string_view value_name;  // "N", "X", "BYTES", "FILE.hits"; choice: the words
  // The range: number lo (exclusive when lo_open) and no upper bound; integer and bytes lo..hi.
  double lo = 0.0, hi = 0.0;
  bool lo_open = false;
  // 0, AccelParams' value, stands for each structure's own default: it is never given, and
  // check_params lets it through.
  bool zero_is_default = false;
  // Taken with the other structure flags by trace, render, shot and view. False for
  // --oracle, which only trace and render take: only their rays have the keys a hit file
  // holds answers for.
  bool structure_flag = true;
  std::string_view help;  // one line
};

std::span<const ParamSpec> param_table();
const ParamSpec& param_spec(Param param);
// The row for flag "--NAME", or nullptr.
const ParamSpec* find_param(std::string_view flag);

// Parses `text` as the flag takes it and stores it. Throws UsageError "FLAG 'TEXT': expected
// ..." for malformed text and "FLAG VALUE: expected ..." for a value out of range.
void set_param(AccelParams& params, const ParamSpec& spec, const std::string& text);
// Stores a number set by a program, not typed (the bench's sweep points); not range-checked
// here (check_params does).
void set_param(AccelParams& params, Param param, double value);
// The value as its flag takes it: "0.2", "8G", "alternate".
std::string param_text(const AccelParams& params, const ParamSpec& spec);

// Throws UsageError "FLAG VALUE: expected RANGE" unless the value is in the row's range (or is
// the 0 of zero_is_default). For an integer, `cap` (when > 0) lowers the upper bound to a
// structure's own, named in the message as " for STRUCTURE".
void check_param(const AccelParams& params, const ParamSpec& spec, int cap = 0,
                 std::string_view structure = "");

// What a value of the row must be, as messages say it: "an integer in 1..4096", "a finite
// number >= 0", "alternate or cost".
std::string expected_value(const ParamSpec& spec);

// BYTES as --memory-budget prints and reads them: the largest suffix K, M or G that divides
// them exactly ("8G", "1536M", "100").
std::string byte_text(uint64_t bytes);

}  // namespace gs
