#include "tests/test_util.h"

#include <stb/stb_image.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <glm/geometric.hpp>
#include <numeric>
#include <span>
#include <sstream>
#include <thread>

#include "core/accel/brute.h"
#include "core/base/error.h"

namespace gs::test {

std::string assets_dir() {
  const char* env = std::getenv("GRIDSCOPE_ASSETS");
  return env && *env ? env : GRIDSCOPE_SOURCE_ASSETS;
}

std::string asset_file(const std::string& relative) {
  const std::filesystem::path path = std::filesystem::path(assets_dir()) / relative;
  return std::filesystem::exists(path) ? path.string() : std::string();
}

std::string missing_asset(const std::string& relative) {
  return (std::filesystem::path(assets_dir()) / relative).string() +
         " is missing: scripts/fetch-assets.sh fetches the scenes git does not hold "
         "(assets/README.md)";
}

std::string temp_path(const std::string& name) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("gridscope-test-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return (dir / name).string();
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string quoted(const std::string& word) { return "'" + word + "'"; }

CommandOutcome run_command(const std::string& command) {
  const std::string out = temp_path("stdout.txt"), err = temp_path("stderr.txt");
  const std::string limited = "timeout 300 " + command + " >" + quoted(out) + " 2>" + quoted(err);
  const int raw = std::system(limited.c_str());
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, slurp(out), slurp(err)};
}

CommandOutcome run_gridscope(const std::string& args, const std::string& prefix) {
  return run_command(prefix + " " + quoted(GRIDSCOPE_BINARY) + " " + args);
}

Png load_png(const std::string& path) {
  const std::string bytes = slurp(path);
  Png png;
  int channels = 0;
  unsigned char* data =
      stbi_load_from_memory(reinterpret_cast<const unsigned char*>(bytes.data()), int(bytes.size()),
                            &png.width, &png.height, &channels, 4);
  if (!data) return png;
  png.rgba.assign(data, data + size_t(png.width) * size_t(png.height) * 4);
  stbi_image_free(data);
  return png;
}

bool walk_coloured(const unsigned char* rgba) {
  const int r = rgba[0], g = rgba[1], b = rgba[2];
  return r > 150 && b > 125 && g < std::min(r, b) - 64;
}

int walk_pixels(const Png& png) {
  int count = 0;
  for (size_t i = 0; i < png.rgba.size(); i += 4) count += walk_coloured(&png.rgba[i]);
  return count;
}

std::string write_temp_file(const std::string& name, const std::string& bytes) {
  const std::string path = temp_path(name);
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

std::string input_error(const std::function<void()>& run) {
  try {
    run();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

Scene make_sphere(glm::vec3 centre, float radius, int rings, int segments) {
  Scene scene;
  scene.name = "sphere";
  scene.vertices.push_back(centre + glm::vec3(0, 0, radius));
  for (int r = 1; r < rings; ++r) {
    const double theta = M_PI * r / rings;
    for (int s = 0; s < segments; ++s) {
      const double phi = 2 * M_PI * s / segments;
      scene.vertices.push_back(centre + radius * glm::vec3(std::sin(theta) * std::cos(phi),
                                                           std::sin(theta) * std::sin(phi),
                                                           std::cos(theta)));
    }
  }
  scene.vertices.push_back(centre - glm::vec3(0, 0, radius));
  const auto ring_vertex = [&](int r, int s) { return 1 + (r - 1) * segments + s % segments; };
  const uint32_t south = uint32_t(scene.vertices.size() - 1);
  for (int s = 0; s < segments; ++s) {
    scene.triangles.emplace_back(0, ring_vertex(1, s), ring_vertex(1, s + 1));
    for (int r = 1; r + 1 < rings; ++r) {
      scene.triangles.emplace_back(ring_vertex(r, s), ring_vertex(r + 1, s),
                                   ring_vertex(r + 1, s + 1));
      scene.triangles.emplace_back(ring_vertex(r, s), ring_vertex(r + 1, s + 1),
                                   ring_vertex(r, s + 1));
    }
    scene.triangles.emplace_back(ring_vertex(rings - 1, s), south, ring_vertex(rings - 1, s + 1));
  }
  return scene;
}

void add_triangle(Scene& scene, glm::vec3 a, glm::vec3 b, glm::vec3 c) {
  const auto first = uint32_t(scene.vertices.size());
  scene.vertices.insert(scene.vertices.end(), {a, b, c});
  scene.triangles.emplace_back(first, first + 1, first + 2);
}

Scene make_soup(uint32_t seed, int count, glm::vec3 lo, glm::vec3 hi, float size) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f), offset(-size, size);
  Scene scene;
  scene.name = "soup";
  for (int i = 0; i < count; ++i) {
    const glm::vec3 c = lo + (hi - lo) * glm::vec3(unit(rng), unit(rng), unit(rng));
    for (int k = 0; k < 3; ++k)
      scene.vertices.push_back(c + glm::vec3(offset(rng), offset(rng), offset(rng)));
    const uint32_t b = uint32_t(scene.vertices.size() - 3);
    scene.triangles.emplace_back(b, b + 1, b + 2);
  }
  return scene;
}

Scene merge(const Scene& a, const Scene& b) {
  Scene out = a;
  const uint32_t base = uint32_t(a.vertices.size());
  out.vertices.insert(out.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (const glm::uvec3& t : b.triangles) out.triangles.push_back(t + glm::uvec3(base));
  return out;
}

Scene transformed(const Scene& scene, float scale, glm::vec3 offset) {
  Scene out = scene;
  for (glm::vec3& v : out.vertices) v = v * scale + offset;
  return out;
}

Scene stadium_scene(int detail) {
  Scene cluster = make_soup(7, detail, glm::vec3(-1), glm::vec3(1), 0.05f);
  Scene ground;
  ground.vertices = {{-1000, -2, -1000}, {1000, -2, -1000},  {1000, -2, 1000},
                     {-1000, -2, 1000},  {-1000, 500, 1000}, {1000, 500, 1000}};
  ground.triangles = {{0, 1, 2}, {0, 2, 3}, {3, 2, 5}, {3, 5, 4}};
  return merge(merge(make_sphere({0, 0, 0}, 0.5f, 16, 32), cluster), ground);
}

Scene wall_planes_scene() {
  Scene scene;
  for (int k = 0; k <= 8; ++k) {
    const float c = k / 8.0f;
    const uint32_t b = uint32_t(scene.vertices.size());
    scene.vertices.insert(scene.vertices.end(), {{c, 0.1f, 0.1f},
                                                 {c, 0.9f, 0.1f},
                                                 {c, 0.9f, 0.6f},
                                                 {0.1f, c, 0.5f},
                                                 {0.9f, c, 0.5f},
                                                 {0.9f, c, 0.9f}});
    scene.triangles.emplace_back(b, b + 1, b + 2);
    scene.triangles.emplace_back(b + 3, b + 4, b + 5);
  }
  return merge(scene, make_soup(3, 500, glm::vec3(0), glm::vec3(1), 0.04f));
}

std::vector<Hit> brute_answers(const Scene& scene, const std::vector<Ray>& rays) {
  BruteForce brute;
  brute.build(scene);
  return trace_all(brute, rays, 2);
}

std::vector<Ray> camera_rays(const Box& box, int width, int height) {
  const glm::vec3 centre = 0.5f * (box.lo + box.hi);
  const float radius = 0.5f * glm::length(box.hi - box.lo);
  const glm::vec3 eye = centre + radius * 2.2f * glm::normalize(glm::vec3(1.0f, 0.7f, 1.3f));
  const glm::vec3 forward = glm::normalize(centre - eye);
  const glm::vec3 right = glm::normalize(glm::cross(forward, glm::vec3(0, 1, 0)));
  const glm::vec3 up = glm::cross(right, forward);
  std::vector<Ray> rays;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const float sx = (2.0f * (x + 0.5f) / width - 1.0f) * 0.45f;
      const float sy = (1.0f - 2.0f * (y + 0.5f) / height) * 0.45f;
      Ray ray;
      ray.origin = eye;
      ray.dir = forward + sx * right + sy * up;
      rays.push_back(ray);
    }
  return rays;
}

std::vector<Ray> random_chords(const Box& box, uint32_t seed, int count) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(-0.1f, 1.1f);
  const auto point = [&] {
    return box.lo + (box.hi - box.lo) * glm::vec3(unit(rng), unit(rng), unit(rng));
  };
  std::vector<Ray> rays;
  for (int i = 0; i < count; ++i) {
    Ray ray;
    ray.origin = point();
    ray.dir = point() - ray.origin;
    if (i % 5 == 0) ray.tmax = 1.0f;  // a chord ending inside the box
    rays.push_back(ray);
  }
  return rays;
}

std::vector<Ray> axis_parallel_rays(const Box& box, uint32_t seed, int count) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<Ray> rays;
  for (int i = 0; i < count; ++i) {
    Ray ray;
    ray.origin = box.lo + (box.hi - box.lo) * glm::vec3(unit(rng), unit(rng), unit(rng));
    ray.dir = glm::vec3(0.0f);
    ray.dir[i % 3] = (i / 3) % 2 ? 1.0f : -1.0f;
    if (i % 7 == 0) ray.dir[(i + 1) % 3] = -0.0f;
    if (i % 11 == 0) ray.dir[(i + 2) % 3] = 1e-30f;
    rays.push_back(ray);
  }
  return rays;
}

std::vector<Ray> edge_and_vertex_rays(const Scene& scene, uint32_t seed, int count) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::uniform_int_distribution<uint32_t> pick(0, uint32_t(scene.triangle_count() - 1));
  const Box box = scene.bounds();
  const float far = 3.0f * glm::length(box.hi - box.lo) + 1.0f;
  std::vector<Ray> rays;
  for (int i = 0; i < count; ++i) {
    const uint32_t t = pick(rng);
    const int corner = i % 3;
    glm::vec3 target = scene.vertex(t, corner);
    if (i % 2) target += unit(rng) * (scene.vertex(t, (corner + 1) % 3) - target);
    const glm::vec3 from =
        0.5f * (box.lo + box.hi) +
        far * glm::normalize(glm::vec3(unit(rng) - 0.5f, unit(rng) - 0.5f, unit(rng) - 0.5f));
    Ray ray;
    ray.origin = from;
    ray.dir = target - from;
    rays.push_back(ray);
  }
  return rays;
}

std::vector<Hit> trace_all(const Accelerator& accel, const std::vector<Ray>& rays, int threads,
                           bool any_hit, size_t packet) {
  std::vector<Hit> hits(rays.size());
  const size_t group = std::max<size_t>(packet, 1);
  std::vector<std::thread> pool;
  for (int k = 0; k < threads; ++k)
    pool.emplace_back([&, k] {
      auto context = accel.make_context();
      std::vector<uint64_t> keys;
      // Interleaved so that both threads reach unbuilt voxels at the same time.
      for (size_t i = size_t(k) * group; i < rays.size(); i += size_t(threads) * group) {
        if (packet == 0) {
          hits[i] = any_hit ? accel.any_hit(rays[i], *context) : accel.intersect(rays[i], *context);
          continue;
        }
        const size_t n = std::min(group, rays.size() - i);
        keys.resize(n);
        std::iota(keys.begin(), keys.end(), uint64_t(i));
        accel.trace_packet(std::span(rays).subspan(i, n), keys, std::span(hits).subspan(i, n),
                           any_hit, *context);
      }
    });
  for (auto& t : pool) t.join();
  return hits;
}

}  // namespace gs::test
