// Helpers shared by the test suites: the assets folder (real scenes), temporary files, scenes
// and ray sets made in code, and tracing a ray set through a structure.
#pragma once
#include <cstdint>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "core/accel/accelerator.h"
#include "core/geometry/ray.h"
#include "core/scene/scene.h"

namespace gs::test {

// A ray file's or hit file's infinity (float records).
inline constexpr float kInf = std::numeric_limits<float>::infinity();

// The folder real scenes are read from: $GRIDSCOPE_ASSETS when set, else the source tree's
// assets/ (assets/README.md lists its files).
std::string assets_dir();
// Path of a scene file in assets_dir(), e.g. "bunny/stanford-bunny.obj", or "" when it is not
// there (callers GTEST_SKIP with missing_asset's message).
std::string asset_file(const std::string& relative);
// Why asset_file(relative) is "": the path looked at and the script that fetches the scenes
// git does not hold.
std::string missing_asset(const std::string& relative);
// A fresh path under the system temp folder; the file is not created.
std::string temp_path(const std::string& name);
// The whole file ("" when it cannot be read).
std::string slurp(const std::string& path);
// Single-quoted for the shell.
std::string quoted(const std::string& word);

// Runs a shell command under a time limit, so a hung program fails its test instead of
// stalling the suite, and collects its exit status and output.
struct CommandOutcome {
  int status = -1;
  std::string out, err;
};
CommandOutcome run_command(const std::string& command);
// Runs `prefix gridscope args` (args quoted where needed) with run_command.
CommandOutcome run_gridscope(const std::string& args, const std::string& prefix = "");

// A PNG decoded to RGBA8 (empty when it cannot be read).
struct Png {
  int width = 0, height = 0;
  std::vector<unsigned char> rgba;
  const unsigned char* at(int x, int y) const { return &rgba[(size_t(y) * width + x) * 4]; }
};
Png load_png(const std::string& path);
// Whether a pixel has the walk overlay's magenta (kWalkColor in core/render/overlay.h): red
// and blue high, green well below both. Grey shading and the structure overlays' colours,
// blended over it or not, never have.
bool walk_coloured(const unsigned char* rgba);
// How many of the PNG's pixels have it.
int walk_pixels(const Png& png);

// `bytes` written to temp_path(name); returns that path.
std::string write_temp_file(const std::string& name, const std::string& bytes);
// The message of the InputError `run` throws ("" when it throws none).
std::string input_error(const std::function<void()>& run);

// Appends triangle a, b, c (three vertices of its own) to `scene`.
void add_triangle(Scene& scene, glm::vec3 a, glm::vec3 b, glm::vec3 c);
// A closed UV sphere with shared vertices (poles included), `rings` x `segments`.
Scene make_sphere(glm::vec3 centre, float radius, int rings, int segments);
// `count` random triangles of size about `size` inside [lo, hi].
Scene make_soup(uint32_t seed, int count, glm::vec3 lo, glm::vec3 hi, float size);
// Appends b's triangles (and vertices) after a's.
Scene merge(const Scene& a, const Scene& b);
// Every vertex mapped by p -> p * scale + offset.
Scene transformed(const Scene& scene, float scale, glm::vec3 offset);

// Dense detail in a small region (a sphere and `detail` small triangles in [-1, 1]^3) inside
// a 1000x larger box of a few big triangles: "teapot in a stadium".
Scene stadium_scene(int detail);
// Quads exactly in the planes x = k/8 and y = k/8 of a unit box (on the walls of every
// power-of-two cut, where rays hit them exactly) among small triangles.
Scene wall_planes_scene();

// A scene, rays through it and brute force's answers: what each structure's suite compares
// with.
struct BruteCase {
  std::string name;
  Scene scene;
  std::vector<Ray> rays;
  std::vector<Hit> expected;
};
std::vector<Hit> brute_answers(const Scene& scene, const std::vector<Ray>& rays);

// Ray sets over a scene's box.
std::vector<Ray> camera_rays(const Box& box, int width, int height);
std::vector<Ray> random_chords(const Box& box, uint32_t seed, int count);
std::vector<Ray> axis_parallel_rays(const Box& box, uint32_t seed, int count);
// Rays from far away aimed exactly at triangle vertices and at points on triangle edges.
std::vector<Ray> edge_and_vertex_rays(const Scene& scene, uint32_t seed, int count);

// Traces every ray with `threads` threads, each with its own context; with packet > 0, in
// packets of `packet` consecutive rays (Accelerator::trace_packet).
std::vector<Hit> trace_all(const Accelerator& accel, const std::vector<Ray>& rays, int threads,
                           bool any_hit = false, size_t packet = 0);

}  // namespace gs::test
