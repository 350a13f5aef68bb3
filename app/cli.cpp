#include "app/cli.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <optional>
#include <vector>

#include "app/bench_job.h"
#include "app/shot.h"
#include "app/view/view.h"
#include "bench/calibrate.h"
#include "core/accel/grid1d/cost_constants.h"
#include "core/base/error.h"
#include "core/base/files.h"
#include "core/geometry/ray_io.h"
#include "core/render/render.h"
#include "core/scene/camera.h"
#include "core/scene/scene.h"
#include "core/trace/trace_job.h"

namespace gs::app {

namespace {

constexpr const char* kUsage = R"(usage: gridscope COMMAND ...

  gridscope trace  SCENE --rays FILE --out FILE [--accel NAME] [--threads N]
                   [--stats FILE.json] [--eager] [--occluded] [--repeat N]
                   [--walk I --walk-out FILE.json] [--sample-image WxH] [--oracle FILE.hits]
                   [STRUCTURE FLAGS]
  gridscope render SCENE --out FILE.png [--size WxH] [--camera STRING] [--spp N]
                   [--accel NAME] [--threads N] [--stats FILE.json] [STRUCTURE FLAGS]
  gridscope shot   SCENE --out FILE.png [--size WxH] [--camera STRING] [--spp N]
                   [--overlay LIST] [--pixel X,Y] [--ui] [--accel NAME] [STRUCTURE FLAGS]
  gridscope view   [SCENE] [--camera STRING] [--size WxH] [--frames N] [--click X,Y]
                   [--screenshot FILE.png] [--walk-out FILE.json] [--accel NAME]
                   [--script FILE] [--stats FILE.json] [STRUCTURE FLAGS]
  gridscope export SCENE --out FILE.obj
  gridscope rays   SCENE --out FILE.rays [--size WxH] [--camera STRING]
  gridscope bench  [--scenes LIST] [--accels LIST] [--out DIR] [--quick] [--seed N]
                   [--threads N] [--shared DIR] [--from results.json]
  gridscope calibrate [--out FILE.json] [--quick] [--seed N]
  gridscope help

SCENE is an .obj or .ply file (.gz too) or builtin:NAME (pyramid, lumpy, sphereflake).
--camera takes "eye=X,Y,Z;target=X,Y,Z;up=X,Y,Z;fov=DEG" (vertical fov in degrees).
Structure flags (the paper's cost constants and limits):
  --intcost --repcost --travcost --vertcost --subcost X   finite, >= 0
  --costs FILE.json (the five constants from `calibrate --out`)
  --max-granularity N (1..4096)   --axis alternate|cost   --max-depth N (1..64)
  --sample-every N (>= 1)         --memory-budget BYTES (suffix K, M or G allowed)
  --build-threads N (0 = all; embree's build)
--accel: brute, uniform, octree, grid3d, grid1d, bvh, embree (when built with Embree), zero
  (the paper's zero-overhead oracle, given --oracle FILE.hits from an earlier run).
shot draws the viewer's frame headless (OSMesa); --overlay takes any of
  cells, states, walk, heat:steps, heat:tests, heat:built (comma-separated);
  --pixel X,Y picks the walk's pixel (default: the image centre).
Exit status: 0 success, 1 bad input or failed run, 2 usage error.
view opens the explorer (default: builtin:lumpy, close-up); --frames N exits after N UI
  frames and the first full-resolution pass, --click X,Y (fractions of the viewport) picks
  a pixel's walk, --walk-out writes it, --screenshot saves the window, --script FILE runs
  lines "frame N: resize WxH|open SCENE|set NAME VALUE|close", --stats writes the last
  frame's figures on exit.
bench runs the paper's experiment (section 7) over a scene suite (pyramid, lumpy, dragon,
  bunny-sibenik, f15, dragon-full; --quick: pyramid and lumpy, smaller images) or --scenes
  (suite names, builtin:NAME or paths) and writes DIR/results.json, report.md and PNG plots;
  --from makes report.md and the plots again from a results.json without measuring.
calibrate measures the section 6.2 cost constants on this machine and prints them as flags.
)";

// A flag and what it does to the job being assembled; `apply` gets "" for a switch.
struct Flag {
  std::string name;
  bool takes_value;
  std::function<void(const std::string&)> apply;
};
using Flags = std::vector<Flag>;

[[noreturn]] void bad_value(const std::string& flag, const std::string& text,
                            const std::string& expected) {
  throw UsageError(flag + " '" + text + "': expected " + expected);
}

// The whole text as an integer, or nothing.
std::optional<long long> to_integer(const std::string& text) {
  long long value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return value;
}

int parse_int(const std::string& flag, const std::string& text, int lo, int hi) {
  const std::optional<long long> value = to_integer(text);
  if (!value || *value < lo || *value > hi)
    bad_value(flag, text, "an integer in " + std::to_string(lo) + ".." + std::to_string(hi));
  return int(*value);
}

double parse_cost(const std::string& flag, const std::string& text) {
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || !std::isfinite(value) ||
      value < 0.0)
    bad_value(flag, text, "a finite number >= 0");
  return value;
}

// BYTES with an optional binary suffix K, M or G.
uint64_t parse_bytes(const std::string& flag, const std::string& text) {
  const std::string suffixes = "KMG";
  const size_t suffix = text.empty() ? std::string::npos : suffixes.find(text.back());
  const int shift = suffix == std::string::npos ? 0 : 10 * int(suffix + 1);
  const std::optional<long long> value = to_integer(shift ? text.substr(0, text.size() - 1) : text);
  if (!value || *value < 0 || *value > std::numeric_limits<long long>::max() >> shift)
    bad_value(flag, text, "a byte count, optionally with suffix K, M or G");
  return uint64_t(*value) << shift;
}

// WxH, each side 1..kMaxImageSide.
void parse_size(const std::string& text, RenderSettings& settings,
                const std::string& flag = "--size") {
  const size_t x = text.find('x');
  const auto side = [&](const std::string& part) {
    const std::optional<long long> value = to_integer(part);
    if (x == std::string::npos || !value || *value < 1 || *value > kMaxImageSide)
      bad_value(flag, text, "WxH with each side 1.." + std::to_string(kMaxImageSide));
    return int(*value);
  };
  settings.width = side(text.substr(0, x));
  settings.height = side(x == std::string::npos ? "" : text.substr(x + 1));
}

AxisRule parse_axis(const std::string& text) {
  if (text == "alternate") return AxisRule::alternate;
  if (text == "cost") return AxisRule::cost;
  bad_value("--axis", text, "alternate or cost");
}

Flags structure_flags(AccelParams& p) {
  auto cost = [](const char* name, double& field) {
    return Flag{name, true, [name, &field](const std::string& v) { field = parse_cost(name, v); }};
  };
  return {
      cost("--intcost", p.intcost),
      cost("--repcost", p.repcost),
      cost("--travcost", p.travcost),
      cost("--vertcost", p.vertcost),
      cost("--subcost", p.subcost),
      // The five constants of a `calibrate --out` file; flags after it override them.
      {"--costs", true,
       [&p](const std::string& v) { p = with_calibration(p, read_calibration(v)); }},
      {"--max-granularity", true,
       [&p](const std::string& v) {
         p.max_granularity = parse_int("--max-granularity", v, 1, kMaxGranularity);
       }},
      {"--axis", true, [&p](const std::string& v) { p.axis = parse_axis(v); }},
      {"--max-depth", true,
       [&p](const std::string& v) { p.max_depth = parse_int("--max-depth", v, 1, kMaxDepth); }},
      {"--leaf-size", true,
       [&p](const std::string& v) { p.leaf_size = parse_int("--leaf-size", v, 1, kMaxLeafSize); }},
      {"--density", true,
       [&p](const std::string& v) {
         p.density = parse_cost("--density", v);
         if (p.density <= 0.0) bad_value("--density", v, "a number > 0");
       }},
      {"--sample-every", true,
       [&p](const std::string& v) {
         p.sample_every = parse_int("--sample-every", v, 1, std::numeric_limits<int>::max());
       }},
      {"--memory-budget", true,
       [&p](const std::string& v) { p.memory_budget = parse_bytes("--memory-budget", v); }},
      {"--build-threads", true,
       [&p](const std::string& v) {
         p.build_threads = parse_int("--build-threads", v, 0, kMaxThreads);
       }},
  };
}

Flag string_flag(const char* name, std::string& field) {
  return {name, true, [&field](const std::string& v) { field = v; }};
}

Flag threads_flag(int& threads) {
  return {"--threads", true, [&threads](const std::string& v) {
            threads = parse_int("--threads", v, 1, kMaxThreads);
          }};
}

// Applies the flags met in words (--name VALUE, --name=VALUE or a --switch, in any order)
// and returns the positional words. Any word starting with '-' is a flag, so a value that
// starts with '-' must follow its flag.
std::vector<std::string> parse_words(const std::string& command, std::span<const std::string> words,
                                     const Flags& flags) {
  std::vector<std::string> positionals;
  for (size_t i = 0; i < words.size(); ++i) {
    const std::string& word = words[i];
    if (word.size() < 2 || word[0] != '-') {
      positionals.push_back(word);
      continue;
    }
    const size_t equals = word.find('=');
    const std::string name = word.substr(0, equals);
    const auto flag =
        std::find_if(flags.begin(), flags.end(), [&](const Flag& f) { return f.name == name; });
    if (flag == flags.end()) throw UsageError("unknown flag '" + name + "' for " + command);
    if (!flag->takes_value) {
      if (equals != std::string::npos) throw UsageError(name + " takes no value");
      flag->apply("");
    } else if (equals != std::string::npos) {
      flag->apply(word.substr(equals + 1));
    } else if (i + 1 < words.size()) {
      flag->apply(words[++i]);
    } else {
      throw UsageError(name + " needs a value");
    }
  }
  return positionals;
}

// Exactly one positional, the scene.
std::string scene_argument(const std::string& command, const std::vector<std::string>& words) {
  if (words.size() != 1)
    throw UsageError(command + " takes one SCENE argument, got " + std::to_string(words.size()));
  return words[0];
}

void require(const std::string& command, const char* flag, const std::string& value) {
  if (value.empty()) throw UsageError(command + " needs " + flag);
}

Command parse_trace(std::span<const std::string> words) {
  TraceJob job;
  Flags flags = structure_flags(job.params);
  flags.insert(flags.end(),
               {string_flag("--rays", job.rays_path),
                string_flag("--out", job.out_path),
                string_flag("--accel", job.accel),
                string_flag("--stats", job.stats_path),
                threads_flag(job.threads),
                {"--eager", false, [&job](const std::string&) { job.eager = true; }},
                {"--occluded", false, [&job](const std::string&) { job.occluded = true; }},
                {"--repeat", true,
                 [&job](const std::string& v) { job.repeat = parse_int("--repeat", v, 1, 1000); }},
                {"--walk", true,
                 [&job](const std::string& v) {
                   job.walk_ray = parse_int("--walk", v, 0, std::numeric_limits<int>::max());
                 }},
                string_flag("--walk-out", job.walk_path),
                string_flag("--oracle", job.params.oracle_path),
                {"--sample-image", true, [&job](const std::string& v) {
                   RenderSettings size;
                   parse_size(v, size, "--sample-image");
                   job.sample_image_width = size.width, job.sample_image_height = size.height;
                 }}});
  job.scene = scene_argument("trace", parse_words("trace", words, flags));
  require("trace", "--rays FILE", job.rays_path);
  require("trace", "--out FILE", job.out_path);
  if ((job.walk_ray >= 0) != !job.walk_path.empty())
    throw UsageError("trace: --walk I and --walk-out FILE.json go together");
  return {[job] {
    run_trace(job);
    return 0;
  }};
}

Command parse_render(std::span<const std::string> words) {
  RenderJob job;
  Flags flags = structure_flags(job.params);
  flags.insert(flags.end(),
               {string_flag("--out", job.out_path),
                string_flag("--accel", job.accel),
                string_flag("--stats", job.stats_path),
                string_flag("--record-hits", job.hits_path),
                string_flag("--oracle", job.params.oracle_path),
                threads_flag(job.settings.threads),
                {"--bounces", true,
                 [&job](const std::string& v) {
                   job.settings.bounces = parse_int("--bounces", v, 0, kMaxBounces);
                 }},
                {"--size", true, [&job](const std::string& v) { parse_size(v, job.settings); }},
                {"--camera", true, [&job](const std::string& v) { job.camera = parse_camera(v); }},
                {"--spp", true, [&job](const std::string& v) {
                   job.settings.spp = parse_int("--spp", v, 1, kMaxSpp);
                 }}});
  job.scene = scene_argument("render", parse_words("render", words, flags));
  require("render", "--out FILE.png", job.out_path);
  return {[job] {
    run_render(job);
    std::printf("%s\n", job.out_path.c_str());
    return 0;
  }};
}

// X,Y: two integers; whether they lie inside the image is checked once the size is known.
std::array<int, 2> parse_pixel(const std::string& text) {
  const size_t comma = text.find(',');
  const auto part = [&](const std::string& word) {
    const std::optional<long long> value = to_integer(word);
    if (comma == std::string::npos || !value || *value < 0 || *value >= kMaxImageSide)
      bad_value("--pixel", text, "X,Y, the column and row of a pixel of the image");
    return int(*value);
  };
  return {part(text.substr(0, comma)),
          part(comma == std::string::npos ? "" : text.substr(comma + 1))};
}

Command parse_shot(std::span<const std::string> words) {
  ShotJob job;
  Flags flags = structure_flags(job.params);
  flags.insert(
      flags.end(),
      {string_flag("--out", job.out_path),
       string_flag("--accel", job.accel),
       {"--size", true, [&job](const std::string& v) { parse_size(v, job.settings); }},
       {"--camera", true, [&job](const std::string& v) { job.camera = parse_camera(v); }},
       {"--spp", true,
        [&job](const std::string& v) { job.settings.spp = parse_int("--spp", v, 1, kMaxSpp); }},
       {"--bounces", true,
        [&job](const std::string& v) {
          job.settings.bounces = parse_int("--bounces", v, 0, kMaxBounces);
        }},
       {"--overlay", true, [&job](const std::string& v) { job.overlays = parse_overlays(v); }},
       {"--pixel", true, [&job](const std::string& v) { job.pixel = parse_pixel(v); }},
       {"--ui", false, [&job](const std::string&) { job.ui = true; }}});
  job.scene = scene_argument("shot", parse_words("shot", words, flags));
  require("shot", "--out FILE.png", job.out_path);
  return {[job] {
    run_shot(job);
    std::printf("%s\n", job.out_path.c_str());
    return 0;
  }};
}

Command parse_view(std::span<const std::string> words) {
  ViewJob job;
  RenderSettings size;
  size.width = job.width, size.height = job.height;
  Flags flags = structure_flags(job.params);
  flags.insert(
      flags.end(),
      {string_flag("--accel", job.accel),
       string_flag("--screenshot", job.screenshot),
       string_flag("--walk-out", job.walk_out),
       string_flag("--script", job.script),
       string_flag("--stats", job.stats),
       {"--size", true, [&size](const std::string& v) { parse_size(v, size); }},
       {"--camera", true, [&job](const std::string& v) { job.camera = parse_camera(v); }},
       {"--frames", true,
        [&job](const std::string& v) { job.frames = parse_int("--frames", v, 1, 1000000); }},
       {"--click", true, [&job](const std::string& v) { job.click = parse_click(v); }},
       {"--overlay", true, [&job](const std::string& v) { job.overlays = parse_overlays(v); }}});
  const std::vector<std::string> positionals = parse_words("view", words, flags);
  if (positionals.size() > 1)
    throw UsageError("view takes at most one SCENE argument, got " +
                     std::to_string(positionals.size()));
  if (!positionals.empty()) job.scene = positionals[0];
  job.width = size.width, job.height = size.height;
  return {[job] {
    run_view(job);
    return 0;
  }};
}

Command parse_export(std::span<const std::string> words) {
  std::string out;
  const Flags flags = {string_flag("--out", out)};
  const std::string scene = scene_argument("export", parse_words("export", words, flags));
  require("export", "--out FILE.obj", out);
  return {[scene, out] {
    export_obj(load_scene(scene), out);
    return 0;
  }};
}

// The primary rays `render --spp 1` shoots (pixel centres, rows from the top-left pixel),
// as a ray file for `trace`: so a trace can be checked against, or timed like, a render.
Command parse_rays(std::span<const std::string> words) {
  std::string out;
  RenderSettings settings;
  std::optional<Camera> camera;
  const Flags flags = {
      string_flag("--out", out),
      {"--size", true, [&settings](const std::string& v) { parse_size(v, settings); }},
      {"--camera", true, [&camera](const std::string& v) { camera = parse_camera(v); }}};
  const std::string scene = scene_argument("rays", parse_words("rays", words, flags));
  require("rays", "--out FILE.rays", out);
  return {[scene, out, settings, camera] {
    const Box box = load_scene(scene).bounds();
    const Camera view = camera ? *camera : frame_box(box, float(settings.width) / settings.height);
    std::vector<Ray> rays;
    rays.reserve(size_t(settings.width) * size_t(settings.height));
    for (int y = 0; y < settings.height; ++y)
      for (int x = 0; x < settings.width; ++x)
        rays.push_back(view.primary_ray(x, y, settings.width, settings.height));
    write_rays(out, rays);
    return 0;
  }};
}

// A comma-separated list of non-empty words.
std::vector<std::string> parse_list(const std::string& flag, const std::string& text) {
  std::vector<std::string> words;
  size_t start = 0;
  while (true) {
    const size_t comma = text.find(',', start);
    words.push_back(text.substr(start, comma - start));
    if (words.back().empty()) bad_value(flag, text, "a comma-separated list of names");
    if (comma == std::string::npos) return words;
    start = comma + 1;
  }
}

void no_positionals(const std::string& command, const std::vector<std::string>& positionals) {
  if (!positionals.empty())
    throw UsageError(command + " takes no SCENE argument (got '" + positionals[0] + "')");
}

Command parse_bench(std::span<const std::string> words) {
  BenchJob job;
  BenchOptions& options = job.options;
  const Flags flags = {
      {"--scenes", true, [&](const std::string& v) { options.scenes = parse_list("--scenes", v); }},
      {"--accels", true, [&](const std::string& v) { options.accels = parse_list("--accels", v); }},
      string_flag("--out", job.out_dir),
      string_flag("--shared", options.shared_dir),
      string_flag("--from", job.from_path),
      {"--quick", false, [&](const std::string&) { options.quick = true; }},
      {"--seed", true,
       [&](const std::string& v) {
         options.seed = uint64_t(parse_int("--seed", v, 0, INT32_MAX));
       }},
      {"--threads", true,
       [&](const std::string& v) { options.threads = parse_int("--threads", v, 1, kMaxThreads); }}};
  no_positionals("bench", parse_words("bench", words, flags));
  check_bench_options(options);
  return {[job] {
    run_bench_job(job);
    return 0;
  }};
}

// Prints the calibration (and writes it with --out) with the flags that apply it.
Command parse_calibrate(std::span<const std::string> words) {
  std::string out;
  CalibrateOptions options;
  const Flags flags = {
      string_flag("--out", out),
      {"--quick", false,
       [&](const std::string&) { options.budget_seconds = CalibrateOptions::kQuickBudget; }},
      {"--seed", true, [&](const std::string& v) {
         options.seed = uint64_t(parse_int("--seed", v, 0, INT32_MAX));
       }}};
  no_positionals("calibrate", parse_words("calibrate", words, flags));
  return {[out, options] {
    const Calibration calibration = calibrate(options);
    if (!out.empty()) write_json(out, to_json(calibration));
    std::printf("--intcost %.6g --repcost %.6g --travcost %.6g --vertcost %.6g --subcost %.6g\n",
                calibration.intcost, calibration.repcost, calibration.travcost,
                calibration.vertcost, calibration.subcost);
    return 0;
  }};
}

bool asks_for_help(std::span<const std::string> args) {
  return args[0] == "help" || args[0] == "-h" ||
         std::find(args.begin(), args.end(), "--help") != args.end();
}

}  // namespace

Command parse_cli(std::span<const std::string> args) {
  if (args.empty()) throw UsageError("no command given (try 'gridscope help')");
  if (asks_for_help(args)) {
    return {[] {
      std::fputs(kUsage, stdout);
      return 0;
    }};
  }
  const std::string& command = args[0];
  const auto rest = args.subspan(1);
  if (command == "trace") return parse_trace(rest);
  if (command == "render") return parse_render(rest);
  if (command == "shot") return parse_shot(rest);
  if (command == "export") return parse_export(rest);
  if (command == "rays") return parse_rays(rest);
  if (command == "view") return parse_view(rest);
  if (command == "bench") return parse_bench(rest);
  if (command == "calibrate") return parse_calibrate(rest);
  throw UsageError("unknown command '" + command + "'");
}

int run_cli(std::span<const std::string> args) { return parse_cli(args).run(); }

void apply_structure_flag(AccelParams& params, const std::string& flag, const std::string& value) {
  const Flags flags = structure_flags(params);
  const auto found =
      std::find_if(flags.begin(), flags.end(), [&](const Flag& f) { return f.name == flag; });
  if (found == flags.end()) throw UsageError("unknown structure flag '" + flag + "'");
  found->apply(value);
}

}  // namespace gs::app
