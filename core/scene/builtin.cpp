// Built-in procedural scenes, generated here from published descriptions (no foreign code):
//   pyramid      Haines' SPD "tetra" at size factor 6: the recursive tetrahedral pyramid.
//   sphereflake  Haines' SPD "balls" at its default size: 7381 spheres over a floor quad.
//   lumpy        Jevans' "teapot in a stadium": a dense cluster of small curved objects on a
//                ground 1000 times wider, ringed by a few huge stands and towers.
// All three are z-up like the SPD databases. Only closed-form math is used (no random
// numbers), so every run produces the same triangles in the same order.
#include <algorithm>
#include <cmath>
#include <functional>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <numbers>
#include <string>
#include <vector>

#include "core/base/error.h"
#include "core/scene/scene.h"

namespace gs {
namespace {

constexpr double kPi = std::numbers::pi;

// Appends vertices and triangles and records which id range each part covers.
class Builder {
 public:
  uint32_t vertex(const glm::dvec3& p) {
    scene_.vertices.emplace_back(glm::vec3(p));
    return static_cast<uint32_t>(scene_.vertices.size() - 1);
  }
  void triangle(uint32_t a, uint32_t b, uint32_t c) { scene_.triangles.emplace_back(a, b, c); }

  void begin_part(const std::string& label, bool detail = false, glm::dvec3 center = {},
                  double radius = 0.0) {
    ScenePart part;
    part.label = label;
    part.detail = detail;
    part.center = center;
    part.radius = radius;
    part.first_triangle = static_cast<uint32_t>(scene_.triangles.size());
    parts_.push_back(part);
  }
  void end_part() {
    parts_.back().triangle_count =
        static_cast<uint32_t>(scene_.triangles.size()) - parts_.back().first_triangle;
  }

  Scene& scene() { return scene_; }
  std::vector<ScenePart>& parts() { return parts_; }

 private:
  Scene scene_;
  std::vector<ScenePart> parts_;
};

// A mesh of `rows` rings of `cols` points each, closed around every ring. Rings run from
// the "top" to the "bottom" of the surface and points counter-clockwise seen from the top,
// which makes every triangle face outward. Optional poles close the ends with fans;
// `wrap_rows` joins the last ring back to the first (a torus).
struct RingMesh {
  int rows = 0, cols = 0;
  std::function<glm::dvec3(int row, int col)> point;
  const glm::dvec3* top = nullptr;
  const glm::dvec3* bottom = nullptr;
  bool wrap_rows = false;
};

void emit_ring_mesh(Builder& b, const RingMesh& m) {
  std::vector<uint32_t> ids(static_cast<size_t>(m.rows) * m.cols);
  for (int r = 0; r < m.rows; ++r) {
    for (int c = 0; c < m.cols; ++c) ids[r * m.cols + c] = b.vertex(m.point(r, c));
  }
  auto at = [&](int r, int c) { return ids[(r % m.rows) * m.cols + c % m.cols]; };
  if (m.top) {
    const uint32_t pole = b.vertex(*m.top);
    for (int c = 0; c < m.cols; ++c) b.triangle(pole, at(0, c), at(0, c + 1));
  }
  const int bands = m.wrap_rows ? m.rows : m.rows - 1;
  for (int r = 0; r < bands; ++r) {
    for (int c = 0; c < m.cols; ++c) {
      b.triangle(at(r, c), at(r + 1, c), at(r + 1, c + 1));
      b.triangle(at(r, c), at(r + 1, c + 1), at(r, c + 1));
    }
  }
  if (m.bottom) {
    const uint32_t pole = b.vertex(*m.bottom);
    for (int c = 0; c < m.cols; ++c) b.triangle(at(m.rows - 1, c), pole, at(m.rows - 1, c + 1));
  }
}

// A UV sphere around the z axis whose radius may vary with direction: `segments` around,
// `bands` from pole to pole (2·segments·(bands−1) triangles).
void emit_sphere(Builder& b, glm::dvec3 center, double radius, int segments, int bands,
                 const std::function<double(double theta, double phi)>& bump = nullptr) {
  auto surface = [&](double theta, double phi) {
    const double r = radius * (bump ? bump(theta, phi) : 1.0);
    return center + r * glm::dvec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                                   std::cos(theta));
  };
  const glm::dvec3 top = surface(0.0, 0.0), bottom = surface(kPi, 0.0);
  RingMesh m;
  m.rows = bands - 1;
  m.cols = segments;
  m.point = [&](int r, int c) { return surface(kPi * (r + 1) / bands, 2 * kPi * c / segments); };
  m.top = &top;
  m.bottom = &bottom;
  emit_ring_mesh(b, m);
}

// ---------------------------------------------------------------------------------------
// pyramid: SPD tetra. The unit tetrahedron with corners (1,1,1), (-1,-1,1), (-1,1,-1),
// (1,-1,-1) is replaced by four half-size copies at its corners, recursively; each leaf
// tetrahedron writes its four faces as separate triangles. Corner, child and face orders
// were read off Haines' own output (scenes/spd/tetra.nff), which the tests compare against.

constexpr glm::dvec3 kTetraCorner[4] = {{1, 1, 1}, {-1, -1, 1}, {-1, 1, -1}, {1, -1, -1}};
constexpr int kTetraChildOrder[4] = {1, 2, 3, 0};
constexpr int kTetraFaces[4][3] = {{1, 2, 3}, {0, 3, 2}, {3, 0, 1}, {2, 1, 0}};

void emit_tetra(Builder& b, glm::dvec3 center, double half, int levels) {
  if (levels == 0) {
    for (const auto& face : kTetraFaces) {
      uint32_t ids[3];
      for (int k = 0; k < 3; ++k) ids[k] = b.vertex(center + half * kTetraCorner[face[k]]);
      b.triangle(ids[0], ids[1], ids[2]);
    }
    return;
  }
  for (int corner : kTetraChildOrder) {
    emit_tetra(b, center + 0.5 * half * kTetraCorner[corner], 0.5 * half, levels - 1);
  }
}

void build_pyramid(Builder& b) {
  constexpr int kSizeFactor = 6;  // SPD default: 4^(6-1) = 1024 tetrahedra, 4096 triangles
  b.begin_part("tetrahedra");
  emit_tetra(b, glm::dvec3(0.0), 1.0, kSizeFactor - 1);
  b.end_part();
}

// ---------------------------------------------------------------------------------------
// sphereflake: SPD balls. A sphere of radius 0.5 at the origin carries nine spheres of a
// third of its radius touching it: three tilted up from its "equator" and six on it, in
// three sets rotated by 120°. Each child's own nine sit the same way around the axis from
// its parent's centre to its own, to four levels (1+9+81+729+6561 = 7381 spheres).

constexpr int kFlakeLevels = 4;
// Tessellation per level (segments, bands): finer where a sphere is large on screen.
constexpr int kFlakeResolution[kFlakeLevels + 1][2] = {{48, 24}, {24, 12}, {12, 8}, {8, 6}, {6, 4}};

glm::dmat3 axis_rotation(glm::dvec3 axis, double angle) {
  const glm::dvec3 k = glm::normalize(axis);
  const double c = std::cos(angle), s = std::sin(angle), t = 1.0 - c;
  // Rodrigues' formula; glm matrices are column-major: m[column][row].
  glm::dmat3 m;
  m[0] = {t * k.x * k.x + c, t * k.x * k.y + s * k.z, t * k.x * k.z - s * k.y};
  m[1] = {t * k.x * k.y - s * k.z, t * k.y * k.y + c, t * k.y * k.z + s * k.x};
  m[2] = {t * k.x * k.z + s * k.y, t * k.y * k.z - s * k.x, t * k.z * k.z + c};
  return m;
}

// The nine child directions around +z.
std::vector<glm::dvec3> flake_directions() {
  const double s = 1.0 / std::sqrt(2.0);
  const glm::dvec3 trio[3] = {{s, s, 0}, {s, 0, -s}, {0, s, -s}};
  // Tilting the trio about (1,-1,0) by asin(2/sqrt 6) lifts the first direction to
  // 35° above the equator and lays the other two on it.
  const glm::dmat3 tilt = axis_rotation({1, -1, 0}, std::asin(2.0 / std::sqrt(6.0)));
  std::vector<glm::dvec3> dirs;
  for (int set = 0; set < 3; ++set) {
    const glm::dmat3 spin = axis_rotation({0, 0, 1}, set * 2.0 * kPi / 3.0);
    for (const glm::dvec3& d : trio) dirs.push_back(spin * (tilt * d));
  }
  return dirs;
}

// The rotation taking +z to `dir`: about the axis z × dir. Straight down that axis is
// undefined; the SPD turns about y then, and so do we, for every direction within rounding
// of -z. (The SPD itself decided by its own rounding: two of its twelve downward spheres
// went the other way, so their sub-flakes in balls.nff are turned about the vertical.)
glm::dmat3 frame_for(const glm::dvec3& dir) {
  constexpr double kRounding = 1e-12;
  if (dir.z >= 1.0 - kRounding) return glm::dmat3(1.0);
  if (dir.z <= -1.0 + kRounding) return axis_rotation({0, 1, 0}, kPi);
  return axis_rotation(glm::cross(glm::dvec3(0, 0, 1), dir), std::acos(dir.z));
}

void emit_flake(Builder& b, const std::vector<glm::dvec3>& dirs, glm::dvec3 center, double radius,
                glm::dvec3 axis, int level) {
  b.begin_part("sphere level " + std::to_string(level), false, center, radius);
  emit_sphere(b, center, radius, kFlakeResolution[level][0], kFlakeResolution[level][1]);
  b.end_part();
  if (level == kFlakeLevels) return;
  const glm::dmat3 frame = frame_for(axis);
  for (const glm::dvec3& d : dirs) {
    const glm::dvec3 dir = frame * d;
    emit_flake(b, dirs, center + dir * (radius * 4.0 / 3.0), radius / 3.0, dir, level + 1);
  }
}

void build_sphereflake(Builder& b) {
  // The floor polygon of balls.nff, split as a fan like every quad.
  b.begin_part("floor");
  const uint32_t v0 = b.vertex({12, 12, -0.5}), v1 = b.vertex({-12, 12, -0.5});
  const uint32_t v2 = b.vertex({-12, -12, -0.5}), v3 = b.vertex({12, -12, -0.5});
  b.triangle(v0, v1, v2);
  b.triangle(v0, v2, v3);
  b.end_part();
  emit_flake(b, flake_directions(), glm::dvec3(0.0), 0.5, glm::dvec3(0, 0, 1), 0);
}

// ---------------------------------------------------------------------------------------
// lumpy: about 56k small triangles within 3.2 units of the origin (a procedural teapot,
// bumpy balls, tori, chess-pawn-like pieces), on a 3200-unit ground ringed by stands and
// light towers made of a few hundred huge triangles: Jevans' "teapot in a stadium".

// Smooth profile through control points (Catmull-Rom), sampled evenly in parameter.
std::vector<glm::dvec2> smooth_profile(const std::vector<glm::dvec2>& knots, int samples) {
  std::vector<glm::dvec2> out;
  const int spans = static_cast<int>(knots.size()) - 1;
  for (int i = 0; i < samples; ++i) {
    const double t = double(i) * spans / (samples - 1);
    const int k = std::min(static_cast<int>(t), spans - 1);
    const double u = t - k;
    const glm::dvec2& p0 = knots[std::max(k - 1, 0)];
    const glm::dvec2& p1 = knots[k];
    const glm::dvec2& p2 = knots[k + 1];
    const glm::dvec2& p3 = knots[std::min(k + 2, spans)];
    out.push_back(0.5 *
                  ((2.0 * p1) + (-p0 + p2) * u + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * u * u +
                   (-p0 + 3.0 * p1 - 3.0 * p2 + p3) * u * u * u));
  }
  return out;
}

// A surface of revolution about the vertical through `base`: the profile (radius, height)
// runs from the top pole down to the bottom pole (both at radius 0).
void emit_revolution(Builder& b, glm::dvec3 base, const std::vector<glm::dvec2>& profile,
                     int segments) {
  const glm::dvec3 top = base + glm::dvec3(0, 0, profile.front().y);
  const glm::dvec3 bottom = base + glm::dvec3(0, 0, profile.back().y);
  RingMesh m;
  m.rows = static_cast<int>(profile.size()) - 2;
  m.cols = segments;
  m.point = [&](int r, int c) {
    const glm::dvec2 q = profile[r + 1];
    const double phi = 2 * kPi * c / segments;
    return base + glm::dvec3(q.x * std::cos(phi), q.x * std::sin(phi), q.y);
  };
  m.top = &top;
  m.bottom = &bottom;
  emit_ring_mesh(b, m);
}

// An open tube of radius `radius(t)` along `curve(t)`, t in [0, 1].
void emit_tube(Builder& b, const std::function<glm::dvec3(double)>& curve,
               const std::function<double(double)>& radius, int rings, int segments) {
  RingMesh m;
  m.rows = rings;
  m.cols = segments;
  m.point = [&](int r, int c) {
    const double t = double(r) / (rings - 1);
    const glm::dvec3 p = curve(t);
    const glm::dvec3 tangent =
        glm::normalize(curve(std::min(t + 1e-4, 1.0)) - curve(std::max(t - 1e-4, 0.0)));
    const glm::dvec3 n = glm::normalize(glm::cross(tangent, glm::dvec3(0, 1, 0)));
    const glm::dvec3 bi = glm::cross(tangent, n);
    // Clockwise about the tangent, so that triangles face outward (see RingMesh).
    const double a = -2 * kPi * c / segments;
    return p + radius(t) * (std::cos(a) * n + std::sin(a) * bi);
  };
  emit_ring_mesh(b, m);
}

void emit_torus(Builder& b, glm::dvec3 center, const glm::dmat3& orientation, double major,
                double minor, int segments, int rings) {
  RingMesh m;
  m.rows = rings;
  m.cols = segments;
  m.wrap_rows = true;
  m.point = [&](int r, int c) {
    const double psi = -2 * kPi * r / rings, phi = 2 * kPi * c / segments;
    const double w = major + minor * std::cos(psi);
    return center +
           orientation * glm::dvec3(w * std::cos(phi), w * std::sin(phi), minor * std::sin(psi));
  };
  emit_ring_mesh(b, m);
}

void build_teapot(Builder& b) {
  // Body, lid and knob as one profile from the knob's top down to the middle of the base.
  const std::vector<glm::dvec2> knots = {{0.0, 1.12},  {0.06, 1.1},  {0.07, 1.05}, {0.04, 1.01},
                                         {0.12, 0.97}, {0.26, 0.93}, {0.34, 0.87}, {0.36, 0.84},
                                         {0.45, 0.78}, {0.53, 0.6},  {0.56, 0.38}, {0.52, 0.16},
                                         {0.42, 0.04}, {0.36, 0.01}, {0.2, 0.01},  {0.0, 0.01}};
  b.begin_part("teapot body", true);
  emit_revolution(b, glm::dvec3(0.0), smooth_profile(knots, 72), 112);
  b.end_part();
  b.begin_part("teapot spout", true);
  emit_tube(
      b,
      [](double t) {  // a quadratic Bézier from inside the body up and out
        const glm::dvec3 p0(0.4, 0, 0.3), p1(0.85, 0, 0.35), p2(0.95, 0, 0.85);
        return (1 - t) * (1 - t) * p0 + 2 * t * (1 - t) * p1 + t * t * p2;
      },
      [](double t) { return 0.11 - 0.06 * t; }, 56, 28);
  b.end_part();
  b.begin_part("teapot handle", true);
  emit_tube(
      b,
      [](double t) {  // a half circle on the far side, ends buried in the body
        const double a = kPi * (0.5 + t);
        return glm::dvec3(-0.4 + 0.34 * std::cos(a), 0.0, 0.5 + 0.28 * std::sin(a));
      },
      [](double) { return 0.045; }, 48, 24);
  b.end_part();
}

void build_cluster(Builder& b) {
  build_teapot(b);
  const glm::dvec2 ball_xy[4] = {{1.05, 0.95}, {-1.1, 0.9}, {-1.0, -1.05}, {1.1, -0.95}};
  for (int i = 0; i < 4; ++i) {
    const double radius = 0.26 + 0.03 * i;
    const glm::dvec3 center(ball_xy[i], radius * 1.1);
    b.begin_part("bumpy ball", true);
    emit_sphere(b, center, radius, 72, 36, [i](double theta, double phi) {
      return 1.0 + 0.1 * std::sin((4 + i) * theta) * std::cos((5 + 2 * i) * phi);
    });
    b.end_part();
  }
  for (int i = 0; i < 3; ++i) {
    const double angle = 2 * kPi * i / 3 + 0.4;
    const glm::dvec3 center(0.75 * std::cos(angle), 0.75 * std::sin(angle) - 0.15, 0.3);
    const glm::dmat3 stand = axis_rotation({std::cos(angle), std::sin(angle), 0}, kPi / 2.5);
    b.begin_part("torus", true);
    emit_torus(b, center, stand, 0.22, 0.065, 48, 24);
    b.end_part();
  }
  const std::vector<glm::dvec2> pawn = smooth_profile({{0.0, 0.42},
                                                       {0.07, 0.41},
                                                       {0.09, 0.36},
                                                       {0.07, 0.31},
                                                       {0.05, 0.28},
                                                       {0.09, 0.26},
                                                       {0.05, 0.22},
                                                       {0.06, 0.1},
                                                       {0.12, 0.05},
                                                       {0.12, 0.01},
                                                       {0.0, 0.01}},
                                                      26);
  for (int i = 0; i < 8; ++i) {
    const double angle = 2 * kPi * (i + 0.5) / 8;
    b.begin_part("pawn", true);
    emit_revolution(b, glm::dvec3(1.45 * std::cos(angle), 1.45 * std::sin(angle), 0.0), pawn, 32);
    b.end_part();
  }
}

void emit_quad(Builder& b, glm::dvec3 p0, glm::dvec3 p1, glm::dvec3 p2, glm::dvec3 p3) {
  const uint32_t a = b.vertex(p0), c = b.vertex(p1), d = b.vertex(p2), e = b.vertex(p3);
  b.triangle(a, c, d);
  b.triangle(a, d, e);
}

void emit_box(Builder& b, glm::dvec3 lo, glm::dvec3 hi) {
  const glm::dvec3 v[8] = {{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z},
                           {lo.x, hi.y, lo.z}, {lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z},
                           {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z}};
  constexpr int kFaces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  for (const auto& f : kFaces) emit_quad(b, v[f[0]], v[f[1]], v[f[2]], v[f[3]]);
}

void build_stadium(Builder& b) {
  constexpr double kGround = 1600, kInner = 1000, kOuter = 1400, kTop = 250;
  constexpr int kSections = 48;
  b.begin_part("ground");
  emit_quad(b, {kGround, kGround, 0}, {-kGround, kGround, 0}, {-kGround, -kGround, 0},
            {kGround, -kGround, 0});
  b.end_part();
  b.begin_part("stands");
  for (int i = 0; i < kSections; ++i) {
    const double a0 = 2 * kPi * i / kSections, a1 = 2 * kPi * (i + 1) / kSections;
    const glm::dvec3 d0(std::cos(a0), std::sin(a0), 0), d1(std::cos(a1), std::sin(a1), 0);
    const glm::dvec3 up(0, 0, kTop);
    emit_quad(b, kInner * d0, kOuter * d0 + up, kOuter * d1 + up, kInner * d1);  // seating
    emit_quad(b, kOuter * d0 + up, kOuter * d0, kOuter * d1, kOuter * d1 + up);  // back wall
  }
  b.end_part();
  b.begin_part("light towers");
  for (int i = 0; i < 4; ++i) {
    const double a = kPi / 4 + kPi / 2 * i;
    const glm::dvec3 c(1500 * std::cos(a), 1500 * std::sin(a), 0);
    emit_box(b, c - glm::dvec3(10, 10, 0), c + glm::dvec3(10, 10, 600));
  }
  b.end_part();
  b.begin_part("scoreboard");
  emit_quad(b, {-150, 1300, 300}, {150, 1300, 300}, {150, 1300, 420}, {-150, 1300, 420});
  b.end_part();
}

void build_lumpy(Builder& b) {
  build_cluster(b);
  build_stadium(b);
}

Builder build(const std::string& name) {
  Builder b;
  if (name == "pyramid") {
    build_pyramid(b);
  } else if (name == "lumpy") {
    build_lumpy(b);
  } else if (name == "sphereflake") {
    build_sphereflake(b);
  } else {
    fail_input("builtin:" + name, "unknown built-in scene (pyramid, lumpy, sphereflake)");
  }
  b.scene().name = "builtin:" + name;
  return b;
}

}  // namespace

Scene make_builtin_scene(const std::string& name) { return std::move(build(name).scene()); }

std::vector<ScenePart> builtin_scene_parts(const std::string& name) {
  return std::move(build(name).parts());
}

std::vector<std::string> builtin_scene_names() { return {"pyramid", "lumpy", "sphereflake"}; }

}  // namespace gs
