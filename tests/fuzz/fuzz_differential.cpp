// The differential target: a small scene, rays and structure parameters made from the
// fuzzer's bytes, every exact structure checked against brute force. The scenes and rays
// aim at what breaks exactness: triangles lying in cell walls (lattice coordinates k/8 lie on
// the walls of every power-of-two cut, §4's global grids), shared corners and edges,
// T-junctions, coincident and degenerate triangles, tiny, huge and far-off scenes; rays
// starting on walls, edges and vertices, aimed at edges and vertices, along the axes, with
// zero, -0 and tiny direction components, and with odd tmin/tmax.
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <limits>
#include <memory>
#include <string>

#include "core/accel/brute.h"
#include "core/base/error.h"
#include "core/trace/run.h"
#include "tests/fuzz/differential.h"
#include "tests/fuzz/fuzz_entries.h"
#include "tests/structure_run.h"

namespace gs::fuzz {
namespace {

constexpr uint32_t kMaxTriangles = 64;
constexpr uint32_t kMaxRays = 64;
constexpr size_t kMaxProblems = 16;  // per input: enough to see a pattern, short to read

// The fuzzer's bytes read as a stream of choices. Past the end every read gives 0, so any
// input, even an empty one, describes a whole case, and a longer input refines it.
class Choices {
 public:
  explicit Choices(std::span<const uint8_t> data) : data_(data) {}
  uint8_t byte() { return pos_ < data_.size() ? data_[pos_++] : 0; }
  uint32_t below(uint32_t n) { return byte() % n; }  // n <= 256
  template <class T, size_t N>
  T pick(const T (&options)[N]) {
    return options[below(N)];
  }
  // Four bytes as the bits of a float: any value, NaN, infinities and denormals included.
  float raw_float() {
    uint32_t bits = 0;
    for (int i = 0; i < 4; ++i) bits |= uint32_t(byte()) << (8 * i);
    return std::bit_cast<float>(bits);
  }
  float raw_finite() {
    const float f = raw_float();
    return std::isfinite(f) ? f : 0.0f;
  }

 private:
  std::span<const uint8_t> data_;
  size_t pos_ = 0;
};

// Where the lattice [-1, 1]^3 is put: tiny, huge and far-from-the-origin scenes.
struct Frame {
  float scale = 1.0f;
  float offset = 0.0f;
  glm::vec3 map(glm::vec3 p) const { return p * scale + offset; }
};

glm::vec3 lattice_point(Choices& in) {
  const auto k = [&] { return float(int(in.below(17)) - 8) / 8.0f; };
  return {k(), k(), k()};
}

// p moved by -2..2 ulps per coordinate: just off a wall, an edge or a vertex.
glm::vec3 nudged(glm::vec3 p, Choices& in) {
  for (int a = 0; a < 3; ++a) {
    const int steps = int(in.below(5)) - 2;
    for (int k = 0; k < std::abs(steps); ++k) p[a] = std::nextafter(p[a], steps > 0 ? kInf : -kInf);
  }
  return p;
}

glm::vec3 raw_point(Choices& in) { return {in.raw_finite(), in.raw_finite(), in.raw_finite()}; }

// The vertex index of a new triangle corner: often an existing vertex (shared corners,
// coincident triangles), else a new one on, near or off the lattice.
uint32_t corner(Scene& scene, const Frame& frame, Choices& in) {
  const uint32_t count = uint32_t(scene.vertices.size());
  const uint32_t kind = in.below(8);
  if (count > 0 && kind == 0) return in.byte() % count;
  glm::vec3 p;
  if (count > 0 && kind == 1) {  // on the segment between two vertices: a T-junction
    const glm::vec3 a = scene.vertices[in.byte() % count], b = scene.vertices[in.byte() % count];
    p = a + (b - a) * (float(in.below(9)) / 8.0f);
  } else if (count > 0 && kind == 2) {  // a vertex with one coordinate moved: axis-aligned edges
    p = scene.vertices[in.byte() % count];
    p[in.below(3)] = frame.map(lattice_point(in)).x;
  } else if (kind == 3) {
    p = nudged(frame.map(lattice_point(in)), in);
  } else if (kind == 4) {
    p = raw_point(in);
  } else {
    p = frame.map(lattice_point(in));
  }
  scene.vertices.push_back(p);
  return count;
}

Scene make_scene(const Frame& frame, Choices& in) {
  Scene scene;
  scene.name = "fuzz";
  uint32_t triangles = 1 + in.below(kMaxTriangles);
  if (in.below(2) == 0) {
    // A degenerate triangle from corner to corner of the lattice box: never hit, but it makes
    // the scene box the lattice box, so that the walls of power-of-two cuts (octree, grid1d
    // with g = 2, 4, 8) fall on lattice coordinates, where the triangles lie.
    scene.vertices = {frame.map(glm::vec3(-1.0f)), frame.map(glm::vec3(1.0f))};
    scene.triangles.emplace_back(0, 1, 1);
    --triangles;
  }
  for (uint32_t t = 0; t < triangles; ++t) {
    glm::uvec3 tri;
    for (int c = 0; c < 3; ++c) tri[c] = corner(scene, frame, in);
    scene.triangles.push_back(tri);
  }
  return scene;
}

// A point a ray starts from or is aimed at.
glm::vec3 target_point(const Scene& scene, const Frame& frame, Choices& in) {
  const glm::uvec3 tri = scene.triangles[in.byte() % scene.triangles.size()];
  const glm::vec3 a = scene.vertices[tri.x], b = scene.vertices[tri.y], c = scene.vertices[tri.z];
  switch (in.below(7)) {
    case 0:
      return a;
    case 1:  // on an edge
      return a + (b - a) * (float(in.below(9)) / 8.0f);
    case 2: {  // inside, or just outside when the weights go negative
      const float u = float(int(in.below(11)) - 1) / 8.0f, v = float(int(in.below(11)) - 1) / 8.0f;
      return a + (b - a) * u + (c - a) * v;
    }
    case 3: {  // on a wall of a cut of the scene box into g cells (g need not be a power of 2)
      const Box box = scene.bounds();
      glm::vec3 p;
      for (int axis = 0; axis < 3; ++axis) {
        const uint32_t g = 2 + in.below(19), i = in.below(g + 1);
        p[axis] = float(double(box.lo[axis]) +
                        (double(box.hi[axis]) - double(box.lo[axis])) * double(i) / double(g));
      }
      return p;
    }
    case 4:  // outside the lattice box
      return frame.map(lattice_point(in) * 4.0f);
    case 5:
      return raw_point(in);
    default:
      return frame.map(lattice_point(in));
  }
}

// A direction component replaced by one that stresses the 1/d and shear arithmetic.
float nasty_component(float d, Choices& in) {
  constexpr float kNasty[] = {0.0f, -0.0f, 1e-30f, -1e-30f, 1e-40f, -1e-45f, 1e30f};
  return in.below(3) == 0 ? in.pick(kNasty) : d;
}

glm::vec3 make_direction(const Scene& scene, const Frame& frame, glm::vec3 origin, Choices& in) {
  switch (in.below(6)) {
    case 0: {  // along an axis; the other components +0 or -0
      glm::vec3 d(in.below(2) ? 0.0f : -0.0f, in.below(2) ? 0.0f : -0.0f,
                  in.below(2) ? 0.0f : -0.0f);
      d[in.below(3)] = in.below(2) ? 1.0f : -1.0f;
      return d;
    }
    case 1: {
      const glm::vec3 d = target_point(scene, frame, in) - origin;
      return {nasty_component(d.x, in), nasty_component(d.y, in), nasty_component(d.z, in)};
    }
    case 2:  // anything, NaN and infinity included: such rays must be misses everywhere
      return {in.raw_float(), in.raw_float(), in.raw_float()};
    case 3:
      return lattice_point(in);  // zero components, the zero vector too
    default:
      return target_point(scene, frame, in) - origin;  // at an edge, a vertex, a wall
  }
}

Ray make_ray(const Scene& scene, const Frame& frame, const Ray* previous, Choices& in) {
  Ray ray;
  ray.origin = previous && in.below(8) == 0 ? previous->origin : target_point(scene, frame, in);
  ray.dir = make_direction(scene, frame, ray.origin, in);
  constexpr float kTmin[] = {-1.0f, -0.0f, 1e-30f, 0.5f, 1.0f};
  constexpr float kTmax[] = {0.0f, 1e-6f, 0.5f, 1.0f, 2.0f};
  switch (in.below(8)) {
    case 0:
      ray.tmin = in.pick(kTmin);
      break;
    case 1:  // ends on or before what it is aimed at
      ray.tmax = in.pick(kTmax);
      break;
    case 2:  // NaN, negative, tmin > tmax: invalid rays are misses
      ray.tmin = in.raw_float(), ray.tmax = in.raw_float();
      break;
    default:
      break;
  }
  return ray;
}

StructureSettings make_settings(Choices& in) {
  StructureSettings s;
  AccelParams& p = s.params;
  // Values the command line accepts, the extremes included; the slow ones come up rarely:
  // the cost function weighs every g up to the maximum for each voxel (§6.5), and a uniform
  // grid of --density 1e12 has as many cells as its budget allows, which rays walk one by one.
  p.max_granularity = in.pick({2, 20, 3, 4, 5, 8, 20, 64, 1, 2, 3, 4, 20, 8, 16, 4096});
  p.axis = in.below(2) ? AxisRule::cost : AxisRule::alternate;
  p.max_depth = in.pick({0, 0, 1, 2, 4, 64});
  p.leaf_size = in.pick({0, 0, 1, 2, 8, 1 << 20});
  p.density =
      in.pick({0.0, 0.0, 0.01, 1.0, 50.0, 0.0, 2.0, 0.5, 0.0, 0.0, 4.0, 0.0, 1.0, 0.0, 0.1, 1e12});
  p.sample_every = in.pick({1, 3, 64});
  // Small budgets keep every execution fast and make structures stop at the cap.
  p.memory_budget =
      in.pick({uint64_t{1} << 20, uint64_t{1} << 20, uint64_t{64} << 10, uint64_t{4} << 10});
  if (in.below(8) == 0) p.subcost = p.vertcost = p.travcost = 0.0;  // every cut pays
  s.threads = 1 + int(in.below(2));
  s.sample = in.below(2) == 1;
  s.any_hit_first = in.below(2) == 1;
  return s;
}

// ---------------------------------------------------------------------------------------
// Comparison

std::string describe(const Ray& r) {
  char text[256];
  std::snprintf(text, sizeof text, "o=(%a,%a,%a) d=(%a,%a,%a) tmin=%a tmax=%a", r.origin.x,
                r.origin.y, r.origin.z, r.dir.x, r.dir.y, r.dir.z, r.tmin, r.tmax);
  return text;
}

std::string describe(const Hit& h) {
  char text[128];
  std::snprintf(text, sizeof text, "id %d t=%a u=%a v=%a", h.id, h.t, h.u, h.v);
  return text;
}

std::string describe(const std::string& accel, bool eager, const StructureSettings& s) {
  const AccelParams& p = s.params;
  return accel + (eager ? " eager" : " lazy") + " g=" + std::to_string(p.max_granularity) +
         (p.axis == AxisRule::cost ? " axis=cost" : " axis=alternate") +
         " depth=" + std::to_string(p.max_depth) + " leaf=" + std::to_string(p.leaf_size) +
         " density=" + std::to_string(p.density) + " budget=" + std::to_string(p.memory_budget) +
         " threads=" + std::to_string(s.threads) + (s.sample ? " sampled" : "") +
         (s.packet > 0 ? " packets of " + std::to_string(s.packet) : "");
}

// Bit for bit: -0 and +0 differ, as they would in two hit files.
bool same_bits(const Hit& a, const Hit& b) { return std::memcmp(&a, &b, sizeof(Hit)) == 0; }

void report(Outcome& outcome, const std::string& problem) {
  if (outcome.problems.size() < kMaxProblems) outcome.problems.push_back(problem);
}

// Brute force over triangle `id` alone, in a scene with the same box: two one-point
// triangles at its corners are degenerate, so never hit, but keep the clip box, which
// decides where the kernel starts the ray. Gives that triangle's own answer for the ray.
class SingleTriangle {
 public:
  SingleTriangle(const Scene& scene, uint32_t id) {
    const Box box = scene.bounds();
    single_.vertices = {scene.vertex(id, 0), scene.vertex(id, 1), scene.vertex(id, 2), box.lo,
                        box.hi};
    single_.triangles = {{0, 1, 2}, {3, 3, 3}, {4, 4, 4}};
    brute_.build(single_);
    context_ = brute_.make_context();
  }
  Hit intersect(const Ray& ray) { return brute_.intersect(ray, *context_); }

 private:
  Scene single_;
  BruteForce brute_;
  std::unique_ptr<ThreadContext> context_;
};

bool blocks(const Scene& scene, const Ray& ray, const Hit& hit) {
  Hit own = SingleTriangle(scene, uint32_t(hit.id)).intersect(ray);
  own.id = hit.id;
  return same_bits(own, hit);
}

std::vector<Hit> trace(const Accelerator& accel, const std::vector<Ray>& rays, int threads,
                       bool any_hit, size_t packet = 0) {
  std::vector<Hit> hits(rays.size());
  if (packet == 0 || !accel.traces_packets()) {
    // Chunks of 2 rays: two threads meet the same unbuilt voxels.
    trace_chunks(
        accel, rays.size(), 2, threads, [&](ThreadContext& context, size_t begin, size_t end) {
          for (size_t i = begin; i < end; ++i)
            hits[i] = any_hit ? accel.any_hit(rays[i], context) : accel.intersect(rays[i], context);
        });
    return hits;
  }
  const size_t packets = (rays.size() + packet - 1) / packet;
  trace_chunks(accel, packets, 1, threads, [&](ThreadContext& context, size_t begin, size_t end) {
    std::vector<uint64_t> keys(packet);
    for (size_t p = begin; p < end; ++p) {
      const size_t first = p * packet, n = std::min(packet, rays.size() - first);
      accel.trace_packet({rays.data() + first, n}, {keys.data(), n}, {hits.data() + first, n},
                         any_hit, context);
    }
  });
  return hits;
}

struct Reference {
  std::vector<Hit> nearest;
  std::vector<bool> blocked;
};

// Brute force's answers, each nearest hit checked against its triangle's own answer.
Reference brute_reference(const Scene& scene, const std::vector<Ray>& rays, Outcome& outcome) {
  BruteForce brute;
  brute.build(scene);
  Reference ref{trace(brute, rays, 1, false), {}};
  const std::vector<Hit> any = trace(brute, rays, 1, true);
  for (size_t i = 0; i < rays.size(); ++i) {
    ref.blocked.push_back(any[i].found());
    if (any[i].found() != ref.nearest[i].found())
      report(outcome, "brute: ray " + std::to_string(i) + " any-hit and nearest disagree");
    if (ref.nearest[i].found() && !blocks(scene, rays[i], ref.nearest[i]))
      report(outcome, "brute: ray " + std::to_string(i) + " (" + describe(rays[i]) + ") nearest " +
                          describe(ref.nearest[i]) + " is not its triangle's own answer");
  }
  return ref;
}

void compare(const std::string& what, const Scene& scene, const std::vector<Ray>& rays,
             const std::vector<Hit>& nearest, const std::vector<Hit>& any, const Reference& ref,
             Outcome& outcome) {
  for (size_t i = 0; i < rays.size(); ++i) {
    const std::string ray = "ray " + std::to_string(i) + " (" + describe(rays[i]) + ")";
    const Hit& brute = ref.nearest[i];
    if (!same_bits(nearest[i], brute))
      report(outcome,
             what + ": " + ray + " nearest " + describe(nearest[i]) + ", brute " + describe(brute));
    if (any[i].found() != ref.blocked[i])
      report(outcome, what + ": " + ray + " any-hit " + describe(any[i]) + ", brute " +
                          (ref.blocked[i] ? "blocked" : "not blocked"));
    if (any[i].found() && !blocks(scene, rays[i], any[i]))
      report(outcome, what + ": " + ray + " any-hit " + describe(any[i]) +
                          " is not that triangle's own answer");
    outcome.checks += 2;
  }
}

}  // namespace

void check_against_brute(const Scene& scene, const std::vector<Ray>& rays,
                         const StructureSettings& settings, Outcome& outcome) {
  const Reference ref = brute_reference(scene, rays, outcome);
  for (const std::string& name : accelerator_names()) {
    if (name == "brute" || name == "embree" || name == "zero") continue;
    for (const bool eager : {false, true}) {
      const std::string what = describe(name, eager, settings);
      try {
        const auto accel = test::build_structure(
            {name, settings.params, settings.sample, eager, settings.threads}, scene, rays);
        std::vector<Hit> nearest, any;
        const size_t packet = settings.packet;
        if (settings.any_hit_first) any = trace(*accel, rays, settings.threads, true, packet);
        nearest = trace(*accel, rays, settings.threads, false, packet);
        if (!settings.any_hit_first) any = trace(*accel, rays, settings.threads, true, packet);
        compare(what, scene, rays, nearest, any, ref, outcome);
      } catch (const UsageError&) {
        // Parameters this structure does not take (its own --max-depth range): the command
        // line rejects them, there is nothing to compare.
      } catch (const std::exception& e) {
        report(outcome, what + ": threw " + e.what());
      }
    }
  }
}

Outcome fuzz_differential(std::span<const uint8_t> data) {
  Choices in(data);
  StructureSettings settings = make_settings(in);
  constexpr float kScales[] = {1.0f, 1.0f, 1e-4f, 1e4f, 3.0f};
  constexpr float kOffsets[] = {0.0f, 0.0f, 0.5f, -7.25f, 1e6f};
  const Frame frame{in.pick(kScales), in.pick(kOffsets)};
  const Scene scene = make_scene(frame, in);
  std::vector<Ray> rays(in.below(kMaxRays + 1));
  for (size_t i = 0; i < rays.size(); ++i)
    rays[i] = make_ray(scene, frame, i > 0 ? &rays[i - 1] : nullptr, in);
  // Chosen last, so that inputs that end before it (the regressions kept from before there
  // were packets) still trace one ray at a time.
  constexpr size_t kPackets[] = {0, 64, 4, 16};
  settings.packet = in.pick(kPackets);
  Outcome outcome;
  outcome.accepted = true;
  check_against_brute(scene, rays, settings, outcome);
  return outcome;
}

}  // namespace gs::fuzz
