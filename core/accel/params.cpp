#include "core/accel/params.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>

#include "core/base/error.h"
#include "core/base/parallel.h"

namespace gs {
namespace {

using P = AccelParams;

constexpr ParamSpec cost(Param param, std::string_view flag, std::string_view key, double P::*field,
                         std::string_view help) {
  return {.param = param,
          .flag = flag,
          .key = key,
          .field = field,
          .kind = ParamKind::number,
          .value_name = "X",
          .help = help};
}

constexpr std::array<ParamSpec, 15> kTable = {{
    cost(Param::intcost, "--intcost", "intcost", &P::intcost,
         "Intcost (§6.2): the cost of one triangle of a cell a ray searches (its box test, "
         "and a ray/triangle test if the ray crosses its box)"),
    cost(Param::repcost, "--repcost", "repcost", &P::repcost,
         "Repcost: the cost of a repeat test the mailbox rejects"),
    cost(Param::travcost, "--travcost", "travcost", &P::travcost,
         "Travcost: the cost of one cell a ray crosses (passing it by, or stepping into it "
         "to search it)"),
    cost(Param::vertcost, "--vertcost", "vertcost", &P::vertcost,
         "Vertcost: the cost of setting a ray up in a subdivided voxel"),
    cost(Param::subcost, "--subcost", "subcost", &P::subcost,
         "Subcost: the cost of sorting one triangle into a voxel's cells"),
    {.param = Param::max_granularity,
     .flag = "--max-granularity",
     .key = "max_granularity",
     .field = &P::max_granularity,
     .kind = ParamKind::integer,
     .value_name = "N",
     .lo = 1,
     .hi = kMaxGranularity,
     .help = "most cells a voxel is cut into (the paper: 20)"},
    {.param = Param::max_root_granularity,
     .flag = "--max-root-granularity",
     .key = "max_root_granularity",
     .field = &P::max_root_granularity,
     .kind = ParamKind::integer,
     .value_name = "N",
     .lo = 1,
     .hi = kMaxGranularity,
     .help = "most cells the root (the scene box) is cut into; --max-granularity caps it too"},
    {.param = Param::axis,
     .flag = "--axis",
     .key = "axis",
     .field = &P::axis,
     .kind = ParamKind::choice,
     .value_name = "alternate|cost",
     .help = "cut the axes in turn (the paper) or choose each voxel's axis by cost"},
    {.param = Param::max_depth,
     .flag = "--max-depth",
     .key = "max_depth",
     .field = &P::max_depth,
     .kind = ParamKind::integer,
     .value_name = "N",
     .lo = 1,
     .hi = kMaxDepth,
     .zero_is_default = true,
     .help = "tree depth cap"},
    {.param = Param::leaf_size,
     .flag = "--leaf-size",
     .key = "leaf_size",
     .field = &P::leaf_size,
     .kind = ParamKind::integer,
     .value_name = "N",
     .lo = 1,
     .hi = kMaxLeafSize,
     .zero_is_default = true,
     .help = "triangles a node may hold before it is split"},
    {.param = Param::density,
     .flag = "--density",
     .key = "density",
     .field = &P::density,
     .kind = ParamKind::number,
     .value_name = "X",
     .lo_open = true,
     .zero_is_default = true,
     .help = "cells per triangle"},
    {.param = Param::memory_budget,
     .flag = "--memory-budget",
     .key = "memory_budget",
     .field = &P::memory_budget,
     .kind = ParamKind::bytes,
     .value_name = "BYTES",
     .hi = double(kMaxMemoryBudget),
     .help = "structure size cap; a voxel or node whose cut would exceed it stays a leaf"},
    {.param = Param::sample_every,
     .flag = "--sample-every",
     .key = "sample_every",
     .field = &P::sample_every,
     .kind = ParamKind::integer,
     .value_name = "N",
     .lo = 1,
     .hi = double(std::numeric_limits<int>::max()),
     .help = "the sampling pass (§6.5) traces one ray in N"},
    {.param = Param::build_threads,
     .flag = "--build-threads",
     .key = "build_threads",
     .field = &P::build_threads,
     .kind = ParamKind::integer,
     .value_name = "N",
     .lo = 0,
     .hi = kMaxThreads,
     .help = "threads the structure builds with (0: all cores); tracing threads are --threads"},
    {.param = Param::oracle,
     .flag = "--oracle",
     .key = "oracle",
     .field = &P::oracle_path,
     .kind = ParamKind::path,
     .value_name = "FILE.hits",
     .structure_flag = false,
     .help = "the hit file of an earlier run over the same rays, replayed"},
}};
// param_spec indexes the table by Param.
static_assert(std::ranges::all_of(kTable, [](const ParamSpec& spec) {
  return &spec - kTable.data() == ptrdiff_t(spec.param);
}));

std::string number_text(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

std::string integer_text(double value) { return std::to_string(static_cast<long long>(value)); }

// The words of a choice row: "alternate|cost" -> {"alternate", "cost"}.
std::vector<std::string_view> choices(const ParamSpec& spec) {
  std::vector<std::string_view> words;
  for (size_t start = 0;;) {
    const size_t bar = spec.value_name.find('|', start);
    words.push_back(spec.value_name.substr(start, bar - start));
    if (bar == std::string_view::npos) return words;
    start = bar + 1;
  }
}

// What a value must be, as the messages say it; `cap` as for check_param.
std::string expected(const ParamSpec& spec, int cap = 0, std::string_view structure = "") {
  switch (spec.kind) {
    case ParamKind::number:
      return std::string("a finite number ") + (spec.lo_open ? "> " : ">= ") + number_text(spec.lo);
    case ParamKind::integer:
      return "an integer in " + integer_text(spec.lo) + ".." +
             integer_text(cap > 0 ? cap : spec.hi) +
             (structure.empty() ? "" : " for " + std::string(structure));
    case ParamKind::bytes:
      return "at most " + byte_text(static_cast<uint64_t>(spec.hi)) +
             " (a byte count; suffix K, M or G allowed)";
    case ParamKind::choice: {
      std::string words;
      for (const std::string_view word : choices(spec))
        words += (words.empty() ? "" : " or ") + std::string(word);
      return words;
    }
    case ParamKind::path:
      break;
  }
  return "a path";
}

[[noreturn]] void malformed(const ParamSpec& spec, const std::string& text,
                            const std::string& expectation) {
  throw UsageError(std::string(spec.flag) + " '" + text + "': expected " + expectation);
}

bool in_range(const ParamSpec& spec, double value, double hi) {
  if (spec.kind == ParamKind::number)
    return std::isfinite(value) && (spec.lo_open ? value > spec.lo : value >= spec.lo);
  return value >= spec.lo && value <= hi;
}

// Every value out of range is worded the same, whether typed or set by a program.
void check_range(const ParamSpec& spec, double value, const std::string& value_text, int cap = 0,
                 std::string_view structure = "") {
  if (in_range(spec, value, cap > 0 ? cap : spec.hi)) return;
  throw UsageError(std::string(spec.flag) + " " + value_text + ": expected " +
                   expected(spec, cap, structure));
}

std::optional<long long> whole_integer(std::string_view text) {
  long long value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return value;
}

std::optional<double> whole_number(std::string_view text) {
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return value;
}

// BYTES with an optional binary suffix K, M or G.
std::optional<uint64_t> byte_count(const std::string& text) {
  constexpr std::string_view kSuffixes = "KMG";
  const size_t suffix = text.empty() ? std::string_view::npos : kSuffixes.find(text.back());
  const int shift = suffix == std::string_view::npos ? 0 : 10 * int(suffix + 1);
  const std::optional<long long> value =
      whole_integer(shift ? std::string_view(text).substr(0, text.size() - 1) : text);
  if (!value || *value < 0 || *value > std::numeric_limits<long long>::max() >> shift)
    return std::nullopt;
  return uint64_t(*value) << shift;
}

// The value of a numeric row as a double (for range checks and messages).
double numeric_value(const AccelParams& params, const ParamSpec& spec) {
  return std::visit(
      [&](auto field) -> double {
        using Value = std::remove_cvref_t<decltype(params.*field)>;
        if constexpr (std::is_arithmetic_v<Value>)
          return double(params.*field);
        else
          return 0.0;
      },
      spec.field);
}

}  // namespace

std::span<const ParamSpec> param_table() { return kTable; }

std::string expected_value(const ParamSpec& spec) { return expected(spec); }

const ParamSpec& param_spec(Param param) { return kTable[size_t(param)]; }

const ParamSpec* find_param(std::string_view flag) {
  const auto row = std::ranges::find(kTable, flag, &ParamSpec::flag);
  return row == kTable.end() ? nullptr : &*row;
}

void set_param(AccelParams& params, const ParamSpec& spec, const std::string& text) {
  switch (spec.kind) {
    case ParamKind::number: {
      const std::optional<double> value = whole_number(text);
      if (!value) malformed(spec, text, expected(spec));
      check_range(spec, *value, number_text(*value));
      params.*std::get<double P::*>(spec.field) = *value;
      return;
    }
    case ParamKind::integer: {
      const std::optional<long long> value = whole_integer(text);
      if (!value) malformed(spec, text, expected(spec));
      check_range(spec, double(*value), std::to_string(*value));
      params.*std::get<int P::*>(spec.field) = int(*value);
      return;
    }
    case ParamKind::bytes: {
      const std::optional<uint64_t> value = byte_count(text);
      if (!value)
        malformed(spec, text,
                  "a byte count with an optional suffix K, M or G, at most " +
                      byte_text(static_cast<uint64_t>(spec.hi)));
      check_range(spec, double(*value), byte_text(*value));
      params.*std::get<uint64_t P::*>(spec.field) = *value;
      return;
    }
    case ParamKind::choice: {
      const std::vector<std::string_view> words = choices(spec);
      const auto word = std::ranges::find(words, text);
      if (word == words.end()) malformed(spec, text, expected(spec));
      params.*std::get<AxisRule P::*>(spec.field) = AxisRule(word - words.begin());
      return;
    }
    case ParamKind::path:
      params.*std::get<std::string P::*>(spec.field) = text;
      return;
  }
}

void set_param(AccelParams& params, Param param, double value) {
  std::visit(
      [&](auto field) {
        using Value = std::remove_cvref_t<decltype(params.*field)>;
        if constexpr (std::is_arithmetic_v<Value>) params.*field = Value(value);
      },
      param_spec(param).field);
}

std::string param_text(const AccelParams& params, const ParamSpec& spec) {
  switch (spec.kind) {
    case ParamKind::bytes:
      return byte_text(params.*std::get<uint64_t P::*>(spec.field));
    case ParamKind::choice:
      return std::string(choices(spec)[size_t(params.*std::get<AxisRule P::*>(spec.field))]);
    case ParamKind::path:
      return params.*std::get<std::string P::*>(spec.field);
    case ParamKind::number:
      return number_text(numeric_value(params, spec));
    case ParamKind::integer:
      break;
  }
  return integer_text(numeric_value(params, spec));
}

void check_param(const AccelParams& params, const ParamSpec& spec, int cap,
                 std::string_view structure) {
  if (spec.kind == ParamKind::choice || spec.kind == ParamKind::path) return;
  const double value = numeric_value(params, spec);
  if (spec.zero_is_default && value == 0.0) return;
  check_range(spec, value, param_text(params, spec), cap, structure);
}

std::string byte_text(uint64_t bytes) {
  constexpr std::pair<int, const char*> kSuffixes[] = {{30, "G"}, {20, "M"}, {10, "K"}};
  for (const auto& [shift, suffix] : kSuffixes)
    if (bytes > 0 && bytes % (uint64_t{1} << shift) == 0)
      return std::to_string(bytes >> shift) + suffix;
  return std::to_string(bytes);
}

nlohmann::json AccelParams::to_json() const {
  nlohmann::json json = nlohmann::json::object();
  for (const ParamSpec& spec : kTable) {
    const std::string key(spec.key);
    if (spec.kind == ParamKind::choice)
      json[key] = param_text(*this, spec);
    else if (spec.kind == ParamKind::path)  // null when none was given
      json[key] = param_text(*this, spec).empty() ? nlohmann::json(nullptr)
                                                  : nlohmann::json(param_text(*this, spec));
    else
      std::visit([&](auto field) { json[key] = this->*field; }, spec.field);
  }
  return json;
}

}  // namespace gs
