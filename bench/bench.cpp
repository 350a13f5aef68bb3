#include "bench/bench.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <numeric>
#include <optional>
#include <thread>

#include "bench/calibrate.h"
#include "bench/scenes.h"
#include "core/accel/registry.h"
#include "core/accel/zero_overhead.h"
#include "core/base/error.h"
#include "core/base/timing.h"
#include "core/render/render.h"

namespace gs {

namespace {

using nlohmann::json;

// Image sizes, repetitions and time limits of a full or --quick run.
struct Protocol {
  int side;         // the paper's 512x512 (full)
  int repetitions;  // warm renders whose median is reported
  int sweep_side;   // parameter sweeps render this square image
  int sweep_repetitions;
  int convergence_side, convergence_spp;
  // A render estimated to take longer than this is traced on every k-th row only (its time
  // scaled by k and marked over_time_cap), so that a structure that breaks down on a scene
  // (the uniform grid on lumpy) cannot stall the run.
  double time_cap;
  std::vector<std::string> convergence_scenes;
};

Protocol protocol_for(bool quick) {
  if (quick) return {256, 3, 96, 2, 96, 6, 2.0, {"lumpy"}};
  return {512, 5, 192, 3, 192, 16, 10.0, {"lumpy", "bunny-sibenik", "dragon"}};
}

std::string first_line_of(const std::string& command) {
  std::string line;
  if (FILE* pipe = popen(command.c_str(), "r")) {
    char buffer[256];
    if (fgets(buffer, sizeof buffer, pipe)) line = buffer;
    pclose(pipe);
  }
  while (!line.empty() && (line.back() == '\n' || line.back() == '\r')) line.pop_back();
  return line.empty() ? "unknown" : line;
}

// The value after "key" in the first matching "key: value" / key="value" line of a file.
std::string file_field(const std::string& path, const std::string& key, char separator) {
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);)
    if (line.rfind(key, 0) == 0) {
      std::string value = line.substr(line.find(separator) + 1);
      value.erase(0, value.find_first_not_of(" \t\""));
      value.erase(value.find_last_not_of(" \t\"") + 1);
      return value;
    }
  return "unknown";
}

json machine_json() {
  return {{"cpu", file_field("/proc/cpuinfo", "model name", ':')},
          {"cores", int(std::thread::hardware_concurrency())},
          {"os", file_field("/etc/os-release", "PRETTY_NAME", '=')},
          {"compiler", std::string("GCC ") + __VERSION__}};
}

// How busy the machine was, so that a figure taken while other processes ran can be told
// from a quiet one: the 1-minute load average, and CPU seconds (all cores, from /proc/stat;
// this process's, from its CPU clock) whose difference over a measurement is what others used.
struct CpuUse {
  double machine_busy_seconds = 0.0;
  double own_seconds = 0.0;
};

double load_average() {
  std::ifstream in("/proc/loadavg");
  double load = 0.0;
  return in >> load ? load : 0.0;
}

CpuUse cpu_use() {
  CpuUse use;
  use.own_seconds = process_cpu_seconds();
  std::ifstream in("/proc/stat");
  std::string cpu;
  // user nice system idle iowait irq softirq steal: busy is all but idle and iowait.
  double ticks[8] = {};
  if (in >> cpu && cpu == "cpu") {
    for (double& t : ticks) in >> t;
    const double busy = ticks[0] + ticks[1] + ticks[2] + ticks[5] + ticks[6] + ticks[7];
    use.machine_busy_seconds = busy / double(sysconf(_SC_CLK_TCK));
  }
  return use;
}

// A figure is marked as taken under load when other processes kept more than this many
// cores busy on average while it was measured.
constexpr double kLoadedCores = 0.25;

// Cores other processes kept busy, on average, from `before` to `after`: the machine's busy
// time less this process's, over `window` seconds of renders.
double others_busy_cores(const CpuUse& before, const CpuUse& after, double window) {
  const double own = after.own_seconds - before.own_seconds;
  return window > 0.0
             ? std::max(0.0, after.machine_busy_seconds - before.machine_busy_seconds - own) /
                   window
             : 0.0;
}

// Load figures of a structure's warm renders: the load average before them, the cores other
// processes kept busy while they and the renders paired with them ran, and the structure's
// own `wall` seconds and `cpu` seconds of this process's CPU time.
void fill_load(json& record, double load_before, double others_busy, double wall, double cpu) {
  record["load_before"] = load_before;
  record["others_busy_cores"] = others_busy;
  record["under_load"] = others_busy > kLoadedCores;
  record["cpu_seconds"] = cpu;
  record["wall_seconds"] = wall;
}

// The five section 6.2 constants of AccelParams or a Calibration (the same field names).
template <class Constants>
json cost_constants(const Constants& c) {
  return {{"intcost", c.intcost},
          {"repcost", c.repcost},
          {"travcost", c.travcost},
          {"vertcost", c.vertcost},
          {"subcost", c.subcost}};
}

// What every record of one run shares.
struct RunInfo {
  json machine;
  std::string commit;
  uint64_t seed;
  int repetitions;
  bool quick;
  Clock::time_point start = Clock::now();
  double seconds() const { return seconds_since(start); }  // since the run began
};

// The reference for one scene and workload: its answers and image at the protocol's size.
struct Reference {
  std::string accel;
  std::vector<Hit> answers;
  Image image;
};

// One timed configuration: what is measured and against what.
struct Config {
  const BenchScene* scene;
  Camera camera;
  std::string accel;
  AccelParams params;
  RenderSettings settings;
  int repetitions;
  double time_cap;
};

json base_record(const RunInfo& run, const Config& config, const std::string& setting,
                 const std::string& workload, const Reference* reference) {
  const BenchScene& bench = *config.scene;
  json record = {{"scene", bench.label},
                 {"role", bench.role.empty() ? json(nullptr) : json(bench.role)},
                 {"varying_complexity",
                  bench.varying_complexity ? json(*bench.varying_complexity) : json(nullptr)},
                 {"triangles", bench.scene->triangle_count()},
                 {"accel", config.accel},
                 {"setting", setting},
                 {"params", config.params.to_json()},
                 {"threads", config.settings.threads},
                 {"workload", workload},
                 {"width", config.settings.width},
                 {"height", config.settings.height},
                 {"spp", config.settings.spp},
                 {"camera", to_string(config.camera)},
                 {"machine", run.machine},
                 {"commit", run.commit},
                 {"seed", run.seed},
                 {"repetitions", config.repetitions},
                 {"quick", run.quick},
                 {"reference", reference ? json(reference->accel) : json(nullptr)}};
  for (const char* key :
       {"build_seconds", "first_pass_seconds", "lazy_build_seconds", "trace_seconds", "rays",
        "rays_per_second", "relative_to_zero", "memory_bytes", "nodes", "tests_per_ray",
        "steps_per_ray", "disagreeing_rays", "image_rmse"})
    record[key] = nullptr;
  record["over_time_cap"] = false;
  record["warm_seconds"] = json::array();
  return record;
}

// Whether two nearest hits name the same triangle at the same distance. t is compared to a
// relative 1e-5, not bit for bit: Embree's kernel rounds differently from ours (the suites
// check our structures bit for bit against brute).
bool same_nearest(const Hit& a, const Hit& b) {
  if (a.id != b.id) return false;
  return !a.found() || std::abs(a.t - b.t) <= 1e-5f * std::max(std::abs(a.t), std::abs(b.t));
}

// Rays whose answers differ from the reference's: a nearest hit must name the same triangle
// at the same t; a shadow ray's any-hit answer may name another blocker, so only blocked or
// not counts.
uint64_t count_disagreements(const RenderSettings& settings, const std::vector<Hit>& answers,
                             const std::vector<Hit>& reference) {
  uint64_t differing = 0;
  const size_t pixels = size_t(settings.width) * size_t(settings.height);
  for (size_t pixel = 0; pixel < pixels; ++pixel)
    for (int sample = 0; sample < settings.spp; ++sample)
      for (int bounce = 0; bounce <= settings.bounces; ++bounce) {
        const uint64_t near = render_ray_key(settings, pixel, sample, bounce, RayKind::nearest);
        const uint64_t shadow = render_ray_key(settings, pixel, sample, bounce, RayKind::shadow);
        differing += !same_nearest(answers[near], reference[near]);
        differing += answers[shadow].found() != reference[shadow].found();
      }
  return differing;
}

// Renders every `stride`-th band of rows (in the order the threads take them): a slow
// structure's image, timed on a fraction of it. `scale` becomes bands / bands rendered.
RenderOutcome strided_render(const BenchScene& bench, const Accelerator& accel,
                             const Camera& camera, const RenderSettings& settings, int stride,
                             double& scale) {
  std::atomic<int> turn{0}, rendered{0};
  const RowRunner every_kth = [&](const std::function<void()>& render_row) {
    if (turn.fetch_add(1) % stride != 0) return;
    render_row();
    rendered.fetch_add(1);
  };
  RenderOutcome outcome =
      render_pass(*bench.scene, accel, camera, settings, 1, 0, nullptr, every_kth);
  scale = double(turn.load()) / double(std::max(1, rendered.load()));
  return outcome;
}

// The structure for a configuration: zero replays the reference's answers.
std::unique_ptr<Accelerator> make_structure(const Config& config, const Reference* reference) {
  if (config.accel == "zero") return std::make_unique<ZeroOverhead>(reference->answers);
  return make_accelerator(config.accel, config.params);
}

// What a probe of one render found: the render's estimated seconds, and the lazy build its
// rows set off.
struct Probe {
  double render_seconds = 0.0;
  double lazy_build_seconds = 0.0;
};

// Estimated seconds of one full render, from every 32nd band of rows (in the order the
// threads take them) until `budget` seconds have gone: so that the probe of a structure
// that breaks down costs little. The rows' rays build what they reach of a lazy structure:
// the upper levels of a grid1d, which every row's rays go through, are cut here.
Probe probe_render(const BenchScene& bench, const Accelerator& accel, const Camera& camera,
                   const RenderSettings& settings, double budget) {
  constexpr int kProbeStride = 32;
  std::atomic<int> turn{0}, rendered{0};
  const auto start = Clock::now();
  const RowRunner probe = [&](const std::function<void()>& render_row) {
    const bool in_time = seconds_since(start) < budget;
    if (turn.fetch_add(1) % kProbeStride == kProbeStride / 2 && in_time) {
      render_row();
      rendered.fetch_add(1);
    }
  };
  const RenderOutcome pass =
      render_pass(*bench.scene, accel, camera, settings, 1, 0, nullptr, probe);
  // The lazy build the probe rows set off is paid once, not once a row: scaled up with the
  // rows it made a structure that builds lazily (the full dragon's sweep points) look slow.
  const double lazy = pass.counters.lazy_build_seconds;
  const double tracing = std::max(0.0, pass.seconds - lazy);
  return {lazy + tracing * double(turn.load()) / double(std::max(1, rendered.load())), lazy};
}

void fill_structure_figures(json& record, const Accelerator& accel, const RenderOutcome& warm) {
  const StructureStats stats = accel.stats();
  record["memory_bytes"] = stats.memory_bytes;
  record["nodes"] = stats.nodes ? json(*stats.nodes) : json(nullptr);
  const double rays = double(std::max<uint64_t>(warm.rays, 1));
  if (stats.counts_tests) record["tests_per_ray"] = double(warm.counters.intersection_tests) / rays;
  if (stats.counts_steps) record["steps_per_ray"] = double(warm.counters.traversal_steps) / rays;
  // Why packets gain what they gain: how full their steps were, how many rays left them.
  if (warm.counters.packet_steps > 0)
    record["packet_active_fraction"] = warm.counters.packet_active_fraction();
  if (const uint64_t offered = warm.counters.packet_rays + warm.counters.packet_fallback_rays)
    record["packet_fallback_fraction"] =
        double(warm.counters.packet_fallback_rays) / double(offered);
}

void fill_times(json& record, double trace_seconds, uint64_t rays) {
  record["trace_seconds"] = trace_seconds;
  record["rays"] = rays;
  record["rays_per_second"] = trace_seconds > 0.0 ? double(rays) / trace_seconds : 0.0;
}

// A structure too slow for the time cap: one pass over every k-th row, scaled.
void measure_over_cap(json& record, const Config& config, const Accelerator& accel,
                      double estimate) {
  const int stride = std::min(config.settings.height, int(std::ceil(estimate / config.time_cap)));
  double scale = 1.0;
  const RenderOutcome part =
      strided_render(*config.scene, accel, config.camera, config.settings, stride, scale);
  record["over_time_cap"] = true;
  record["first_pass_seconds"] = part.seconds * scale;
  fill_times(record, part.seconds * scale, uint64_t(double(part.rays) * scale));
  fill_structure_figures(record, accel, part);
}

// One structure's measurement: built and rendered once (the lazy build) on its own, then its
// warm renders taken in rounds with the other measurements of its group (measure_in_rounds).
struct Measurement {
  Config config;
  json record;
  std::vector<Hit> answers;  // empty when over the time cap
  Image image;
  std::unique_ptr<Accelerator> accel;  // as measured: built, its lazy parts too
  bool warm = false;                   // false when over the time cap: no warm renders
  // The warm renders, when each began (seconds since the run began), and the renders paired
  // with them.
  std::vector<double> warm_seconds, started, floor_seconds, one_thread_seconds;
  double warm_cpu = 0.0;
  RenderOutcome last;
};

// The zero-overhead replay of one workload's reference at one thread count, kept built while
// the structures are measured: each warm render of a structure is followed by one of the
// floor, and the structure's time relative to zero is the median of the pairs' ratios. A
// shared machine's speed drifts by 10-30% over minutes; a floor measured once, before the
// structures, would carry that drift into every ratio taken later.
struct Floor {
  Config config;
  std::unique_ptr<Accelerator> zero;
  double seconds;  // the floor's own warm median (for a figure over the time cap)
};

// What a group of measurements asks for: a configuration and its setting's name.
struct Planned {
  Config config;
  std::string setting;
};

// Builds the structure, runs the sampling pass and renders once (the first pass, lazy build
// included); a structure estimated over the time cap is measured on a strided pass instead
// and takes no warm renders.
Measurement start_measurement(const RunInfo& run, const Planned& plan, const std::string& workload,
                              const Reference* reference, const Floor* floor) {
  Measurement m;
  m.config = plan.config;
  const Config& config = m.config;
  json& record = m.record;
  record = base_record(run, config, plan.setting, workload, reference);
  const Scene& scene = *config.scene->scene;
  m.accel = make_structure(config, reference);
  record["build_seconds"] = seconds_of([&] { m.accel->build(scene); }) + seconds_of([&] {
                              sample_image(scene, *m.accel, config.camera, config.settings);
                            });
  const Probe probe = config.accel == "zero"
                          ? Probe{}
                          : probe_render(*config.scene, *m.accel, config.camera, config.settings,
                                         0.05 * config.time_cap);
  if (probe.render_seconds > config.time_cap) {
    measure_over_cap(record, config, *m.accel, probe.render_seconds);
    if (floor) record["relative_to_zero"] = record["trace_seconds"].get<double>() / floor->seconds;
    return m;
  }
  RenderOutcome first = render_image(scene, *m.accel, config.camera, config.settings, &m.answers);
  const FirstPassFigures figures = first_pass_figures(first, probe.lazy_build_seconds);
  record["first_pass_seconds"] = figures.seconds;
  record["lazy_build_seconds"] = figures.lazy_build_seconds;
  m.image = std::move(first.image);
  m.warm = true;
  return m;
}

// One warm render, followed by one of the floor (with a floor) and, on more than one thread,
// by one of the same structure on one thread: the speed-up is the median of those pairs'
// ratios, not a ratio of two figures taken minutes apart (the machine's drift between them
// read as speed-ups of 1.6x and 2.6x on two cores).
void warm_render(Measurement& m, const Floor* floor, double run_seconds) {
  const Config& config = m.config;
  const Scene& scene = *config.scene->scene;
  m.started.push_back(run_seconds);
  m.last = render_image(scene, *m.accel, config.camera, config.settings);
  m.warm_seconds.push_back(m.last.seconds);
  m.warm_cpu += m.last.cpu_seconds;
  if (config.settings.threads > 1) {
    RenderSettings one_thread = config.settings;
    one_thread.threads = 1;
    m.one_thread_seconds.push_back(
        render_image(scene, *m.accel, config.camera, one_thread).seconds);
  }
  if (floor)
    m.floor_seconds.push_back(
        render_image(scene, *floor->zero, floor->config.camera, floor->config.settings).seconds);
}

double sum_of(const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0); }

// The median of numerator[i] / denominator[i].
double median_ratio(const std::vector<double>& numerator, const std::vector<double>& denominator) {
  std::vector<double> ratios;
  for (size_t i = 0; i < numerator.size(); ++i) ratios.push_back(numerator[i] / denominator[i]);
  return median(ratios);
}

// The record's warm figures from the renders taken (others_busy: cores other processes kept
// busy during the rounds).
void finish_measurement(Measurement& m, const Reference* reference, double load_before,
                        double others_busy) {
  json& record = m.record;
  if (m.warm) {
    fill_load(record, load_before, others_busy, sum_of(m.warm_seconds), m.warm_cpu);
    record["warm_seconds"] = m.warm_seconds;
    record["warm_started_seconds"] = m.started;
    fill_times(record, median(m.warm_seconds), m.last.rays);
    if (!m.floor_seconds.empty()) {
      record["zero_warm_seconds"] = m.floor_seconds;
      record["relative_to_zero"] = median_ratio(m.warm_seconds, m.floor_seconds);
    }
    if (!m.one_thread_seconds.empty()) {
      record["one_thread_warm_seconds"] = m.one_thread_seconds;
      record["speedup"] = median_ratio(m.one_thread_seconds, m.warm_seconds);
    }
    fill_structure_figures(record, *m.accel, m.last);
  }
  if (reference && !reference->answers.empty() && !m.answers.empty()) {
    record["disagreeing_rays"] =
        count_disagreements(m.config.settings, m.answers, reference->answers);
    record["image_rmse"] = image_rmse(m.image.rgba, reference->image.rgba);
  }
}

// Measures a group of structures in rounds: each is built and rendered once, then every
// round takes one warm render of each (with the renders paired with it, warm_render), the
// first structure of a round moving on by one each round. Structures compared with each other
// (one scene, workload and thread count) are then timed in the same minutes, so that the
// machine's drift, which reaches 30% within a minute here, falls on all of them alike.
std::vector<Measurement> measure_in_rounds(const RunInfo& run, const std::vector<Planned>& plans,
                                           const std::string& workload, const Reference* reference,
                                           const Floor* floor) {
  std::vector<Measurement> group;
  for (const Planned& plan : plans)
    group.push_back(start_measurement(run, plan, workload, reference, floor));
  const double load_before = load_average();
  const CpuUse before = cpu_use();
  const size_t n = group.size();
  int rounds = 0;
  for (const Measurement& m : group) rounds = std::max(rounds, m.config.repetitions);
  for (int round = 0; round < rounds; ++round)
    for (size_t k = 0; k < n; ++k) {
      Measurement& m = group[(size_t(round) + k) % n];
      if (m.warm && round < m.config.repetitions) warm_render(m, floor, run.seconds());
    }
  double window = 0.0;
  for (const Measurement& m : group)
    window += sum_of(m.warm_seconds) + sum_of(m.floor_seconds) + sum_of(m.one_thread_seconds);
  const double others_busy = others_busy_cores(before, cpu_use(), window);
  for (Measurement& m : group) finish_measurement(m, reference, load_before, others_busy);
  return group;
}

// One structure measured on its own (the reference, the floor, a sweep point).
Measurement measure(const RunInfo& run, const Config& config, const std::string& setting,
                    const std::string& workload, const Reference* reference) {
  return std::move(measure_in_rounds(run, {{config, setting}}, workload, reference, nullptr)[0]);
}

// brute when it is affordable (a few billion ray-triangle tests), else bvh, whose answers the
// suites check equal to brute's bit for bit.
Reference make_reference(const RunInfo& run, Config config) {
  const double work =
      double(config.scene->scene->triangle_count()) * double(render_ray_keys(config.settings));
  config.accel = work < 3e9 && !run.quick ? "brute" : "bvh";
  config.params = AccelParams{};
  config.repetitions = 0;
  config.time_cap = 1e30;
  config.settings.threads = default_thread_count();
  Measurement measured = measure(run, config, "reference", "reference", nullptr);
  return {config.accel, std::move(measured.answers), std::move(measured.image)};
}

// A scene label as a file name: a user's path gives its file name's stem.
std::string file_label(const std::string& label) {
  return std::filesystem::path(label).stem().string();
}

std::string format_progress(const json& record, double elapsed) {
  char line[256];
  const double rate =
      record["rays_per_second"].is_number() ? record["rays_per_second"].get<double>() * 1e-6 : 0.0;
  std::snprintf(line, sizeof line, "[%6.1f s] %-14s %-8s %-10s t%d %-14s %8.3f Mrays/s%s", elapsed,
                record["scene"].get<std::string>().c_str(),
                record["accel"].get<std::string>().c_str(),
                record["setting"].get<std::string>().c_str(), record["threads"].get<int>(),
                record["workload"].get<std::string>().c_str(), rate,
                record["over_time_cap"].get<bool>() ? " (over time cap: strided)" : "");
  return line;
}

// The progressive renderer's error against its own converged image over wall time, from the
// start of the build (run time against error): a correct structure reaches zero
// error at the last pass, a faster one sooner.
class Convergence {
 public:
  Convergence(const BenchScene& bench, const Camera& camera, RenderSettings settings,
              double time_limit)
      : bench_(bench), camera_(camera), settings_(settings), time_limit_(time_limit) {
    auto reference = make_accelerator("bvh", AccelParams{});
    reference->build(*bench.scene);
    converged_ = render_image(*bench.scene, *reference, camera, settings).image;
  }

  // [[seconds, rmse], ...] after each accumulation pass; stops early past the time limit.
  json points(const std::string& accel_name) const {
    json points = json::array();
    const auto start = Clock::now();
    auto elapsed = [&] { return seconds_since(start); };
    auto accel = make_accelerator(accel_name, AccelParams{});
    accel->build(*bench_.scene);
    sample_image(*bench_.scene, *accel, camera_, settings_);
    RenderSettings one_sample = settings_;
    one_sample.spp = 1;
    // A structure that cannot make two passes in the time limit (the uniform grid on lumpy)
    // gets no curve rather than stalling the run.
    if (2.0 * probe_render(bench_, *accel, camera_, one_sample, 0.05 * time_limit_).render_seconds >
        time_limit_)
      return points;
    std::vector<glm::vec3> sums(size_t(settings_.width) * size_t(settings_.height));
    // The viewer's accumulation (core/progressive.cpp): the pass for spp N adds the samples
    // render_image takes for spp N that the image does not have yet.
    for (int spp = 2; spp <= settings_.spp && elapsed() < time_limit_; ++spp) {
      RenderSettings pass = settings_;
      pass.spp = spp;
      const RenderOutcome outcome =
          render_pass(*bench_.scene, *accel, camera_, pass, 1, spp == 2 ? 0 : spp - 1, &sums);
      points.push_back({elapsed(), image_rmse(outcome.image.rgba, converged_.rgba)});
    }
    return points;
  }

 private:
  const BenchScene& bench_;
  Camera camera_;
  RenderSettings settings_;
  double time_limit_;
  Image converged_;
};

class BenchRun {
 public:
  explicit BenchRun(const BenchOptions& options)
      : options_(options), protocol_(protocol_for(options.quick)) {
    run_.machine = machine_json();
    run_.commit = first_line_of("git -C '" + std::string(GRIDSCOPE_SOURCE_DIR) +
                                "' rev-parse HEAD 2>/dev/null");
    run_.seed = options.seed;
    run_.repetitions = protocol_.repetitions;
    run_.quick = options.quick;
    accels_ = options.accels;
    if (accels_.empty())
      for (const std::string& name : bench_structures())
        if (find_structure(name)->available()) accels_.push_back(name);
    total_steps_ = planned_steps();
  }

  json run() {
    calibrate_constants();
    const std::string assets =
        options_.assets_dir.empty() ? find_assets_dir() : options_.assets_dir;
    for (const std::string& name : scene_names()) {
      std::string skipped;
      const std::optional<BenchScene> bench = load_bench_scene(name, assets, skipped);
      if (bench) {
        run_scene(*bench);
      } else {
        records_.push_back(
            {{"scene", name}, {"accel", nullptr}, {"workload", "skipped"}, {"reason", skipped}});
        step_done(name, "", "skipped " + skipped, scene_steps(name));
      }
    }
    return records_;
  }

 private:
  // A measurement's record, reported as a step.
  void add(json record) {
    step_done(record["scene"].get<std::string>(), record["accel"].get<std::string>(),
              format_progress(record, elapsed()));
    records_.push_back(std::move(record));
  }

  // Counts `steps` more done (a skipped scene's all at once) and reports the newest.
  void step_done(const std::string& scene, const std::string& accel, const std::string& line,
                 int steps = 1) {
    done_steps_ += steps;
    if (options_.progress)
      options_.progress({done_steps_, total_steps_, elapsed(), scene, accel, line});
  }

  // "[  12.3 s] text", as format_progress starts its lines.
  std::string stamped(const std::string& text) const {
    char stamp[32];
    std::snprintf(stamp, sizeof stamp, "[%6.1f s] ", elapsed());
    return stamp + text;
  }

  std::vector<std::string> scene_names() const {
    return options_.scenes.empty() ? bench_suite(options_.quick) : options_.scenes;
  }

  // The steps run() reports, planned before it begins (the progress line's total and ETA):
  // the calibration, then per scene scene_steps.
  int planned_steps() const {
    int steps = calibrates() ? 1 : 0;
    for (const std::string& name : scene_names()) steps += scene_steps(name);
    return steps;
  }

  // Per workload its reference, then per thread count zero and each structure (again by
  // packets where it walks them); grid1d calibrated; each sweep point and its best (or that
  // there is none); a convergence curve per structure where run_scene makes them.
  int scene_steps(const std::string& name) const {
    int per_thread_count = 1;
    for (const std::string& accel : accels_)
      per_thread_count += find_structure(accel)->traces_packets ? 2 : 1;
    int steps = 2 * (1 + int(thread_counts().size()) * per_thread_count);
    if (calibrates()) ++steps;
    for (const std::string& accel : accels_) {
      for (const SweepAxis& axis : find_structure(accel)->sweep) steps += int(axis.values.size());
      ++steps;
    }
    const std::vector<std::string> suite = bench_suite(false);
    const bool users_scene = std::find(suite.begin(), suite.end(), name) == suite.end();
    if (converges(name, users_scene)) steps += int(accels_.size());
    return steps;
  }

  // The progressive renderer's convergence is followed on the protocol's scenes and on every
  // scene a user names.
  bool converges(const std::string& label, bool users_scene) const {
    const auto& wanted = protocol_.convergence_scenes;
    return users_scene || std::find(wanted.begin(), wanted.end(), label) != wanted.end();
  }

  bool calibrates() const {
    return std::find(accels_.begin(), accels_.end(), "grid1d") != accels_.end();
  }

  double elapsed() const { return run_.seconds(); }

  // The paper's section 6.2 constants measured on this machine (bench/calibrate.h).
  void calibrate_constants() {
    if (!calibrates()) return;
    CalibrateOptions calibrate_options;
    calibrate_options.budget_seconds =
        options_.quick ? CalibrateOptions::kQuickBudget : CalibrateOptions::kDefaultBudget;
    calibrate_options.seed = options_.seed;
    calibration_ = calibrate(calibrate_options);
    records_.push_back({{"accel", "calibration"},
                        {"workload", "calibration"},
                        {"constants", cost_constants(*calibration_)},
                        {"nanoseconds_per_unit", calibration_->nanoseconds_per_unit},
                        {"detail", calibration_->detail},
                        {"defaults", cost_constants(AccelParams{})},
                        {"machine", run_.machine},
                        {"commit", run_.commit}});
    step_done("", "grid1d", stamped("calibration of the section 6.2 constants"));
  }

  Config config(const BenchScene& bench, const std::string& accel, int side, int threads,
                int bounces) const {
    RenderSettings settings;
    settings.width = settings.height = side;
    settings.spp = 1;
    settings.threads = threads;
    settings.bounces = bounces;
    settings.light = bench.light;
    // One ray at a time unless a measurement asks for packets (setting "packets").
    settings.packets = false;
    // Every structure builds on the threads its run traces on: Embree's build would take
    // every core otherwise, also in a 1-thread figure (the full dragon's build here: 0.22-0.33
    // s on two cores, 0.33-0.41 s on one).
    AccelParams params;
    params.build_threads = threads;
    return {&bench,
            camera_for(bench.camera, *bench.scene, settings),
            accel,
            params,
            settings,
            protocol_.repetitions,
            protocol_.time_cap};
  }

  std::vector<int> thread_counts() const {
    return options_.threads > 1 ? std::vector<int>{1, options_.threads} : std::vector<int>{1};
  }

  void run_scene(const BenchScene& bench) {
    for (const auto& [workload, bounces] :
         {std::pair<const char*, int>{"primary_shadow", 0}, {"diffuse", 1}}) {
      Reference reference = make_reference(run_, config(bench, "", protocol_.side, 1, bounces));
      step_done(bench.label, reference.accel,
                stamped(bench.label + " " + reference.accel + " reference " + workload));
      for (const int threads : thread_counts()) {
        Floor floor = run_workload(bench, reference, workload, bounces, threads);
        if (bounces == 0 && threads == 1) primary_floor_ = std::move(floor);
      }
      if (bounces == 0) {
        if (!options_.image_dir.empty())
          write_png(options_.image_dir + "/scene-" + file_label(bench.label) + ".png",
                    reference.image.width, reference.image.height, reference.image.rgba);
        primary_reference_ = std::move(reference);
      }
    }
    run_bests(run_sweeps(bench));
    if (converges(bench.label, bench.role.empty())) run_convergence(bench);
  }

  // The zero-overhead replay of the reference, measured on its own, then kept built as the
  // floor the structures' renders alternate with.
  Floor measure_floor(const BenchScene& bench, const Reference& reference, const char* workload,
                      int bounces, int threads) {
    Config zero = config(bench, "zero", protocol_.side, threads, bounces);
    Measurement own = measure(run_, zero, "default", workload, &reference);
    own.record["relative_to_zero"] = 1.0;
    Floor floor{zero, std::move(own.accel), own.record["trace_seconds"].get<double>()};
    add(std::move(own.record));
    return floor;
  }

  // Every structure against the floor, in rounds, at the protocol's size (with packets too
  // where a structure walks them, and grid1d with the calibrated constants on primary and
  // shadow rays on one thread, so that they are timed beside the defaults); returns the floor.
  Floor run_workload(const BenchScene& bench, const Reference& reference, const char* workload,
                     int bounces, int threads) {
    Floor floor = measure_floor(bench, reference, workload, bounces, threads);
    std::vector<Planned> plans;
    for (const std::string& accel : accels_) {
      Config single = config(bench, accel, protocol_.side, threads, bounces);
      plans.push_back({single, "default"});
      if (!find_structure(accel)->traces_packets) continue;
      // The same rays by packets (8x8 pixel blocks, then their shadow rays).
      Config packets = single;
      packets.settings.packets = true;
      plans.push_back({packets, "packets"});
    }
    if (calibration_ && bounces == 0 && threads == 1) {
      Config calibrated = config(bench, "grid1d", protocol_.side, 1, 0);
      calibrated.params = with_calibration(AccelParams{}, *calibration_);
      plans.push_back({calibrated, "calibrated"});
    }
    for (Measurement& m : measure_in_rounds(run_, plans, workload, &reference, &floor))
      add(std::move(m.record));
    return floor;
  }

  // Each structure's parameters one at a time on a smaller image (1 thread, primary and
  // shadow rays), a structure's points timed in rounds; returns each structure's fastest
  // point, to be measured again in full.
  std::vector<Planned> run_sweeps(const BenchScene& bench) {
    std::vector<Planned> bests;
    for (const std::string& accel : accels_) {
      std::vector<Planned> points;
      std::vector<std::pair<std::string_view, double>> swept;  // per point: parameter, value
      for (const SweepAxis& axis : find_structure(accel)->sweep)
        for (const double value : axis.values) {
          Config point = config(bench, accel, protocol_.sweep_side, 1, 0);
          point.repetitions = protocol_.sweep_repetitions;
          point.time_cap = protocol_.time_cap / 4;
          set_param(point.params, axis.param, value);
          points.push_back({point, "sweep"});
          swept.emplace_back(param_spec(axis.param).key, value);
        }
      std::optional<std::pair<double, AccelParams>> best;
      std::vector<Measurement> measured =
          measure_in_rounds(run_, points, "sweep", nullptr, nullptr);
      for (size_t i = 0; i < measured.size(); ++i) {
        json& record = measured[i].record;
        record["sweep_param"] = swept[i].first;
        record["sweep_value"] = swept[i].second;
        const double seconds = record["trace_seconds"].get<double>();
        if (!record["over_time_cap"].get<bool>() && (!best || seconds < best->first))
          best = {seconds, measured[i].config.params};
        add(std::move(record));
      }
      if (!best) {
        step_done(bench.label, accel,
                  stamped(bench.label + " " + accel +
                          " best: none, every sweep point over the time cap"));
        continue;
      }
      Config full = config(bench, accel, protocol_.side, 1, 0);
      full.params = best->second;
      bests.push_back({full, "best"});
    }
    return bests;
  }

  // The structures at their best settings under the paper's protocol (1 thread, primary and
  // shadow rays, full size), in rounds, against the scene's reference and zero-overhead time.
  void run_bests(const std::vector<Planned>& bests) {
    for (Measurement& m :
         measure_in_rounds(run_, bests, "primary_shadow", &primary_reference_, &*primary_floor_))
      add(std::move(m.record));
  }

  void run_convergence(const BenchScene& bench) {
    Config setup = config(bench, "", protocol_.convergence_side, options_.threads, 1);
    setup.settings.spp = protocol_.convergence_spp;
    const Convergence convergence(bench, setup.camera, setup.settings, 4.0 * protocol_.time_cap);
    for (const std::string& accel : accels_) {
      setup.accel = accel;
      json record = base_record(run_, setup, "default", "convergence", nullptr);
      record["reference"] = "bvh";
      record["points"] = convergence.points(accel);
      records_.push_back(std::move(record));
      step_done(bench.label, accel,
                stamped(bench.label + " " + accel + " convergence: " +
                        std::to_string(records_.back()["points"].size()) + " passes"));
    }
  }

  const BenchOptions& options_;
  Protocol protocol_;
  RunInfo run_;
  std::vector<std::string> accels_;
  std::optional<Calibration> calibration_;
  int total_steps_ = 0, done_steps_ = 0;
  Reference primary_reference_;
  std::optional<Floor> primary_floor_;  // primary and shadow rays, 1 thread
  json records_ = json::array();
};

}  // namespace

FirstPassFigures first_pass_figures(const RenderOutcome& first, double probe_lazy_build_seconds) {
  return {first.seconds + probe_lazy_build_seconds,
          first.counters.lazy_build_seconds + probe_lazy_build_seconds};
}

std::vector<std::string> bench_structures() {
  std::vector<std::string> names;
  for (const Structure& structure : structures())
    if (structure.group != StructureGroup::reference) names.push_back(structure.name);
  return names;
}

void check_bench_options(const BenchOptions& options) {
  const std::vector<std::string> benched = bench_structures();
  for (const std::string& accel : options.accels)
    if (std::ranges::find(benched, accel) == benched.end() || !find_structure(accel)->available())
      throw UsageError("--accels: '" + accel + "' is not a structure this build can bench");
  check_thread_count(options.threads);
}

nlohmann::json run_bench(const BenchOptions& options) {
  check_bench_options(options);
  return BenchRun(options).run();
}

double image_rmse(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  if (a.size() != b.size() || a.size() % 4 != 0)
    throw std::invalid_argument("image_rmse: images of different sizes");
  double sum = 0.0;
  for (size_t i = 0; i < a.size(); ++i) {
    if (i % 4 == 3) continue;  // alpha
    const double d = double(a[i]) - double(b[i]);
    sum += d * d;
  }
  const size_t channels = a.size() / 4 * 3;
  return channels ? std::sqrt(sum / double(channels)) : 0.0;
}

}  // namespace gs
