// Drives the built `gridscope` binary the way scripts and outside checkers do (docs/design.md §3):
// exit statuses, one-line error messages, and file outputs checked against answers worked
// out by hand.
#include <gtest/gtest.h>
#include <stb/stb_image.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <glm/geometric.hpp>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "app/cli.h"
#include "core/accel/registry.h"
#include "core/base/error.h"
#include "core/geometry/ray_io.h"
#include "core/render/render.h"
#include "tests/test_util.h"

namespace {

using gs::test::kInf;
using gs::test::temp_path;

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

using gs::test::quoted;
using gs::test::slurp;
using gs::test::write_temp_file;
using Outcome = gs::test::CommandOutcome;

// Runs gridscope with `args` (already shell-quoted where needed).
Outcome run(const std::string& args) { return gs::test::run_gridscope(args); }

// Exit status 1 or 2 with exactly one stderr line naming `mention`.
void expect_failure(const Outcome& result, int status, const std::string& mention) {
  EXPECT_EQ(result.status, status) << result.err;
  EXPECT_EQ(result.err.rfind("gridscope: ", 0), 0u) << result.err;
  EXPECT_EQ(std::count(result.err.begin(), result.err.end(), '\n'), 1) << result.err;
  EXPECT_NE(result.err.find(mention), std::string::npos) << result.err;
}

// Two triangles, hand-placed: id 0 in z = 0 with corners (0,0) (1,0) (0,1); id 1 in z = 2
// with corners (0,0) (2,0) (0,2). For a point (x, y) inside, u = x / side and v = y / side.
std::string two_triangles() {
  return write_temp_file("two.obj",
                         "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
                         "v 0 0 2\nv 2 0 2\nv 0 2 2\n"
                         "f 1 2 3\nf 4 5 6\n");
}

// A ray file written byte by byte, independent of the library: ox oy oz tmin dx dy dz tmax.
using RayRecord = std::array<float, 8>;
std::string ray_file(const std::string& name, const std::vector<RayRecord>& rays) {
  std::string bytes(rays.size() * 32, '\0');
  for (size_t i = 0; i < rays.size(); ++i) std::memcpy(&bytes[32 * i], rays[i].data(), 32);
  return write_temp_file(name, bytes);
}

struct HitRecord {
  int32_t id;
  float t, u, v;
};

std::vector<HitRecord> hit_file(const std::string& path) {
  const std::string bytes = slurp(path);
  EXPECT_EQ(bytes.size() % 16, 0u);
  std::vector<HitRecord> hits(bytes.size() / 16);
  for (size_t i = 0; i < hits.size(); ++i) {
    std::memcpy(&hits[i].id, &bytes[16 * i], 4);
    std::memcpy(&hits[i].t, &bytes[16 * i + 4], 4);
    std::memcpy(&hits[i].u, &bytes[16 * i + 8], 4);
    std::memcpy(&hits[i].v, &bytes[16 * i + 12], 4);
  }
  return hits;
}

struct Case {
  RayRecord ray;
  HitRecord expected;
  const char* what;
};

const HitRecord kMiss = {-1, kInf, 0.0f, 0.0f};

// Worked out by hand from the two triangles above.
std::vector<Case> hand_cases() {
  return {
      {{0.25f, 0.25f, -1, 0, 0, 0, 1, kInf}, {0, 1.0f, 0.25f, 0.25f}, "straight up, nearest"},
      {{0.25f, 0.25f, -1, 0, 0, 0, 2, kInf}, {0, 0.5f, 0.25f, 0.25f}, "t in units of dir"},
      {{0.25f, 0.25f, -1, 1.5f, 0, 0, 1, kInf}, {1, 3.0f, 0.125f, 0.125f}, "tmin skips id 0"},
      {{0.25f, 0.25f, -1, 1.0f, 0, 0, 1, kInf}, {1, 3.0f, 0.125f, 0.125f}, "t = tmin excluded"},
      {{0.9f, 0.9f, -1, 0, 0, 0, 1, kInf}, {1, 3.0f, 0.45f, 0.45f}, "outside id 0, inside id 1"},
      {{0.25f, 0.25f, 5, 0, 0, 0, -1, kInf}, {1, 3.0f, 0.125f, 0.125f}, "from above"},
      {{0.25f, 0.25f, -1, 0, 0, 0, 1, 1.0f}, {0, 1.0f, 0.25f, 0.25f}, "t = tmax included"},
      {{0.25f, 0.25f, -1, 0, 0, 0, 1, 0.5f}, kMiss, "hit beyond tmax"},
      {{0, 0, -1, 0, 0.5f, 0.25f, 1, kInf}, {0, 1.0f, 0.5f, 0.25f}, "oblique"},
      {{5, 5, -1, 0, 0, 0, 1, kInf}, kMiss, "beside both"},
      {{0.25f, 0.25f, -1, 0, kNaN, 0, 1, kInf}, kMiss, "NaN direction"},
      {{0.25f, 0.25f, -1, 2, 0, 0, 1, 1}, kMiss, "tmin > tmax"},
      {{0.25f, 0.25f, -1, 0, 0, 0, 0, kInf}, kMiss, "zero direction"},
      {{kInf, 0.25f, -1, 0, 0, 0, 1, kInf}, kMiss, "infinite origin"},
  };
}

std::vector<RayRecord> rays_of(const std::vector<Case>& cases) {
  std::vector<RayRecord> rays;
  for (const Case& c : cases) rays.push_back(c.ray);
  return rays;
}

std::string trace_args(const std::string& scene, const std::string& rays, const std::string& out) {
  return "trace " + quoted(scene) + " --rays " + quoted(rays) + " --out " + quoted(out);
}

TEST(Cli, BruteTraceGivesHandComputedHits) {
  const std::vector<Case> cases = hand_cases();
  const std::string rays = ray_file("hand.rays", rays_of(cases));
  const std::string out = temp_path("hand.hits");
  const Outcome result = run(trace_args(two_triangles(), rays, out) + " --accel brute --threads 2");
  ASSERT_EQ(result.status, 0) << result.err;
  const std::vector<HitRecord> hits = hit_file(out);
  ASSERT_EQ(hits.size(), cases.size());
  for (size_t i = 0; i < cases.size(); ++i) {
    SCOPED_TRACE(cases[i].what);
    EXPECT_EQ(hits[i].id, cases[i].expected.id);
    EXPECT_FLOAT_EQ(hits[i].t, cases[i].expected.t);
    EXPECT_NEAR(hits[i].u, cases[i].expected.u, 1e-6);
    EXPECT_NEAR(hits[i].v, cases[i].expected.v, 1e-6);
  }
}

TEST(Cli, OccludedGivesSomeBlockingTriangle) {
  const std::vector<Case> cases = hand_cases();
  const std::string out = temp_path("any.hits");
  const Outcome result =
      run(trace_args(two_triangles(), ray_file("any.rays", rays_of(cases)), out) +
          " --accel brute --occluded");
  ASSERT_EQ(result.status, 0) << result.err;
  const std::vector<HitRecord> hits = hit_file(out);
  ASSERT_EQ(hits.size(), cases.size());
  for (size_t i = 0; i < cases.size(); ++i) {
    SCOPED_TRACE(cases[i].what);
    EXPECT_EQ(hits[i].id < 0, cases[i].expected.id < 0);
    // Either triangle on the ray's interval is a valid answer, with its own t: triangle id
    // lies in the plane z = 2 * id.
    const RayRecord& r = cases[i].ray;
    if (hits[i].id >= 0) {
      EXPECT_FLOAT_EQ(hits[i].t, (2.0f * float(hits[i].id) - r[2]) / r[6]);
    }
  }
}

TEST(Cli, EmptyRayFileGivesEmptyHitFile) {
  const std::string out = write_temp_file("empty.hits", "stale");
  const Outcome result =
      run(trace_args(two_triangles(), ray_file("empty.rays", {}), out) + " --accel brute");
  ASSERT_EQ(result.status, 0) << result.err;
  EXPECT_EQ(slurp(out), "");
}

TEST(Cli, ThreadCountDoesNotChangeHits) {
  std::mt19937 random(7);
  std::uniform_real_distribution<float> coordinate(-1.0f, 3.0f);
  std::vector<RayRecord> rays(5000);
  for (RayRecord& r : rays)
    r = {coordinate(random),     coordinate(random),     -1, 0,
         coordinate(random) - 1, coordinate(random) - 1, 1,  kInf};
  const std::string file = ray_file("many.rays", rays);
  const std::string one = temp_path("one.hits"), four = temp_path("four.hits");
  ASSERT_EQ(run(trace_args(two_triangles(), file, one) + " --accel brute --threads 1").status, 0);
  ASSERT_EQ(run(trace_args(two_triangles(), file, four) + " --accel brute --threads 4").status, 0);
  EXPECT_EQ(slurp(one).size(), rays.size() * 16);
  EXPECT_TRUE(slurp(one) == slurp(four));
}

TEST(Cli, StatsHoldEveryKey) {
  const std::string scene = two_triangles();
  const std::string stats = temp_path("stats.json");
  const std::vector<Case> cases = hand_cases();
  const Outcome result =
      run(trace_args(scene, ray_file("stats.rays", rays_of(cases)), temp_path("stats.hits")) +
          " --accel brute --threads 3 --eager --stats " + quoted(stats) +
          " --intcost 3.5 --memory-budget 64M --axis cost --sample-every 5");
  ASSERT_EQ(result.status, 0) << result.err;
  const nlohmann::json json = nlohmann::json::parse(slurp(stats));
  for (const char* key : {"accel",
                          "parameters",
                          "scene",
                          "triangles",
                          "degenerate_triangles",
                          "rays",
                          "build_seconds",
                          "lazy_build_seconds",
                          "trace_seconds",
                          "rays_per_second",
                          "nodes",
                          "voxels_subdivided",
                          "leaves",
                          "traversal_states",
                          "intersection_tests",
                          "mailbox_rejections",
                          "traversal_steps",
                          "packets",
                          "packet_fallback_rays",
                          "packet_steps",
                          "packet_active_fraction",
                          "memory_bytes",
                          "voxels_over_budget"})
    EXPECT_TRUE(json.contains(key)) << key;
  EXPECT_TRUE(json["packets"].is_null());  // no --packets
  EXPECT_EQ(json["accel"], "brute");
  EXPECT_EQ(json["scene"], scene);
  EXPECT_EQ(json["triangles"], 2);
  EXPECT_EQ(json["degenerate_triangles"], 0);
  EXPECT_EQ(json["rays"], cases.size());
  const nlohmann::json& parameters = json["parameters"];
  EXPECT_EQ(parameters["threads"], 3);
  EXPECT_EQ(parameters["eager"], true);
  EXPECT_EQ(parameters["occluded"], false);
  EXPECT_EQ(parameters["intcost"], 3.5);
  EXPECT_EQ(parameters["memory_budget"], 64u << 20);
  EXPECT_EQ(parameters["axis"], "cost");
  EXPECT_EQ(parameters["sample_every"], 5);
  for (const char* key : {"nodes", "voxels_subdivided", "leaves", "traversal_states"})
    EXPECT_TRUE(json[key].is_null() || json[key].is_number_unsigned()) << key;
  for (const char* key :
       {"build_seconds", "lazy_build_seconds", "trace_seconds", "rays_per_second"})
    EXPECT_GE(json[key].get<double>(), 0.0) << key;
  EXPECT_GE(json["build_seconds"].get<double>(), json["lazy_build_seconds"].get<double>());
  // Every valid ray (8 of them) is tested against some triangle; none against more than two.
  EXPECT_GE(json["intersection_tests"].get<uint64_t>(), 8u);
  EXPECT_LE(json["intersection_tests"].get<uint64_t>(), 2 * cases.size());
  EXPECT_TRUE(json["memory_bytes"].is_number_unsigned());
  EXPECT_TRUE(json["warm_trace_seconds"].is_null());  // one pass only
}

// --repeat 4: the counters describe one pass (brute tests every usable triangle once per
// valid ray: 2 x 8), the warm figures are a median of the 3 later passes.
TEST(Cli, RepeatReportsWarmPassesApart) {
  const std::string stats = temp_path("repeat.json");
  const std::vector<Case> cases = hand_cases();
  const Outcome result = run(trace_args(two_triangles(), ray_file("repeat.rays", rays_of(cases)),
                                        temp_path("repeat.hits")) +
                             " --accel brute --threads 1 --repeat 4 --stats " + quoted(stats));
  ASSERT_EQ(result.status, 0) << result.err;
  const nlohmann::json json = nlohmann::json::parse(slurp(stats));
  EXPECT_EQ(json["parameters"]["repeat"], 4);
  EXPECT_EQ(json["intersection_tests"], 16u);
  ASSERT_TRUE(json["warm_trace_seconds"].is_number());
  EXPECT_GT(json["warm_trace_seconds"].get<double>(), 0.0);
  EXPECT_NEAR(json["warm_rays_per_second"].get<double>(),
              double(cases.size()) / json["warm_trace_seconds"].get<double>(), 1e-6);
  expect_failure(run(trace_args(two_triangles(), ray_file("repeat0.rays", rays_of(cases)),
                                temp_path("repeat0.hits")) +
                     " --repeat 0"),
                 2, "--repeat");
}

TEST(Cli, BadInputExitsOneNamingTheFile) {
  const std::string scene = two_triangles();
  const std::string rays = ray_file("ok.rays", {{0, 0, -1, 0, 0, 0, 1, kInf}});
  const std::string out = temp_path("bad.hits");
  const std::string missing_scene = temp_path("no-such-scene.obj");
  expect_failure(run(trace_args(missing_scene, rays, out) + " --accel brute"), 1, missing_scene);

  const std::string malformed = write_temp_file("malformed.obj", "v 0 0 0\nv 1 0 0\nf 1 2 7\n");
  expect_failure(run(trace_args(malformed, rays, out) + " --accel brute"), 1, malformed);

  const std::string odd = write_temp_file("odd.rays", std::string(33, '\0'));
  expect_failure(run(trace_args(scene, odd, out) + " --accel brute"), 1, odd + ": size 33");

  const std::string missing_rays = temp_path("no-such.rays");
  expect_failure(run(trace_args(scene, missing_rays, out) + " --accel brute"), 1, missing_rays);

  const std::string unwritable = "/nonexistent-dir/x.hits";
  expect_failure(run(trace_args(scene, rays, unwritable) + " --accel brute"), 1, unwritable);
  expect_failure(run(trace_args(scene, rays, out) + " --accel brute --stats " + unwritable), 1,
                 unwritable);
  expect_failure(
      run("render " + quoted(scene) + " --accel brute --size 8x8 --out /nonexistent-dir/x.png"), 1,
      "/nonexistent-dir/x.png");
  expect_failure(run("export " + quoted(missing_scene) + " --out " + quoted(temp_path("x.obj"))), 1,
                 missing_scene);
}

TEST(Cli, UsageErrorsExitTwo) {
  const std::string scene = two_triangles();
  const std::string trace = trace_args(scene, ray_file("u.rays", {}), temp_path("u.hits"));
  const std::string render = "render " + quoted(scene) + " --out " + quoted(temp_path("u.png"));
  // Each command line, and what its one-line error must name.
  std::vector<std::pair<std::string, std::string>> usage_errors = {
      {"", "no command"},
      {"frobnicate", "frobnicate"},
      {trace + " --bogus", "--bogus"},
      {trace + " --accel nosuch", "nosuch"},
      {trace + " --threads 0", "--threads"},
      {trace + " --threads 1025", "--threads"},
      {trace + " --threads two", "--threads"},
      {trace + " --rays", "--rays"},
      {"trace " + quoted(scene) + " --out x.hits", "--rays"},
      {trace + " --intcost -1", "--intcost"},
      {trace + " --vertcost nan", "--vertcost"},
      {trace + " --max-granularity 0", "--max-granularity"},
      {trace + " --max-depth 65", "--max-depth"},
      {trace + " --sample-every 0", "--sample-every"},
      {trace + " --axis diagonal", "--axis"},
      {trace + " --memory-budget 12Q", "--memory-budget"},
      {trace + " --size 8x8", "--size"},
      {render + " --rays x", "--rays"},
      {render + " --spp 0", "--spp"},
      {"bench --accels bvh,kd-tree", "kd-tree"},
      {"bench --scenes lumpy,", "--scenes"},
      {"bench --threads 0", "--threads"},
      {"bench builtin:lumpy", "builtin:lumpy"},
      {"calibrate --seed x", "--seed"},
      {"calibrate --budget 5", "--budget"},
  };
  for (const char* size :
       {"640", "0x10", "10x", "x10", "axb", "16385x1", "-1x5", "10x10x10", "10X10"})
    usage_errors.push_back({render + " --size " + size, "--size"});
  for (const char* camera :
       {"garbage", "eye=0,0,1;target=0,0,0;up=0,1,0", "eye=0,0,1;target=0,0,0;up=0,1,0;fov=0",
        "eye=0,0,1;target=0,0,0;up=0,1,0;fov=180", "eye=0,0,0;target=0,0,0;up=0,1,0;fov=45",
        "eye=0,0,1;target=0,0,0;up=0,0,2;fov=45", "eye=0,0,1;target=0,0,0;up=0,0,0;fov=45",
        "eye=nan,0,1;target=0,0,0;up=0,1,0;fov=45", "eye=0,0;target=0,0,0;up=0,1,0;fov=45",
        "eye=0,0,1;target=0,0,0;up=0,1,0;fov=45;fov=50",
        "eye=0,0,1e39;target=0,0,0;up=0,1,0;fov=45",
        "eye=0,0,1;target=0,0,0;up=0,1,0;fov=45;zoom=2"})
    usage_errors.push_back({render + " --camera " + quoted(camera), "--camera"});
  for (const auto& [args, mention] : usage_errors) {
    SCOPED_TRACE(args);
    expect_failure(run(args), 2, mention);
  }
}

TEST(Cli, BenchOutputDirectoryThatCannotBeMadeExitsOne) {
  // A regular file where the directory should go: refused before anything is measured.
  const std::string file = temp_path("bench-out-file");
  { std::ofstream(file) << "x"; }
  const Outcome result = run("bench --quick --accels bvh --out " + quoted(file + "/sub"));
  expect_failure(result, 1, file);
}

// The bench's progress on stderr (a file here, not a terminal): progress lines with the time
// left and a summary, or with --verbose every step's line. A tiny sphere, one structure, one
// thread: the quickest bench there is.
TEST(Cli, BenchPrintsProgressLinesOrWithVerboseEveryStep) {
  const std::string scene = temp_path("bench-progress.obj");
  gs::export_obj(gs::test::make_sphere({0.0f, 0.0f, 0.0f}, 1.0f, 6, 8), scene);
  const std::string bench =
      "bench --quick --accels bvh --threads 1 --scenes " + quoted(scene) + " --out ";
  const auto count = [](const std::string& text, const std::string& part) {
    size_t n = 0;
    for (size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
    return n;
  };
  const std::string out = temp_path("bench-progress");
  const Outcome plain = run(bench + quoted(out));
  ASSERT_EQ(plain.status, 0) << plain.err;
  const std::string verbose_out = temp_path("bench-progress-verbose");
  const Outcome verbose = run(bench + quoted(verbose_out) + " --verbose");
  ASSERT_EQ(verbose.status, 0) << verbose.err;

  // Every measurement record (its rays per second a number: not the convergence curve's) is a
  // step with its own line (Mrays/s) under --verbose only.
  size_t measured = 0;
  for (const nlohmann::json& r : nlohmann::json::parse(slurp(verbose_out + "/results.json")))
    measured += r.contains("rays_per_second") && r["rays_per_second"].is_number();
  ASSERT_GT(measured, 0u);
  EXPECT_EQ(count(verbose.err, "Mrays/s"), measured) << verbose.err;
  EXPECT_EQ(count(plain.err, "Mrays/s"), 0u) << plain.err;
  EXPECT_EQ(count(verbose.err, "ETA"), 0u) << verbose.err;
  // The summary, the log's last progress line and --verbose's summary count the same steps,
  // all of those planned.
  std::smatch summary;
  ASSERT_TRUE(
      std::regex_search(plain.err, summary, std::regex(R"(bench: (\d+) of (\d+) steps in \d+s\n)")))
      << plain.err;
  const std::string steps = summary[1].str();
  EXPECT_EQ(summary[2].str(), steps);
  EXPECT_NE(plain.err.find("bench: " + steps + "/" + steps + " steps (100%)"), std::string::npos)
      << plain.err;
  EXPECT_NE(plain.err.find("ETA"), std::string::npos);
  EXPECT_NE(verbose.err.find("bench: " + steps + " of " + steps + " steps in"), std::string::npos)
      << verbose.err;
}

TEST(Cli, CostsFileSetsTheFiveConstantsAndLaterFlagsWin) {
  const std::string costs = temp_path("costs.json"), stats = temp_path("costs-stats.json");
  {
    std::ofstream(costs) << R"({"intcost": 2, "repcost": 0.5, "travcost": 3, "vertcost": 4,)"
                         << R"( "subcost": 5, "detail": {}})";
  }
  const Outcome result =
      run("render builtin:pyramid --size 8x8 --out " + quoted(temp_path("costs.png")) +
          " --costs " + quoted(costs) + " --travcost 7 --stats " + quoted(stats));
  ASSERT_EQ(result.status, 0) << result.err;
  const nlohmann::json parameters = nlohmann::json::parse(slurp(stats))["parameters"];
  EXPECT_EQ(parameters["intcost"], 2.0);
  EXPECT_EQ(parameters["repcost"], 0.5);
  EXPECT_EQ(parameters["travcost"], 7.0);
  EXPECT_EQ(parameters["vertcost"], 4.0);
  EXPECT_EQ(parameters["subcost"], 5.0);
  { std::ofstream(costs) << R"({"intcost": 2})"; }
  expect_failure(run("render builtin:pyramid --out x.png --costs " + quoted(costs)), 1, costs);
}

TEST(Cli, HelpExitsZero) {
  const Outcome result = run("--help");
  EXPECT_EQ(result.status, 0);
  EXPECT_NE(result.out.find("gridscope trace"), std::string::npos);
}

TEST(Cli, ExportWritesEveryTriangle) {
  const std::string out = temp_path("pyramid.obj");
  const Outcome result = run("export builtin:pyramid --out " + quoted(out));
  ASSERT_EQ(result.status, 0) << result.err;
  std::istringstream text(slurp(out));
  int faces = 0;
  for (std::string line; std::getline(text, line);) faces += line.rfind("f ", 0) == 0;
  EXPECT_EQ(faces, 4096);
}

// The vertices and faces of an OBJ that export wrote ("v x y z", "f a b c" lines).
struct ObjText {
  std::vector<glm::vec3> vertices;
  int faces = 0;
};
ObjText read_obj_text(const std::string& path) {
  ObjText obj;
  std::istringstream text(slurp(path));
  for (std::string line; std::getline(text, line);) {
    std::istringstream words(line);
    std::string tag;
    words >> tag;
    if (tag == "f") ++obj.faces;
    if (tag != "v") continue;
    glm::vec3 v;
    words >> v.x >> v.y >> v.z;
    obj.vertices.push_back(v);
  }
  return obj;
}

// `export suite:f15` writes the bench's F-15 scene: the mesh as it is, then a ground square of
// two triangles half a unit below its lowest point (bench/scenes.cpp), and prints the bench's
// camera, which `rays --camera` takes as it is.
TEST(Cli, ExportOfASuiteSceneIsTheBenchsComposition) {
  const std::string f15 = gs::test::asset_file("f15/f15.obj");
  if (f15.empty()) GTEST_SKIP() << gs::test::missing_asset("f15/f15.obj");
  const std::string plain = temp_path("f15_plain.obj"), suite = temp_path("f15_suite.obj");
  ASSERT_EQ(run("export " + quoted(f15) + " --out " + quoted(plain)).status, 0);
  const Outcome result =
      gs::test::run_gridscope("export suite:f15 --out " + quoted(suite),
                              "env GRIDSCOPE_ASSETS=" + quoted(gs::test::assets_dir()));
  ASSERT_EQ(result.status, 0) << result.err;
  const ObjText mesh = read_obj_text(plain), scene = read_obj_text(suite);
  ASSERT_EQ(scene.faces, mesh.faces + 2);
  ASSERT_EQ(scene.vertices.size(), mesh.vertices.size() + 4);
  float lowest = std::numeric_limits<float>::infinity();
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    EXPECT_EQ(scene.vertices[i], mesh.vertices[i]) << i;
    lowest = std::min(lowest, mesh.vertices[i].z);
  }
  for (size_t i = mesh.vertices.size(); i < scene.vertices.size(); ++i)
    EXPECT_FLOAT_EQ(scene.vertices[i].z, lowest - 0.5f) << i;
  ASSERT_EQ(result.out.rfind("camera ", 0), 0u) << result.out;
  const std::string camera = result.out.substr(7, result.out.find('\n') - 7);
  EXPECT_EQ(result.out.find("light"), std::string::npos) << result.out;
  EXPECT_EQ(run("rays " + quoted(suite) + " --size 4x4 --camera " + quoted(camera) + " --out " +
                quoted(temp_path("f15_suite.rays")))
                .status,
            0);
}

TEST(Cli, ExportOfAnUnknownSuiteSceneIsAnInputError) {
  expect_failure(run("export suite:stadium --out " + quoted(temp_path("stadium.obj"))), 1,
                 "suite:stadium");
}

// `trace --walk 5` re-traces ray 5 ("from above", hand-computed: id 1 at t = 3) with the
// recorder: the walk ends on that hit, cell after cell.
TEST(Cli, WalkOfOneRayEndsOnItsHit) {
  const std::vector<Case> cases = hand_cases();
  const std::string rays = ray_file("walk.rays", rays_of(cases));
  const std::string walk = temp_path("walk.json");
  const Outcome result = run(trace_args(two_triangles(), rays, temp_path("walk.hits")) +
                             " --accel grid1d --walk 5 --walk-out " + quoted(walk));
  ASSERT_EQ(result.status, 0) << result.err;
  const nlohmann::json json = nlohmann::json::parse(slurp(walk));
  EXPECT_EQ(json["hit"]["id"], 1);
  EXPECT_FLOAT_EQ(json["hit"]["t"].get<float>(), 3.0f);
  EXPECT_EQ(json["ray"]["origin"][2], 5.0f);
  const nlohmann::json& cells = json["cells"];
  ASSERT_GE(cells.size(), 1u);
  EXPECT_EQ(json["steps"], cells.size());
  EXPECT_EQ(cells.back()["hit"], 1);
  EXPECT_EQ(cells[0]["entered_axis"], -1);
  for (const nlohmann::json& cell : cells) {
    EXPECT_TRUE(cell["descents"].is_array());
    for (int a = 0; a < 3; ++a) EXPECT_LE(cell["lo"][a], cell["hi"][a]);
  }
  // The walk needs cells (brute has none), a ray that exists, and both flags.
  expect_failure(run(trace_args(two_triangles(), rays, temp_path("walk.hits")) +
                     " --accel brute --walk 0 --walk-out " + quoted(walk)),
                 2, "--walk");
  expect_failure(run(trace_args(two_triangles(), rays, temp_path("walk.hits")) +
                     " --walk 14 --walk-out " + quoted(walk)),
                 1, rays);
  expect_failure(run(trace_args(two_triangles(), rays, temp_path("walk.hits")) + " --walk 0"), 2,
                 "--walk-out");
}

// --sample-image WxH samples a ray file of that image's primary rays as `render` samples the
// image; a file of another size is refused naming it.
TEST(Cli, SampleImageNeedsTheImagesRays) {
  const std::string rays = temp_path("image.rays");
  ASSERT_EQ(run("rays builtin:pyramid --size 24x16 --out " + quoted(rays)).status, 0);
  const std::string stats = temp_path("image.json");
  const Outcome good = run(trace_args("builtin:pyramid", rays, temp_path("image.hits")) +
                           " --sample-image 24x16 --stats " + quoted(stats));
  ASSERT_EQ(good.status, 0) << good.err;
  EXPECT_EQ(nlohmann::json::parse(slurp(stats))["rays"], 24 * 16);
  expect_failure(
      run(trace_args("builtin:pyramid", rays, temp_path("image.hits")) + " --sample-image 24x15"),
      1, rays);
  expect_failure(
      run(trace_args("builtin:pyramid", rays, temp_path("image.hits")) + " --sample-image 24"), 2,
      "--sample-image");
}

// --packets N gives the hits of single rays, byte for byte, as consecutive rays or as the
// image's k x k tiles, and reports its packets; a structure without packet traversal, N out
// of range, and N not a square with --sample-image are usage errors.
TEST(Cli, PacketsGiveTheHitsOfSingleRays) {
  const std::string rays = temp_path("packets.rays");
  ASSERT_EQ(run("rays builtin:pyramid --size 40x24 --out " + quoted(rays)).status, 0);
  const std::string single = temp_path("single.hits"), tiles = temp_path("tiles.hits"),
                    rows = temp_path("rows.hits"), stats = temp_path("packets.json");
  const std::string image = " --sample-image 40x24";
  ASSERT_EQ(run(trace_args("builtin:pyramid", rays, single) + image).status, 0);
  const Outcome tiled = run(trace_args("builtin:pyramid", rays, tiles) + image +
                            " --packets 64 --stats " + quoted(stats));
  ASSERT_EQ(tiled.status, 0) << tiled.err;
  ASSERT_EQ(run(trace_args("builtin:pyramid", rays, rows) + " --packets 7").status, 0);
  EXPECT_EQ(slurp(single).size(), 40u * 24u * 16u);
  EXPECT_TRUE(slurp(single) == slurp(tiles));
  EXPECT_TRUE(slurp(single) == slurp(rows));
  const nlohmann::json json = nlohmann::json::parse(slurp(stats));
  EXPECT_EQ(json["parameters"]["packets"], 64);
  EXPECT_GT(json["packets"].get<uint64_t>(), 0u);
  EXPECT_LE(json["packets"].get<uint64_t>(), 15u);  // 5 x 3 tiles of 8 x 8
  EXPECT_GT(json["packet_steps"].get<uint64_t>(), 0u);
  const double active = json["packet_active_fraction"].get<double>();
  EXPECT_GT(active, 0.0);
  EXPECT_LE(active, 1.0);
  expect_failure(run(trace_args("builtin:pyramid", rays, rows) + " --packets 16 --accel bvh"), 2,
                 "--packets");
  expect_failure(run(trace_args("builtin:pyramid", rays, rows) + " --packets 65"), 2, "--packets");
  expect_failure(run(trace_args("builtin:pyramid", rays, rows) + image + " --packets 10"), 2,
                 "--packets");
}

// A camera at (0,0,5) looking down -z with a 90° vertical field of view: the centre of pixel
// (x, y) of a 4x2 image lies at NDC ((x + 0.5) / 2 - 1, 1 - (y + 0.5)), so its ray runs
// along (2 * ndc_x, ndc_y, -1) (aspect 2, tan 45° = 1).
TEST(Cli, RaysWritesThePixelCentreRays) {
  const std::string out = temp_path("camera.rays");
  const Outcome result = run("rays " + quoted(two_triangles()) + " --size 4x2 --out " +
                             quoted(out) + " --camera 'eye=0,0,5;target=0,0,0;up=0,1,0;fov=90'");
  ASSERT_EQ(result.status, 0) << result.err;
  const std::vector<gs::Ray> rays = gs::read_rays(out);
  ASSERT_EQ(rays.size(), 8u);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x) {
      const gs::Ray& ray = rays[size_t(y * 4 + x)];
      EXPECT_EQ(ray.origin, glm::vec3(0, 0, 5));
      const glm::vec3 expected(2.0f * ((x + 0.5f) / 2.0f - 1.0f), 1.0f - (y + 0.5f), -1.0f);
      EXPECT_NEAR(glm::length(glm::cross(glm::normalize(ray.dir), glm::normalize(expected))), 0.0f,
                  1e-6f)
          << "pixel " << x << "," << y;
      EXPECT_GT(glm::dot(ray.dir, expected), 0.0f);
    }
}

uint32_t big_endian(const std::string& bytes, size_t at) {
  uint32_t value = 0;
  for (size_t k = 0; k < 4; ++k) value = value << 8 | uint8_t(bytes[at + k]);
  return value;
}

TEST(Cli, RenderWritesPngOfRequestedSize) {
  const std::string out = temp_path("size.png");
  const Outcome result =
      run("render " + quoted(two_triangles()) + " --accel brute --size 37x23 --out " + quoted(out));
  ASSERT_EQ(result.status, 0) << result.err;
  EXPECT_EQ(result.out, out + "\n");
  const std::string png = slurp(out);
  ASSERT_GE(png.size(), 24u);
  EXPECT_EQ(png.substr(0, 8), "\x89PNG\r\n\x1a\n");
  EXPECT_EQ(png.substr(12, 4), "IHDR");
  EXPECT_EQ(big_endian(png, 16), 37u);
  EXPECT_EQ(big_endian(png, 20), 23u);
}

// A quad covering y <= 0 of the plane z = 0, seen from (0,0,5) with a 90° field of view:
// the top half of the image looks above the quad's edge (background), the bottom half at it.
TEST(Cli, RenderShowsSurfaceAgainstBackground) {
  const std::string scene = write_temp_file(
      "quad.obj", "v -100 -100 0\nv 100 -100 0\nv 100 0 0\nv -100 0 0\nf 1 2 3 4\n");
  for (const char* spp : {"1", "4"}) {
    SCOPED_TRACE(spp);
    const std::string out = temp_path("quad.png");
    const std::string stats = temp_path("quad.json");
    const Outcome result = run("render " + quoted(scene) + " --accel brute --size 64x64 --spp " +
                               spp + " --camera 'eye=0,0,5;target=0,0,0;up=0,1,0;fov=90' --out " +
                               quoted(out) + " --stats=" + quoted(stats));
    ASSERT_EQ(result.status, 0) << result.err;
    // Rows 32..63 look down at the quad: one primary ray per sample, plus one shadow ray
    // for each of those since the whole quad faces the light.
    const nlohmann::json json = nlohmann::json::parse(slurp(stats));
    EXPECT_EQ(json["rays"], (64 * 64 + 64 * 32) * std::stoi(spp));
    EXPECT_EQ(json["parameters"]["camera"], "eye=0,0,5;target=0,0,0;up=0,1,0;fov=90");
    int w = 0, h = 0, n = 0;
    unsigned char* pixels = stbi_load(out.c_str(), &w, &h, &n, 4);
    ASSERT_NE(pixels, nullptr);
    ASSERT_EQ(w, 64);
    ASSERT_EQ(h, 64);
    auto pixel = [&](int x, int y) { return pixels + 4 * (y * w + x); };
    for (int x : {0, 32, 63}) {
      for (int k = 0; k < 3; ++k) EXPECT_EQ(pixel(x, 10)[k], gs::kBackground[k]) << x;
      // The quad faces the camera and the light is above and behind it: lit, well above
      // the background and the ambient-only level.
      for (int k = 0; k < 3; ++k) EXPECT_GT(pixel(x, 50)[k], 100) << x;
      EXPECT_EQ(pixel(x, 50)[3], 255);
    }
    stbi_image_free(pixels);
  }
}

// Jittered samples come from a fixed hash, and rows may go to any thread: the image must not
// depend on the thread count or the run.
TEST(Cli, RenderIsDeterministic) {
  std::vector<std::string> images;
  for (const char* threads : {"1", "3", "3"}) {
    const std::string out = temp_path(std::string("det-") + threads + ".png");
    const Outcome result =
        run("render builtin:pyramid --accel brute --size 40x30 --spp 3 --threads " +
            std::string(threads) + " --out " + quoted(out));
    ASSERT_EQ(result.status, 0) << result.err;
    images.push_back(slurp(out));
  }
  EXPECT_TRUE(images[0] == images[1]);
  EXPECT_TRUE(images[1] == images[2]);
}

// ---- Help, --version and the structure registry -----------------------------------------

// Whether `text` names `flag` as a whole word: "--walk" is not named by "--walk-out".
bool names(const std::string& text, const std::string& flag) {
  for (size_t at = text.find(flag); at != std::string::npos; at = text.find(flag, at + 1)) {
    const size_t end = at + flag.size();
    if (end == text.size() || !(std::isalnum(static_cast<unsigned char>(text[end])) ||
                                text[end] == '-' || text[end] == '_'))
      return true;
  }
  return false;
}

// Every flag every command's parser takes (the command list itself, not a hand list) is in
// `gridscope help`, in `gridscope COMMAND --help` and in README.md; so is every command.
TEST(Help, NamesEveryFlagOfEveryCommandAndReadmeDoesToo) {
  const Outcome help = run("help");
  ASSERT_EQ(help.status, 0) << help.err;
  const std::string readme = slurp(GRIDSCOPE_README);
  ASSERT_FALSE(readme.empty()) << GRIDSCOPE_README;
  const std::vector<gs::app::CommandFlags> commands = gs::app::command_flags();
  ASSERT_GE(commands.size(), 10u);
  size_t flags = 0;
  for (const gs::app::CommandFlags& command : commands) {
    const std::string synopsis = "gridscope " + command.command;
    EXPECT_TRUE(names(help.out, synopsis)) << synopsis;
    EXPECT_TRUE(names(readme, synopsis)) << synopsis << " is not in README.md";
    const Outcome own = run(command.command + " --help");
    ASSERT_EQ(own.status, 0) << command.command << ": " << own.err;
    for (const std::string& flag : command.flags) {
      EXPECT_TRUE(names(help.out, flag)) << flag << " of " << command.command << " not in help";
      EXPECT_TRUE(names(own.out, flag)) << flag << " not in " << command.command << " --help";
      EXPECT_TRUE(names(readme, flag)) << flag << " of " << command.command << " not in README";
      ++flags;
    }
  }
  EXPECT_GE(flags, 80u);  // the structure flags alone are 14 for each of 4 commands
}

TEST(Help, CommandHelpPrintsThatCommandAlone) {
  const Outcome trace = run("trace --help");
  ASSERT_EQ(trace.status, 0) << trace.err;
  EXPECT_EQ(trace.out.rfind("gridscope trace SCENE --rays FILE --out FILE", 0), 0u) << trace.out;
  for (const char* other : {"render", "shot", "view", "export", "rays", "bench", "calibrate"})
    EXPECT_FALSE(names(trace.out, std::string("gridscope ") + other)) << other;
  EXPECT_TRUE(names(trace.out, "--sample-image"));
  EXPECT_TRUE(names(trace.out, "--oracle"));
  EXPECT_FALSE(names(trace.out, "--bounces"));  // render's and shot's, not trace's
  EXPECT_EQ(run("help trace").out, trace.out);
  // A command without structure flags lists none, nor the structures.
  const Outcome rays = run("rays --help");
  ASSERT_EQ(rays.status, 0);
  EXPECT_FALSE(names(rays.out, "--intcost"));
  EXPECT_FALSE(names(rays.out, "--accel"));
  expect_failure(run("help frobnicate"), 2, "frobnicate");
}

// The defaults and caps the structures' headers and README give (octree.h, grid3d.h, bvh.h,
// grid1d.h), as `render --help` reports them for the flags the structures read.
TEST(Help, StructureFlagsNameTheirReadersAndDefaults) {
  const Outcome help = run("render --help");
  ASSERT_EQ(help.status, 0);
  std::string text = help.out;  // one line per flag entry: unwrap the continuation lines
  text = std::regex_replace(text, std::regex("\n {28}"), " ");
  const auto line_of = [&](const std::string& flag) {
    const size_t at = text.find("\n  " + flag + " ");
    if (at == std::string::npos) return std::string();
    return text.substr(at + 1, text.find('\n', at + 1) - at - 1);
  };
  const std::string leaf = line_of("--leaf-size");
  for (const char* reader : {"octree (default 4)", "grid3d (default 16)", "bvh (default 4)"})
    EXPECT_NE(leaf.find(reader), std::string::npos) << reader << " in: " << leaf;
  EXPECT_EQ(leaf.find("grid1d"), std::string::npos) << leaf;
  const std::string depth = line_of("--max-depth");
  for (const char* reader : {"octree (default 6, at most 20)", "grid3d (default 3, at most 16)",
                             "grid1d (default 32)", "bvh (default 64)"})
    EXPECT_NE(depth.find(reader), std::string::npos) << reader << " in: " << depth;
  EXPECT_NE(line_of("--density").find("Read by uniform (default"), std::string::npos);
  EXPECT_NE(line_of("--build-threads").find("Read by embree (default 0)"), std::string::npos);
  EXPECT_NE(line_of("--memory-budget").find("(default 8G)"), std::string::npos);
  EXPECT_NE(line_of("--costs").find("Read by grid1d."), std::string::npos);
}

TEST(Cli, VersionPrintsTheVersionAndTheCommit) {
  const Outcome result = run("--version");
  ASSERT_EQ(result.status, 0) << result.err;
  const std::regex line("gridscope " +
                        std::regex_replace(GRIDSCOPE_VERSION, std::regex("\\."), "\\.") +
                        " \\(commit ([0-9a-f]{40}|unknown)\\)\n");
  EXPECT_TRUE(std::regex_match(result.out, line)) << result.out;
  expect_failure(run("--version extra"), 2, "extra");
}

// OSMesa, and with it LLVM, is opened for a headless frame, not at start-up: linked, it cost
// every command about 60 ms (app/gl/headless.cpp). The dynamic loader lists what it loads.
// The sanitizer builds link it (app/gl/CMakeLists.txt says why).
TEST(Cli, OsMesaIsLoadedOnlyForAHeadlessFrame) {
  if (GRIDSCOPE_OSMESA_LINKED) GTEST_SKIP() << "this build links OSMesa";
  const Outcome start = gs::test::run_gridscope("--version", "env LD_DEBUG=files");
  ASSERT_EQ(start.status, 0) << start.err;
  EXPECT_NE(start.err.find("file="), std::string::npos) << "no loader listing: " << start.err;
  EXPECT_EQ(start.err.find("libOSMesa"), std::string::npos) << start.err;
  const Outcome shot = gs::test::run_gridscope(
      "shot builtin:pyramid --size 16x16 --out " + quoted(temp_path("osmesa.png")),
      "env LD_DEBUG=files");
  ASSERT_EQ(shot.status, 0) << shot.err;
  EXPECT_NE(shot.err.find("file=libOSMesa.so"), std::string::npos);
  EXPECT_NE(shot.err.find("dynamically loaded by"), std::string::npos);
}

// Which structure reads which flag, from the structures' own code (the parameters each
// constructor and cost model takes): a flag another structure reads is refused by name.
TEST(Cli, StructureFlagTheStructureDoesNotReadIsExitTwo) {
  const std::string render =
      "render builtin:pyramid --size 8x8 --out " + quoted(temp_path("r.png"));
  expect_failure(run(render + " --density 2"), 2, "--density: structure 'grid1d' does not use it");
  expect_failure(run(render + " --accel uniform --max-granularity 8"), 2,
                 "--max-granularity: structure 'uniform' does not use it");
  expect_failure(run(render + " --accel bvh --oracle " + quoted(temp_path("x.hits"))), 2,
                 "--oracle: structure 'bvh' does not use it");
  const std::string costs = gs::test::write_temp_file(
      "ignored-costs.json",
      R"({"intcost": 2, "repcost": 0.5, "travcost": 3, "vertcost": 4, "subcost": 5})");
  expect_failure(run(render + " --accel octree --costs " + quoted(costs)), 2,
                 "--costs: structure 'octree' does not use it");
  const std::string stats = temp_path("density.json");
  const Outcome read = run(render + " --accel uniform --density 2 --stats " + quoted(stats));
  ASSERT_EQ(read.status, 0) << read.err;
  EXPECT_EQ(nlohmann::json::parse(slurp(stats))["parameters"]["density"], 2.0);
}

std::vector<std::string> words_of(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> words;
  for (std::string word; in >> word;) words.push_back(word);
  return words;
}

// Whether parse_cli takes the command line (it reads no file but --costs's).
bool parses(const std::string& line) {
  try {
    gs::app::parse_cli(words_of(line));
    return true;
  } catch (const gs::UsageError&) {
    return false;
  }
}

TEST(Cli, EachStructureTakesExactlyTheFlagsItReads) {
  const std::string costs = gs::test::write_temp_file(
      "reader-costs.json",
      R"({"intcost": 2, "repcost": 0.5, "travcost": 3, "vertcost": 4, "subcost": 5})");
  const std::map<std::string, std::string> value = {
      {"--intcost", "2"},         {"--repcost", "0.5"},
      {"--travcost", "2"},        {"--vertcost", "3"},
      {"--subcost", "1"},         {"--costs", costs},
      {"--max-granularity", "8"}, {"--axis", "cost"},
      {"--max-depth", "3"},       {"--leaf-size", "2"},
      {"--density", "0.5"},       {"--memory-budget", "1M"},
      {"--sample-every", "4"},    {"--build-threads", "1"},
      {"--oracle", "x.hits"},     {"--max-root-granularity", "4"}};
  const std::vector<std::string> grid1d = {
      "--intcost",   "--repcost",       "--travcost",        "--vertcost",
      "--subcost",   "--costs",         "--max-granularity", "--axis",
      "--max-depth", "--memory-budget", "--sample-every",    "--max-root-granularity"};
  const std::vector<std::string> tree = {"--max-depth", "--leaf-size", "--memory-budget"};
  const std::map<std::string, std::vector<std::string>> reads = {
      {"grid1d", grid1d},    {"uniform", {"--density", "--memory-budget"}},
      {"octree", tree},      {"grid3d", tree},
      {"bvh", tree},         {"embree", {"--build-threads"}},
      {"zero", {"--oracle"}}};
  const std::vector<std::string> names = gs::accelerator_names();
  for (const gs::app::CommandFlags& command : gs::app::command_flags()) {
    if (command.command != "trace") continue;
    for (const std::string& flag : command.flags) {
      if (!gs::find_param(flag) && flag != "--costs") continue;
      ASSERT_TRUE(value.contains(flag)) << "no test value for structure flag " << flag;
      for (const std::string& accel : names) {
        const std::string line =
            "trace s.obj --rays r --out h --accel " + accel + " " + flag + " " + value.at(flag);
        const bool reader = accel == "brute" || std::ranges::count(reads.at(accel), flag) > 0;
        EXPECT_EQ(parses(line), reader) << line;
      }
    }
  }
}

// Values at the ends of a parameter's range (none for a choice or a path).
std::vector<double> range_ends(const gs::ParamSpec& spec) {
  switch (spec.kind) {
    case gs::ParamKind::integer:
      return {spec.lo - 1, spec.lo, spec.hi, spec.hi + 1};
    case gs::ParamKind::bytes:
      return {spec.hi, spec.hi + 1};
    case gs::ParamKind::number:
      return {spec.lo - 1, spec.lo, spec.lo + 0.5};
    default:
      return {};
  }
}

// One set of bounds: at the ends of every range, a value typed on the command line and the
// same value set by a program (make_accelerator's check) are both taken or both refused; 0,
// each structure's own default, is never typed.
TEST(Cli, CommandLineAndCheckParamsTakeTheSameValues) {
  int compared = 0;
  for (const gs::ParamSpec& spec : gs::param_table()) {
    const gs::Structure* reader = nullptr;
    for (const gs::Structure& s : gs::structures())
      if (s.available() && s.use(spec.param) && !reader) reader = &s;
    ASSERT_NE(reader, nullptr) << spec.flag;
    for (const double value : range_ends(spec)) {
      if (value == 0 && spec.zero_is_default) continue;
      if (spec.kind == gs::ParamKind::integer && value > std::numeric_limits<int>::max())
        continue;  // not an int field's value
      gs::AccelParams params;
      gs::set_param(params, spec.param, value);
      bool checked = true;
      try {
        gs::check_params(reader->name, params);
      } catch (const gs::UsageError&) {
        checked = false;
      }
      const std::string typed = spec.kind == gs::ParamKind::number
                                    ? std::to_string(value)
                                    : std::to_string(static_cast<long long>(value));
      const std::string line = "trace s.obj --rays r --out h --accel " + reader->name + " " +
                               std::string(spec.flag) + " " + typed;
      EXPECT_EQ(parses(line), checked) << line;
      ++compared;
    }
  }
  EXPECT_GE(compared, 30);
  EXPECT_FALSE(parses("trace s.obj --rays r --out h --accel octree --max-depth 0"));
  EXPECT_FALSE(parses("trace s.obj --rays r --out h --accel uniform --density 0"));
  EXPECT_TRUE(parses("trace s.obj --rays r --out h --accel octree --max-depth 20"));
  EXPECT_FALSE(parses("trace s.obj --rays r --out h --accel octree --max-depth 21"));
}

TEST(Registry, ListsEveryStructureOnceInReportOrderWithItsOwnName) {
  std::vector<std::string> expected = {"uniform", "octree", "grid3d", "grid1d", "bvh"};
  const std::vector<std::string> names = gs::accelerator_names();
  if (std::ranges::count(names, "embree")) expected.push_back("embree");
  expected.insert(expected.end(), {"brute", "zero"});
  EXPECT_EQ(names, expected);
  gs::AccelParams params;
  params.oracle_path = "x.hits";  // zero is made with its oracle's path, read at build
  for (const std::string& name : names) {
    const auto accel = gs::make_accelerator(name, params);
    EXPECT_EQ(accel->name(), name);
    // The bench measures packets of the structures the registry says walk them.
    EXPECT_EQ(gs::find_structure(name)->traces_packets, accel->traces_packets()) << name;
  }
}

}  // namespace
