// The scene-and-ray cases the structure suites share, and the driver that compares
// structures with brute force on them: every exact structure must give brute's answers
// (same id, t, u and v) on every ray, lazy or eager, with one thread or two.
#pragma once
#include <cstdint>
#include <functional>
#include <ostream>
#include <span>
#include <string>
#include <vector>

#include "core/accel/accelerator.h"
#include "core/geometry/ray.h"
#include "core/scene/scene.h"
#include "tests/structure_run.h"
#include "tests/test_util.h"

namespace gs::test {

// ---------------------------------------------------------------------------------------
// Scenes

struct NamedScene {
  std::string name;
  Scene scene;
};

// A finely tessellated sphere (24 x 48) in a soup of 1,500 triangles: "sphere+soup".
Scene sphere_in_soup();
// A coarser sphere (16 x 32) in a soup of `soup_triangles` smaller triangles.
Scene small_sphere_in_soup(int soup_triangles = 1200);
// The four scenes the structure suites compare on: builtin "pyramid", "sphere+soup",
// "stadium" (stadium_scene(stadium_detail)) and "wall planes" (the suite's own triangles on
// its structure's cell walls).
std::vector<NamedScene> comparison_scenes(int stadium_detail, Scene wall_planes);
// transformed(base, scale, offset), named by its transform.
NamedScene scaled_and_moved(const Scene& base, float scale, glm::vec3 offset);
// `base` scaled by 1e-4 and by 1e4, and moved a million units from the origin (where float
// spacing is 1/16).
std::vector<NamedScene> moved_and_scaled(const Scene& base);
// 5,000 copies of one triangle among 300 others: no cut can separate them.
Scene coincident_scene();
// 3,000 small triangles all in the plane z = 0: zero extent along z.
Scene flat_scene();
// 1,500 long thin slivers filling a 100 x 2 x 2 box.
Scene sliver_scene();
// The triangle (0,0,0) (1,0,0) (0,1,0).
Scene one_triangle();

// ---------------------------------------------------------------------------------------
// Rays

// How many rays of each kind mixed_rays makes (in this order), and the random ones' seeds.
struct RayMix {
  int camera_width = 0, camera_height = 0;  // camera_rays
  int chords = 0;                           // random_chords
  int axis_parallel = 0;                    // axis_parallel_rays
  int edges_and_vertices = 0;               // edge_and_vertex_rays
  uint32_t chord_seed = 1, axis_seed = 2, edge_seed = 3;
  size_t camera_count() const { return size_t(camera_width) * size_t(camera_height); }
};
// The mix's camera rays, chords and axis-parallel rays over `box`, then its rays aimed at
// the scene's edges and vertices.
std::vector<Ray> mixed_rays(const Scene& scene, const Box& box, const RayMix& mix);
std::vector<Ray> mixed_rays(const Scene& scene, const RayMix& mix);  // over the scene's box

// Component i % 3 of every `step`-th ray i set to -0 (odd i) or 1e-30 (even i): the 1/d
// arithmetic's hardest inputs.
void set_negative_zero_or_tiny_components(std::span<Ray> rays, size_t step);
// Chords with such a component each, and -1e-30 in the next component of every fifth.
std::vector<Ray> negative_zero_and_tiny_chords(const Box& box, uint32_t seed, int count);
// Chords through [-1, 1]^3 (around the flat scene's box, which has no depth) and rays aimed
// at the edges and vertices of `flat` (flat_scene()).
std::vector<Ray> flat_scene_rays(const Scene& flat, int chords, int edges_and_vertices);
// side x side rays along +z, 0.01 apart, from the corner (-9, -9, -11): a view of one
// corner of a scene filling [-10, 10]^3.
std::vector<Ray> corner_view_rays(int side);

// ---------------------------------------------------------------------------------------
// Comparison with brute force

// Each scene with its rays (`rays_of`) and brute force's answers.
std::vector<BruteCase> brute_cases(
    std::vector<NamedScene> scenes,
    const std::function<std::vector<Ray>(const NamedScene&)>& rays_of);

// The rays whose `hits` differ from brute's `expected`; the first few are reported as
// failures of the running test, headed by `what`.
size_t count_mismatches(const std::string& what, const std::vector<Hit>& hits,
                        const std::vector<Hit>& expected);
// The rays whose any-hit answers break the any-hit rule against brute's nearest hits: a hit
// iff brute finds one, within the ray's (tmin, tmax], never nearer than the nearest.
size_t count_any_hit_mismatches(const std::vector<Ray>& rays, const std::vector<Hit>& hits,
                                const std::vector<Hit>& expected);

// "grid1d eager, 2 threads": a run as failure messages name it.
std::string describe(const StructureRun& run);
// How GoogleTest prints a run that parameterises a test.
inline void PrintTo(const StructureRun& run, std::ostream* out) { *out << describe(run); }
// The runs that check one structure both ways: lazy and eager, each traced by 1 and 2
// threads, no sampling pass.
std::vector<StructureRun> lazy_and_eager_runs(const std::string& accel,
                                              const AccelParams& params = {});
// Each run built over `scene` (its sampling pass over `rays`) and traced: the (run, ray)
// pairs whose answers differ from `expected` (brute's when not given).
size_t disagreements(const Scene& scene, const std::vector<Ray>& rays,
                     const std::vector<StructureRun>& runs, const std::vector<Hit>& expected);
size_t disagreements(const Scene& scene, const std::vector<Ray>& rays,
                     const std::vector<StructureRun>& runs);

enum class Answers { nearest, any_hit };
// `run` built over every case and traced: expects brute's nearest hits on every ray (then
// calls `check` on the structure), or with Answers::any_hit the any-hit rule. Returns the
// rays checked.
using StructureCheck = std::function<void(const BruteCase&, const Accelerator&)>;
size_t expect_brute_answers(const std::vector<BruteCase>& cases, const StructureRun& run,
                            Answers answers, const StructureCheck& check = {});

// `accel` built with default parameters: over an empty scene every ray misses and no rays
// give no answers; over one_triangle() a ray along +z through (0.2, 0.3) hits it at t 0.5
// with u 0.2, v 0.3.
void expect_empty_and_one_triangle_answers(const std::string& accel, const std::vector<Ray>& rays);

}  // namespace gs::test
