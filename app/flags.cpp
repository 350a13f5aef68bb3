#include "app/flags.h"

#include <algorithm>
#include <charconv>

#include "core/accel/accelerator.h"
#include "core/accel/grid1d/cost_constants.h"
#include "core/accel/registry.h"
#include "core/base/error.h"
#include "core/base/parallel.h"
#include "core/render/render.h"

namespace gs::app {

namespace {

// A structure's default for `param` as its flag takes it, with its own cap for --max-depth
// ("" when it has none to show).
std::string default_text(const Structure& structure, Param param) {
  const ParamUse& use = *structure.use(param);
  const std::string text =
      use.default_text.empty() ? param_text(AccelParams{}, param_spec(param)) : use.default_text;
  const bool capped = param == Param::max_depth && structure.depth_cap < kMaxDepth;
  if (text.empty()) return "";
  return capped ? text + ", at most " + std::to_string(structure.depth_cap) : text;
}

// "Read by octree (default 6, at most 20), grid1d (default 32)." or, when they share it,
// "Read by uniform, grid1d (default 8G).": the structures that read every one of `params`
// and, for one parameter, their defaults.
std::string readers(std::span<const Param> params) {
  std::vector<std::string> names, defaults;
  for (const Structure& structure : structures())
    if (std::ranges::all_of(params, [&](Param p) { return structure.use(p) != nullptr; })) {
      names.push_back(structure.name);
      defaults.push_back(params.size() == 1 ? default_text(structure, params[0]) : "");
    }
  if (names.empty()) return "";
  const bool shared = std::ranges::count(defaults, defaults[0]) == long(defaults.size());
  std::string text;
  for (size_t i = 0; i < names.size(); ++i) {
    text += (i ? ", " : "Read by ") + names[i];
    if (!shared && !defaults[i].empty()) text += " (default " + defaults[i] + ")";
  }
  if (shared && !defaults[0].empty()) text += " (default " + defaults[0] + ")";
  return text + ".";
}

Flag param_flag(AccelParams& params, const ParamSpec& spec) {
  const std::string range = spec.kind == ParamKind::path ? "" : "; " + expected_value(spec);
  const Param param[] = {spec.param};
  return {std::string(spec.flag), std::string(spec.value_name),
          std::string(spec.help) + range + ". " + readers(param),
          [&params, &spec](const std::string& v) { set_param(params, spec, v); },
          spec.structure_flag};
}

Flag costs_flag(AccelParams& params) {
  return {
      "--costs", "FILE.json",
      "the five cost constants of a `calibrate --out` file; cost flags after it override "
      "them. " +
          readers(kCostParams),
      [&params](const std::string& v) { params = with_calibration(params, read_calibration(v)); },
      true};
}

// The parameters a structure flag sets: --costs the five cost constants, the others their
// own; none for any other flag.
std::vector<Param> params_set_by(const std::string& flag) {
  if (flag == "--costs") return {std::begin(kCostParams), std::end(kCostParams)};
  if (const ParamSpec* spec = find_param(flag)) return {spec->param};
  return {};
}

}  // namespace

std::optional<long long> to_integer(const std::string& text) {
  long long value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return value;
}

Words parse_words(const std::string& command, std::span<const std::string> words,
                  const Flags& flags) {
  Words parsed;
  for (size_t i = 0; i < words.size(); ++i) {
    const std::string& word = words[i];
    if (word.size() < 2 || word[0] != '-') {
      parsed.positionals.push_back(word);
      continue;
    }
    const size_t equals = word.find('=');
    const std::string name = word.substr(0, equals);
    const auto flag = std::ranges::find(flags, name, &Flag::name);
    if (flag == flags.end()) throw UsageError("unknown flag '" + name + "' for " + command);
    if (flag->value_name.empty()) {
      if (equals != std::string::npos) throw UsageError(name + " takes no value");
      flag->apply("");
    } else if (equals != std::string::npos) {
      flag->apply(word.substr(equals + 1));
    } else if (i + 1 < words.size()) {
      flag->apply(words[++i]);
    } else {
      throw UsageError(name + " needs a value");
    }
    parsed.flags.push_back(name);
  }
  return parsed;
}

void bad_value(const std::string& flag, const std::string& text, const std::string& expected) {
  throw UsageError(flag + " '" + text + "': expected " + expected);
}

int parse_int(const std::string& flag, const std::string& text, int lo, int hi) {
  const std::optional<long long> value = to_integer(text);
  if (!value || *value < lo || *value > hi)
    bad_value(flag, text, "an integer in " + std::to_string(lo) + ".." + std::to_string(hi));
  return int(*value);
}

Flag string_flag(std::string name, std::string value_name, std::string help, std::string& field) {
  return {std::move(name), std::move(value_name), std::move(help),
          [&field](const std::string& v) { field = v; }};
}

Flag switch_flag(std::string name, std::string help, bool& field) {
  return {std::move(name), "", std::move(help), [&field](const std::string&) { field = true; }};
}

Flag int_flag(std::string name, std::string help, int lo, int hi, int& field) {
  return {name, "N",
          std::move(help) + "; an integer in " + std::to_string(lo) + ".." + std::to_string(hi),
          [name, lo, hi, &field](const std::string& v) { field = parse_int(name, v, lo, hi); }};
}

Flag seed_flag(uint64_t& seed) {
  return {"--seed", "N",
          "the seed of the calibration's random scenes (default " + std::to_string(seed) +
              "); an integer in 0..2147483647",
          [&seed](const std::string& v) { seed = uint64_t(parse_int("--seed", v, 0, INT32_MAX)); }};
}

Flag size_flag(std::string name, std::string help, int& width, int& height) {
  const std::string sides = "each side 1.." + std::to_string(kMaxImageSide);
  if (width > 0) help += " (default " + std::to_string(width) + "x" + std::to_string(height) + ")";
  return {name, "WxH", help + "; " + sides,
          [name, sides, &width, &height](const std::string& text) {
            const size_t x = text.find('x');
            const auto side = [&](const std::string& part) {
              const std::optional<long long> value = to_integer(part);
              if (x == std::string::npos || !value || *value < 1 || *value > kMaxImageSide)
                bad_value(name, text, "WxH with " + sides);
              return int(*value);
            };
            const int w = side(text.substr(0, x));
            height = side(x == std::string::npos ? "" : text.substr(x + 1));
            width = w;
          }};
}

Flag camera_flag(std::optional<Camera>& camera) {
  return {"--camera", "STRING",
          "a pinhole camera, \"eye=X,Y,Z;target=X,Y,Z;up=X,Y,Z;fov=DEG\" (vertical field of view "
          "in degrees); default: one framing the scene",
          [&camera](const std::string& v) { camera = parse_camera(v); }};
}

Flag spp_flag(int& spp) {
  return int_flag("--spp",
                  "samples per pixel: 1 shoots through pixel centres, more are jittered, the same "
                  "every run (default " +
                      std::to_string(spp) + ")",
                  1, kMaxSpp, spp);
}

Flag bounces_flag(int& bounces) {
  return int_flag("--bounces",
                  "diffuse bounces per primary hit, each with its own shadow ray; 0 is the "
                  "paper's workload, a primary and a shadow ray per sample (default " +
                      std::to_string(bounces) + ")",
                  0, kMaxBounces, bounces);
}

Flag packets_flag(bool& packets) {
  return {"--packets", "on|off",
          "on: the primary rays of 8x8 pixel blocks, then their shadow rays, are walked together "
          "by a structure that can (grid1d, embree); same image (default on)",
          [&packets](const std::string& v) {
            if (v != "on" && v != "off") bad_value("--packets", v, "on or off");
            packets = v == "on";
          }};
}

Flag threads_flag(int& threads) {
  return int_flag("--threads", "tracing threads (default: all cores)", 1, kMaxThreads, threads);
}

Flag accel_flag(std::string& accel) {
  return string_flag("--accel", "NAME",
                     "the structure (default " + accel + "), one of those under \"Structures\"",
                     accel);
}

Flag overlay_flag(OverlaySelection& overlays) {
  return {"--overlay", "LIST",
          "comma-separated, grid1d's: cells, states, walk; depth:A-B (cells and states of levels "
          "A..B only, root 0), near-walk (only the voxels the walk crossed); and heat:steps, "
          "heat:tests or heat:built. Cells and states show at most " +
              std::to_string(kMaxOverlaySegments) +
              " lines each, shallow levels first (view's default: cells,walk,near-walk)",
          [&overlays](const std::string& v) { overlays = parse_overlays(v); }};
}

Flags structure_flags(AccelParams& params) {
  Flags flags;
  for (const ParamSpec& spec : param_table()) {
    if (!spec.structure_flag) continue;
    flags.push_back(param_flag(params, spec));
    // --costs sets the five cost constants together: listed after them.
    if (spec.param == std::end(kCostParams)[-1]) flags.push_back(costs_flag(params));
  }
  return flags;
}

Flag oracle_flag(AccelParams& params) { return param_flag(params, param_spec(Param::oracle)); }

void check_structure(const std::string& accel, const std::vector<std::string>& given,
                     const AccelParams& params) {
  const Structure& structure = structure_named(accel);
  if (!structure.takes_any_flag)
    for (const std::string& flag : given)
      for (const Param param : params_set_by(flag))
        if (!structure.use(param))
          throw UsageError(flag + ": structure '" + accel + "' does not use it");
  check_params(accel, params);
}

void apply_structure_flag(AccelParams& params, const std::string& flag, const std::string& value) {
  const Flags flags = structure_flags(params);
  const auto found = std::ranges::find(flags, flag, &Flag::name);
  if (found == flags.end()) throw UsageError("unknown structure flag '" + flag + "'");
  found->apply(value);
}

}  // namespace gs::app
