#include "bench/scenes.h"

#include <cstdlib>
#include <filesystem>
#include <glm/geometric.hpp>

#include "core/accel/accelerator.h"
#include "core/base/error.h"

namespace gs {

namespace {

namespace fs = std::filesystem;

// Appends `part` to `scene`, each vertex scaled by `scale` and moved by `offset`; the part's
// triangles take the ids after the scene's.
void append_part(Scene& scene, const Scene& part, float scale, const glm::vec3& offset) {
  const auto base = uint32_t(scene.vertices.size());
  for (const glm::vec3& v : part.vertices) scene.vertices.push_back(v * scale + offset);
  for (const glm::uvec3& t : part.triangles) scene.triangles.push_back(t + glm::uvec3(base));
}

// Two triangles: a square of half-size `half` at height z around (cx, cy), facing +z.
Scene ground_quad(float cx, float cy, float z, float half) {
  Scene quad;
  quad.vertices = {{cx - half, cy - half, z},
                   {cx + half, cy - half, z},
                   {cx + half, cy + half, z},
                   {cx - half, cy + half, z}};
  quad.triangles = {{0, 1, 2}, {0, 2, 3}};
  return quad;
}

// Where a ray from `origin` straight down (-y) first meets the scene: the cathedral's floor.
float floor_below(const Scene& scene, const glm::vec3& origin) {
  auto brute = make_accelerator("brute", AccelParams{});
  brute->build(scene);
  auto context = brute->make_context();
  Ray ray;
  ray.origin = origin;
  ray.dir = {0.0f, -1.0f, 0.0f};
  const Hit hit = brute->intersect(ray, *context);
  return hit.found() ? origin.y - hit.t : scene.bounds().lo.y;
}

// The trike role (irregular extents of complexity): the Stanford bunny, 3 units tall, on the
// floor of the Sibenik cathedral (y up), seen from down the nave.
BenchScene bunny_in_sibenik(const fs::path& assets) {
  Scene scene = load_scene((assets / "sibenik" / "sibenik.obj").string());
  const Scene bunny = load_scene((assets / "bunny" / "stanford-bunny.obj").string());
  const Box cathedral = scene.bounds(), rabbit = bunny.bounds();
  const float scale = 3.0f / (rabbit.hi.y - rabbit.lo.y);
  const float floor = floor_below(scene, 0.5f * (cathedral.lo + cathedral.hi));
  const glm::vec3 foot = 0.5f * (rabbit.lo + rabbit.hi) * scale;
  const glm::vec3 offset(-foot.x, floor - rabbit.lo.y * scale, -foot.z);
  append_part(scene, bunny, scale, offset);
  scene.name = "bunny-sibenik";
  Camera camera;
  camera.target = {0.0f, floor + 1.5f, 0.0f};
  camera.eye = {-13.0f, floor + 5.0f, 3.0f};
  camera.up = {0.0f, 1.0f, 0.0f};
  camera.fov = 50.0f;
  BenchScene bench{"bunny-sibenik", "trike", true, std::make_shared<const Scene>(std::move(scene)),
                   camera};
  // Under the vault above the crossing: light from outside would leave the nave in shadow.
  bench.light = glm::vec3(-6.0f, floor + 12.0f, 1.0f);
  return bench;
}

// The car role (a central object in modest extents): the F-15 (z up) over a ground square
// three times its length, seen from above and to the front-left.
BenchScene f15_on_ground(const fs::path& assets) {
  Scene scene = load_scene((assets / "f15" / "f15.obj").string());
  const Box plane = scene.bounds();
  const glm::vec3 centre = 0.5f * (plane.lo + plane.hi);
  const float length = glm::length(plane.hi - plane.lo);
  append_part(scene, ground_quad(centre.x, centre.y, plane.lo.z - 0.5f, 1.5f * length), 1.0f,
              glm::vec3(0.0f));
  scene.name = "f15";
  Camera camera;
  camera.target = centre;
  camera.eye = centre + glm::vec3(-0.9f, -0.8f, 0.5f) * length;
  camera.up = {0.0f, 0.0f, 1.0f};
  camera.fov = 40.0f;
  return {"f15", "car", true, std::make_shared<const Scene>(std::move(scene)), camera};
}

BenchScene mesh_scene(const fs::path& path, const std::string& label, const std::string& role) {
  auto scene = std::make_shared<Scene>(load_scene(path.string()));
  scene->name = label;
  return {label, role, true, std::move(scene), std::nullopt};
}

BenchScene builtin_scene(const std::string& label) {
  BenchScene bench{label, label, label != "pyramid",
                   std::make_shared<const Scene>(load_scene("builtin:" + label)), std::nullopt};
  // The cluster at the stadium's centre, from inside the stadium (scripts/run.sh's view).
  if (label == "lumpy")
    bench.camera = parse_camera("eye=3.2,-4.2,2.2;target=0,0,0.35;up=0,0,1;fov=40");
  return bench;
}

// The files a suite scene needs, relative to the assets folder.
std::vector<std::string> suite_files(const std::string& name) {
  if (name == "dragon") return {"dragon/dragon_vrip_res3.ply"};
  if (name == "dragon-full") return {"dragon/dragon_vrip.ply.gz"};
  if (name == "bunny-sibenik") return {"sibenik/sibenik.obj", "bunny/stanford-bunny.obj"};
  if (name == "f15") return {"f15/f15.obj"};
  return {};
}

// Why a suite scene cannot run, and what fixes it.
std::string missing_files_reason(const std::string& name, const std::string& assets_dir,
                                 const std::string& file) {
  const std::string fix = "scripts/fetch-assets.sh fetches the scenes git does not hold";
  if (assets_dir.empty())
    return name + ": no assets folder (run from the source tree or set GRIDSCOPE_ASSETS; " + fix +
           ")";
  return name + ": " + (fs::path(assets_dir) / file).string() + " is missing (" + fix + ")";
}

}  // namespace

std::string find_assets_dir() {
  if (const char* env = std::getenv("GRIDSCOPE_ASSETS"); env && *env) return env;
  std::error_code error;
  return fs::is_directory("assets", error) ? fs::absolute("assets", error).string() : std::string();
}

std::vector<std::string> bench_suite(bool quick) {
  if (quick) return {"pyramid", "lumpy"};
  return {"pyramid", "lumpy", "dragon", "bunny-sibenik", "f15", "dragon-full"};
}

std::optional<BenchScene> load_bench_scene(const std::string& name, const std::string& assets_dir,
                                           std::string& skipped) {
  if (name == "pyramid" || name == "lumpy") return builtin_scene(name);
  const std::vector<std::string> files = suite_files(name);
  if (files.empty()) {
    auto scene = std::make_shared<const Scene>(load_scene(name));
    return BenchScene{name, "", std::nullopt, std::move(scene), std::nullopt};
  }
  const fs::path assets(assets_dir);
  for (const std::string& file : files)
    if (assets_dir.empty() || !fs::exists(assets / file)) {
      skipped = missing_files_reason(name, assets_dir, file);
      return std::nullopt;
    }
  if (name == "bunny-sibenik") return bunny_in_sibenik(assets);
  if (name == "f15") return f15_on_ground(assets);
  return mesh_scene(assets / files.front(), name, name == "dragon" ? "drum" : "scale");
}

}  // namespace gs
