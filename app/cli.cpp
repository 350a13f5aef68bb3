#include "app/cli.h"

#include <algorithm>
#include <array>
#include <cstdio>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>

#include "app/bench_job.h"
#include "app/compare_spec.h"
#include "app/flags.h"
#include "app/shot.h"
#include "app/version.h"
#include "app/view/view.h"
#include "bench/bench.h"
#include "bench/calibrate.h"
#include "bench/scenes.h"
#include "core/accel/registry.h"
#include "core/base/error.h"
#include "core/base/files.h"
#include "core/geometry/ray_io.h"
#include "core/render/render.h"
#include "core/scene/camera.h"
#include "core/scene/scene.h"
#include "core/trace/trace_job.h"

namespace gs::app {

namespace {

// A command line being parsed: flags bound to the job being assembled, and what makes the run
// from the rest once every flag is applied (positionals, and checks no single flag can make).
struct Parser {
  Flags flags;
  std::function<Command(const Words&)> finish;
};

struct CommandSpec {
  std::string_view name;
  std::string_view synopsis;  // after "gridscope NAME"
  std::string_view about;     // one paragraph
  Parser (*parser)();         // a fresh job's parser
};

// ---- What the commands share ------------------------------------------------------------

void append(Flags& flags, Flags more) {
  flags.insert(flags.end(), std::make_move_iterator(more.begin()),
               std::make_move_iterator(more.end()));
}

// Exactly one positional, the scene.
std::string scene_argument(const std::string& command, const std::vector<std::string>& words) {
  if (words.size() != 1)
    throw UsageError(command + " takes one SCENE argument, got " + std::to_string(words.size()));
  return words[0];
}

void no_positionals(const std::string& command, const std::vector<std::string>& positionals) {
  if (!positionals.empty())
    throw UsageError(command + " takes no SCENE argument (got '" + positionals[0] + "')");
}

void require(const std::string& command, const char* flag, const std::string& value) {
  if (value.empty()) throw UsageError(command + " needs " + flag);
}

// A command that writes one image of a scene (render, shot): checks its scene, --out and
// structure flags, then runs `run` on a copy of the job and prints the image's path.
template <class Job, class Run>
Command image_command(const char* command, Job& job, const Words& words, Run run) {
  job.scene = scene_argument(command, words.positionals);
  require(command, "--out FILE.png", job.out_path);
  check_structure(job.accel, words.flags, job.params);
  return Command{[job, run] {
    run(job);
    std::printf("%s\n", job.out_path.c_str());
    return 0;
  }};
}

Command print(std::string text) {
  return {[text] {
    std::fputs(text.c_str(), stdout);
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

std::string joined(const std::vector<std::string>& words) {
  std::string text;
  for (const std::string& word : words) text += (text.empty() ? "" : ", ") + word;
  return text;
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

// ---- The commands -------------------------------------------------------------------------

Parser trace_parser() {
  auto job = std::make_shared<TraceJob>();
  Flags flags = {
      string_flag("--rays", "FILE", "the ray file to trace", job->rays_path),
      string_flag("--out", "FILE", "the hit file to write", job->out_path),
      accel_flag(job->accel),
      threads_flag(job->threads),
      string_flag("--stats", "FILE.json",
                  "writes the run's record: parameters, times, structure figures, counters",
                  job->stats_path),
      switch_flag("--eager", "builds the whole structure before tracing instead of lazily",
                  job->eager),
      switch_flag("--occluded", "answers any blocking triangle instead of the nearest",
                  job->occluded),
      int_flag("--repeat",
               "traces the rays N times: the first pass builds lazily and gives the counters, "
               "the median of the others is reported as warm",
               1, 1000, job->repeat),
      int_flag("--packets",
               "traces N rays at a time, walked together by a structure that can (grid1d): N "
               "consecutive rays, or with --sample-image tiles of N pixels (N a square)",
               2, int(Accelerator::kMaxPacketRays), job->packets),
      {"--walk", "I",
       "re-traces ray I after the run with the traversal's recorder (grid1d; needs --walk-out)",
       [&walk_ray = job->walk_ray](const std::string& v) {
         walk_ray = parse_int("--walk", v, 0, std::numeric_limits<int>::max());
       }},
      string_flag("--walk-out", "FILE.json", "where --walk writes the ray's walk, cell by cell",
                  job->walk_path),
      size_flag("--sample-image",
                "the rays are a WxH image's primary rays (as `rays` writes them): the sampling "
                "pass takes the image's pixels as render does",
                job->sample_image_width, job->sample_image_height),
      {"--camera", "STRING",
       "with --sample-image: the camera the rays were made with (`rays --camera`); the sampling "
       "pass then also samples the shadow rays of the sample pixels' hits, as render does",
       [&camera = job->sample_camera](const std::string& v) { camera = parse_camera(v); }},
      oracle_flag(job->params),
  };
  append(flags, structure_flags(job->params));
  return {std::move(flags), [job](const Words& words) {
            job->scene = scene_argument("trace", words.positionals);
            require("trace", "--rays FILE", job->rays_path);
            require("trace", "--out FILE", job->out_path);
            if ((job->walk_ray >= 0) != !job->walk_path.empty())
              throw UsageError("trace: --walk I and --walk-out FILE.json go together");
            if (job->sample_camera && job->sample_image_width == 0)
              throw UsageError("trace: --camera is the camera of --sample-image's image");
            check_structure(job->accel, words.flags, job->params);
            return Command{[job = *job] {
              run_trace(job);
              return 0;
            }};
          }};
}

Parser render_parser() {
  auto job = std::make_shared<RenderJob>();
  Flags flags = {
      string_flag("--out", "FILE.png", "the image to write", job->out_path),
      size_flag("--size", "the image size", job->settings.width, job->settings.height),
      camera_flag(job->camera),
      spp_flag(job->settings.spp),
      bounces_flag(job->settings.bounces),
      packets_flag(job->settings.packets),
      accel_flag(job->accel),
      threads_flag(job->settings.threads),
      string_flag("--stats", "FILE.json", "writes trace's record, rays counting every ray cast",
                  job->stats_path),
      string_flag("--record-hits", "FILE.hits",
                  "writes every ray key's answer, for --accel zero --oracle to replay",
                  job->hits_path),
      oracle_flag(job->params),
  };
  append(flags, structure_flags(job->params));
  return {std::move(flags), [job](const Words& words) {
            return image_command("render", *job, words, [](const RenderJob& j) { run_render(j); });
          }};
}

Parser shot_parser() {
  auto job = std::make_shared<ShotJob>();
  Flags flags = {
      string_flag("--out", "FILE.png", "the frame to write", job->out_path),
      size_flag("--size", "the image size", job->settings.width, job->settings.height),
      camera_flag(job->camera),
      spp_flag(job->settings.spp),
      bounces_flag(job->settings.bounces),
      packets_flag(job->settings.packets),
      overlay_flag(job->overlays),
      {"--pixel", "X,Y", "the pixel whose walk the walk overlay shows (default: the centre)",
       [&pixel = job->pixel](const std::string& v) { pixel = parse_pixel(v); }},
      switch_flag("--ui", "draws the viewer's statistics panel over the frame", job->ui),
      {"--compare", "SPEC",
       "A/B: draws side B, this command line changed by SPEC (NAME=VALUE words: accel=NAME, "
       "packets=on|off or a structure flag without its dashes, e.g. \"accel=bvh\" or "
       "\"max-granularity=8\"), to the right of A with the same camera; with a heatmap both "
       "share one scale and B - A follows as a third frame; prints the totals side by side",
       [&compare = job->compare](const std::string& v) { compare = parse_compare(v); }},
      accel_flag(job->accel),
  };
  append(flags, structure_flags(job->params));
  return {std::move(flags),
          [job](const Words& words) { return image_command("shot", *job, words, run_shot); }};
}

Parser view_parser() {
  auto job = std::make_shared<ViewJob>();
  Flags flags = {
      camera_flag(job->camera),
      size_flag("--size", "the window size", job->width, job->height),
      accel_flag(job->accel),
      packets_flag(job->packets),
      overlay_flag(job->overlays),
      int_flag("--max-spp", "stops refining the view at N samples per pixel (default 256)", 1,
               kMaxSpp, job->max_spp),
      int_flag("--frames", "draws at least N frames and the first full-resolution pass, then exits",
               1, 1000000, job->frames),
      {"--click", "X,Y",
       "clicks that point of the viewport (fractions 0..1) once that pass is done",
       [&click = job->click](const std::string& v) { click = parse_click(v); }},
      string_flag("--walk-out", "FILE.json", "writes the clicked pixel's walk (needs --click)",
                  job->walk_out),
      string_flag("--screenshot", "FILE.png", "saves the window just before exiting",
                  job->screenshot),
      string_flag(
          "--script", "FILE",
          "runs lines \"frame N: resize WxH|open SCENE|set NAME VALUE|orbit DEG|wait|close\" "
          "(NAME: accel, packets, overlay (VALUE as --overlay takes it), a structure flag, "
          "compare or compare-view)",
          job->script),
      string_flag("--stats", "FILE.json", "writes the last frame's figures on exit", job->stats),
      {"--compare", "SPEC",
       "A/B: renders B, this view changed by SPEC (as shot --compare takes it), in a split "
       "viewport beside A",
       [&compare = job->compare](const std::string& v) {
         parse_compare(v);
         compare = v;
       }},
  };
  append(flags, structure_flags(job->params));
  return {std::move(flags), [job](const Words& words) {
            if (words.positionals.size() > 1)
              throw UsageError("view takes at most one SCENE argument, got " +
                               std::to_string(words.positionals.size()));
            if (!words.positionals.empty()) job->scene = words.positionals[0];
            check_structure(job->accel, words.flags, job->params);
            if (!job->compare.empty())  // B's flags must suit B's structure: usage, exit 2
              side_b(parse_compare(job->compare), job->accel, job->params);
            return Command{[job = *job] {
              run_view(job);
              return 0;
            }};
          }};
}

// `export suite:NAME`: a bench scene as the bench composes it (a mesh placed in another, a
// ground added), and on stdout the bench's camera and light, so that rays, trace and view can
// look at what the bench measured. One line per figure: "camera STRING", "light X,Y,Z".
void export_suite_scene(const std::string& name, const std::string& out) {
  const std::vector<std::string> suite = bench_suite(false);
  if (std::find(suite.begin(), suite.end(), name) == suite.end())
    throw InputError("suite:" + name + ": not a bench scene (" + joined(suite) + ")");
  std::string skipped;
  const std::optional<BenchScene> bench = load_bench_scene(name, find_assets_dir(), skipped);
  if (!bench) throw InputError(skipped);
  export_obj(*bench->scene, out);
  if (bench->camera) std::printf("camera %s\n", to_string(*bench->camera).c_str());
  if (bench->light)
    std::printf("light %.9g,%.9g,%.9g\n", bench->light->x, bench->light->y, bench->light->z);
}

Parser export_parser() {
  auto out = std::make_shared<std::string>();
  return {{string_flag("--out", "FILE.obj", "the OBJ file to write", *out)},
          [out](const Words& words) {
            const std::string scene = scene_argument("export", words.positionals);
            require("export", "--out FILE.obj", *out);
            return Command{[scene, out = *out] {
              constexpr std::string_view kSuite = "suite:";
              if (scene.rfind(kSuite, 0) == 0)
                export_suite_scene(scene.substr(kSuite.size()), out);
              else
                export_obj(load_scene(scene), out);
              return 0;
            }};
          }};
}

// The primary rays `render --spp 1` shoots (pixel centres, rows from the top-left pixel),
// as a ray file for `trace`: so a trace can be checked against, or timed like, a render.
Parser rays_parser() {
  struct Job {
    std::string out;
    RenderSettings settings;
    std::optional<Camera> camera;
  };
  auto job = std::make_shared<Job>();
  Flags flags = {
      string_flag("--out", "FILE.rays", "the ray file to write", job->out),
      size_flag("--size", "the image size", job->settings.width, job->settings.height),
      camera_flag(job->camera),
  };
  return {std::move(flags), [job](const Words& words) {
            const std::string scene = scene_argument("rays", words.positionals);
            require("rays", "--out FILE.rays", job->out);
            return Command{[scene, job = *job] {
              const Box box = load_scene(scene).bounds();
              const RenderSettings& size = job.settings;
              const Camera view =
                  job.camera ? *job.camera : frame_box(box, float(size.width) / size.height);
              std::vector<Ray> rays;
              rays.reserve(size_t(size.width) * size_t(size.height));
              const PrimaryRays primary_ray(view, size.width, size.height);
              for (int y = 0; y < size.height; ++y)
                for (int x = 0; x < size.width; ++x) rays.push_back(primary_ray(x, y));
              write_rays(job.out, rays);
              return 0;
            }};
          }};
}

Parser bench_parser() {
  auto job = std::make_shared<BenchJob>();
  BenchOptions& options = job->options;
  Flags flags = {
      {"--scenes", "LIST",
       "comma-separated suite names (" + joined(bench_suite(false)) +
           "), builtin:NAME or paths (default: the suite; --quick: " + joined(bench_suite(true)) +
           ")",
       [&options](const std::string& v) { options.scenes = parse_list("--scenes", v); }},
      {"--accels", "LIST",
       "comma-separated structures to measure (default: all of " + joined(bench_structures()) +
           " this build has)",
       [&options](const std::string& v) { options.accels = parse_list("--accels", v); }},
      string_flag("--out", "DIR",
                  "where results.json, report.md and the plots go (default " + job->out_dir + ")",
                  job->out_dir),
      string_flag("--assets", "DIR",
                  "the folder holding the suite's scene files (default: found beside the source "
                  "tree)",
                  options.assets_dir),
      string_flag("--from", "results.json",
                  "makes report.md and the plots again from a results.json, measuring nothing",
                  job->from_path),
      switch_flag("--quick", "built-in scenes only, smaller images, fewer repetitions",
                  options.quick),
      switch_flag("--verbose",
                  "a line per step (each measurement's figures) instead of one progress line "
                  "with the time left",
                  job->verbose),
      seed_flag(options.seed),
      threads_flag(options.threads),
  };
  return {std::move(flags), [job](const Words& words) {
            no_positionals("bench", words.positionals);
            check_bench_options(job->options);
            return Command{[job = *job] {
              run_bench_job(job);
              return 0;
            }};
          }};
}

// Prints the calibration (and writes it with --out) with the flags that apply it.
Parser calibrate_parser() {
  struct Job {
    std::string out;
    bool quick = false;
    CalibrateOptions options;
  };
  auto job = std::make_shared<Job>();
  Flags flags = {
      string_flag("--out", "FILE.json", "also writes the calibration, for --costs", job->out),
      switch_flag("--quick", "a shorter timing budget", job->quick),
      seed_flag(job->options.seed),
  };
  return {std::move(flags), [job](const Words& words) {
            no_positionals("calibrate", words.positionals);
            if (job->quick) job->options.budget_seconds = CalibrateOptions::kQuickBudget;
            return Command{[job = *job] {
              const Calibration calibration = calibrate(job.options);
              if (!job.out.empty()) write_json(job.out, to_json(calibration));
              std::printf(
                  "--intcost %.6g --repcost %.6g --travcost %.6g --vertcost %.6g --subcost %.6g\n",
                  calibration.intcost, calibration.repcost, calibration.travcost,
                  calibration.vertcost, calibration.subcost);
              return 0;
            }};
          }};
}

Parser help_parser() {
  return {
      {}, [](const Words& words) {
        if (words.positionals.size() > 1) throw UsageError("help takes at most one COMMAND");
        return print(words.positionals.empty() ? help_text() : command_help(words.positionals[0]));
      }};
}

Parser version_parser() {
  return {{}, [](const Words& words) {
            if (!words.positionals.empty())
              throw UsageError("--version takes no argument (got '" + words.positionals[0] + "')");
            return print(version_text() + "\n");
          }};
}

constexpr CommandSpec kCommands[] = {
    {"trace", "SCENE --rays FILE --out FILE [FLAGS]",
     "Traces a ray file (per ray eight little-endian float32: ox oy oz tmin dx dy dz tmax; tmax "
     "may be +inf) through a structure and writes a hit file (per ray int32 id and float32 t u "
     "v: the nearest triangle with tmin < t <= tmax, lowest id among equal t; a miss, and every "
     "invalid ray, is -1 +inf 0 0).",
     trace_parser},
    {"render", "SCENE --out FILE.png [FLAGS]",
     "Renders a PNG with Lambert shading and a shadow ray toward a light above and behind the "
     "camera, and prints its path.",
     render_parser},
    {"shot", "SCENE --out FILE.png [FLAGS]",
     "Draws the frame the viewer shows, headless (OSMesa), with overlays of what the structure "
     "built, and prints the PNG's path.",
     shot_parser},
    {"view", "[SCENE] [FLAGS]",
     "Opens the interactive explorer (default builtin:lumpy, close-up): a progressive render, "
     "the structure's cells, a clicked pixel's walk and the cost model beside it. The script "
     "flags run it unattended.",
     view_parser},
    {"export", "SCENE --out FILE.obj",
     "Writes any scene, built-ins included, as OBJ with the same triangles in the same order. "
     "SCENE suite:NAME is a bench scene as the bench composes it (NAME one of the suite's); its "
     "camera and light are then printed (\"camera STRING\", \"light X,Y,Z\").",
     export_parser},
    {"rays", "SCENE --out FILE.rays [FLAGS]",
     "Writes the primary rays a one-sample render shoots (pixel centres, rows from the top-left "
     "pixel) as a ray file for trace.",
     rays_parser},
    {"bench", "[FLAGS]",
     "Runs the paper's experiment (§7) over a scene suite on every structure and writes "
     "DIR/results.json, report.md and PNG plots.",
     bench_parser},
    {"calibrate", "[FLAGS]",
     "Measures the §6.2 cost constants on this machine and prints them as flags.",
     calibrate_parser},
    {"help", "[COMMAND]", "Prints this help, or one command's.", help_parser},
    {"--version", "", "Prints the version and the git commit the binary was built from.",
     version_parser},
};

const CommandSpec* find_command(std::string_view name) {
  const auto found = std::ranges::find(kCommands, name, &CommandSpec::name);
  return found == std::end(kCommands) ? nullptr : &*found;
}

// ---- Help -----------------------------------------------------------------------------------

constexpr size_t kHelpWidth = 100;
constexpr size_t kFlagColumn = 28;

// The words of `text` in lines of at most kHelpWidth, the first after `lead`, all indented
// by `indent` (a lead that reaches the indent gets a line of its own).
std::string wrapped(const std::string& lead, const std::string& text, size_t indent) {
  std::string out;
  std::string line = lead;
  if (!lead.empty() && line.size() + 1 > indent) out += line + "\n", line.clear();
  line.resize(indent, ' ');
  bool empty = true;
  std::istringstream words(text);
  for (std::string word; words >> word;) {
    if (!empty && line.size() + 1 + word.size() > kHelpWidth) {
      out += line + "\n";
      line.assign(indent, ' ');
      empty = true;
    }
    line += (empty ? "" : " ") + word;
    empty = false;
  }
  return out + line + "\n";
}

std::string flag_entry(const Flag& flag) {
  return wrapped("  " + flag.name + (flag.value_name.empty() ? "" : " " + flag.value_name),
                 flag.help, kFlagColumn);
}

bool takes_structure_flags(const Parser& parser) {
  return std::ranges::any_of(parser.flags, &Flag::structure);
}

bool takes_accel(const Parser& parser) {
  return std::ranges::any_of(
      parser.flags, [](const Flag& f) { return f.name == "--accel" || f.name == "--accels"; });
}

std::string structure_flags_intro() {
  std::vector<std::string> commands, lenient;
  for (const CommandSpec& command : kCommands)
    if (takes_structure_flags(command.parser())) commands.emplace_back(command.name);
  for (const Structure& structure : structures())
    if (structure.takes_any_flag) lenient.push_back(structure.name);
  return wrapped("",
                 "Structure flags (" + joined(commands) +
                     "): the paper's cost constants (§6.2) and each structure's limits. A "
                     "structure refuses a flag it does not read (exit status 2), but " +
                     joined(lenient) +
                     ", the reference, takes and ignores them all, so that a command line can "
                     "be run against it by changing --accel alone.",
                 0);
}

std::string structure_flag_entries() {
  AccelParams params;
  std::string out;
  for (const Flag& flag : structure_flags(params)) out += flag_entry(flag);
  return out;
}

std::string structures_section() {
  std::string out = "Structures (--accel):\n";
  for (const Structure& structure : structures()) {
    std::string text = "[";
    text.append(group_name(structure.group)).append("] ").append(structure.description);
    if (structure.takes_any_flag) text += "; takes and ignores every structure flag";
    if (!structure.available()) text += ". Not in this build: " + structure.missing;
    out += wrapped("  " + structure.name, text, 12);
  }
  return out;
}

std::string notes(std::string_view synopsis) {
  std::string out;
  if (synopsis.find("SCENE") != std::string_view::npos)
    out += wrapped(
        "",
        "SCENE is an .obj or .ply file (.gz too) or builtin:NAME (pyramid, lumpy, sphereflake).",
        0);
  return out + "Exit status: 0 success, 1 bad input or a failed run, 2 usage error.\n";
}

std::string synopsis_line(const CommandSpec& command) {
  std::string line = "gridscope ";
  line += command.name;
  if (!command.synopsis.empty()) line.append(" ").append(command.synopsis);
  return line + "\n";
}

// Sections of help with a blank line between them.
std::string separated(const std::vector<std::string>& sections) {
  std::string text;
  for (const std::string& section : sections) {
    if (!text.empty()) text += '\n';
    text += section;
  }
  return text;
}

// A command's synopsis, paragraph and own flags (its structure flags are listed apart).
std::string command_section(const CommandSpec& command) {
  std::string out = synopsis_line(command) + wrapped("", std::string(command.about), 2);
  for (const Flag& flag : command.parser().flags)
    if (!flag.structure) out += flag_entry(flag);
  return out;
}

}  // namespace

std::vector<CommandFlags> command_flags() {
  std::vector<CommandFlags> list;
  for (const CommandSpec& command : kCommands) {
    list.push_back({std::string(command.name), {}});
    for (const Flag& flag : command.parser().flags) list.back().flags.push_back(flag.name);
  }
  return list;
}

std::string help_text() {
  std::vector<std::string> sections = {
      "usage: gridscope COMMAND [SCENE] [FLAGS]  (gridscope COMMAND --help: that command "
      "alone)\nFlags come in any order after the command, as --flag VALUE or --flag=VALUE.\n"};
  for (const CommandSpec& command : kCommands) {
    sections.push_back(command_section(command));
    if (takes_structure_flags(command.parser()))
      sections.back() +=
          wrapped("  STRUCTURE FLAGS", "as listed under \"Structure flags\" below", kFlagColumn);
  }
  sections.push_back(structure_flags_intro() + structure_flag_entries());
  sections.push_back(structures_section());
  sections.push_back(notes("SCENE"));
  return separated(sections);
}

std::string command_help(const std::string& name) {
  const CommandSpec* command = find_command(name);
  if (!command) throw UsageError("unknown command '" + name + "'");
  const Parser parser = command->parser();
  std::vector<std::string> sections = {command_section(*command)};
  if (takes_structure_flags(parser))
    sections.push_back(structure_flags_intro() + structure_flag_entries());
  if (takes_accel(parser)) sections.push_back(structures_section());
  sections.push_back(notes(command->synopsis));
  return separated(sections);
}

Command parse_cli(std::span<const std::string> args) {
  if (args.empty()) throw UsageError("no command given (try 'gridscope help')");
  const std::string& name = args[0];
  if (name == "-h" || name == "--help") return print(help_text());
  const CommandSpec* command = find_command(name);
  if (std::ranges::find(args, "--help") != args.end())
    return print(command ? command_help(name) : help_text());
  if (!command) throw UsageError("unknown command '" + name + "'");
  const Parser parser = command->parser();
  return parser.finish(parse_words(name, args.subspan(1), parser.flags));
}

int run_cli(std::span<const std::string> args) { return parse_cli(args).run(); }

}  // namespace gs::app
