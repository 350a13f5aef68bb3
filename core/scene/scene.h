// A scene is a triangle soup in triangle-id order (docs/design.md §3: faces in file order, an
// n-gon split into n-2 consecutive ids). Loaders and built-in generators produce it; every
// accelerator consumes it.
#pragma once
#include <bit>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <glm/vec3.hpp>
#include <limits>
#include <string>
#include <vector>

namespace gs {

struct Box {
  glm::vec3 lo{std::numeric_limits<float>::infinity()};
  glm::vec3 hi{-std::numeric_limits<float>::infinity()};

  void extend(const glm::vec3& p);
  bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
};

struct Scene {
  std::string name;  // the SCENE argument it was loaded from ("builtin:pyramid", a path)
  std::vector<glm::vec3> vertices;
  std::vector<glm::uvec3> triangles;  // vertex indices; the position is the triangle id

  size_t triangle_count() const { return triangles.size(); }
  const glm::vec3& vertex(uint32_t triangle, int corner) const {
    return vertices[triangles[triangle][corner]];
  }
  Box bounds() const;  // of the vertices used by triangles
  // Zero-area triangles (coincident or collinear corners): kept in the id sequence, set
  // aside by every structure and counted in stats.
  bool is_degenerate(uint32_t triangle) const;
  size_t degenerate_count() const;
};

// Loads SCENE: a path to .obj, .ply or .ply.gz / .obj.gz, or "builtin:NAME".
// Throws InputError ("FILE: problem") for a missing, unreadable or malformed file, NaN or
// infinite coordinates, out-of-range indices, or a scene with no triangles.
Scene load_scene(const std::string& spec);

// Format-specific loaders (used by load_scene; `name` is used in error messages).
Scene load_obj(const std::string& path);
Scene load_ply(const std::string& path);
// Built-in procedural scenes: "pyramid", "lumpy", "sphereflake". Throws InputError for others.
Scene make_builtin_scene(const std::string& name);
std::vector<std::string> builtin_scene_names();

// Writes the scene as OBJ: one `v` per vertex, one `f` per triangle, in id order.
// Throws InputError when the file cannot be written.
void export_obj(const Scene& scene, const std::string& path);

// Splits a polygon (vertex indices in order) into n-2 triangles keeping its vertex order:
// a fan for convex polygons, ear clipping for concave ones.
void triangulate_polygon(const std::vector<glm::vec3>& vertices,
                         const std::vector<uint32_t>& polygon, std::vector<glm::uvec3>& out);

// Where each part of a built-in scene lies in its triangle-id sequence, so that tests, the
// bench and the viewer can tell the parts apart without guessing from geometry. Spheres
// (sphereflake) carry the centre and radius they were tessellated from; `detail` marks the
// small, dense cluster of "lumpy" (the teapot in the stadium).
struct ScenePart {
  std::string label;
  uint32_t first_triangle = 0;
  uint32_t triangle_count = 0;
  bool detail = false;
  glm::dvec3 center{0.0};
  double radius = 0.0;
};
// Parts of built-in scene NAME in id order (they cover every triangle once).
std::vector<ScenePart> builtin_scene_parts(const std::string& name);

// Input limits (README "Limits"), so that a huge or hostile file is a one-line error and
// never an exhausted machine. Loaders hold the whole file, then the scene (12 bytes a
// triangle, 12 a vertex); a structure holds per triangle its corners (36 bytes), a padded
// box while building (48) and references: about 100 bytes a triangle in all, so 2^28
// triangles already take ~27 GB. 2^28 is also about what a 2 GiB binary PLY can describe
// (13 bytes a face), 300 times the largest scene the bench uses (the dragon, 871k
// triangles), and keeps triangle ids and reference counts well inside 32 bits.
inline constexpr uint64_t kMaxSceneFileBytes = uint64_t{2} << 30;  // on disk
inline constexpr uint64_t kMaxSceneDataBytes = uint64_t{4} << 30;  // inflated from gzip
inline constexpr uint64_t kMaxSceneTriangles = uint64_t{1} << 28;  // after triangulation
inline constexpr uint64_t kMaxSceneVertices = uint64_t{1} << 28;

// Throws InputError naming `file` when a scene would hold more vertices or triangles than
// the limits. Loaders may call it with declared counts before allocating; load_scene calls
// it on every scene it returns.
void check_scene_counts(const std::string& file, uint64_t vertices, uint64_t triangles,
                        uint64_t max_vertices = kMaxSceneVertices,
                        uint64_t max_triangles = kMaxSceneTriangles);

namespace detail {
// Reads a whole scene file into memory, inflating it when it starts with the gzip magic.
// Throws InputError naming `path` for a missing file, a directory, a read error, corrupt
// gzip data, a file of more than `file_limit` bytes or more than `limit` bytes of data
// (the latter bounds what a gzip bomb can allocate).
std::string read_scene_file(const std::string& path, uint64_t limit = kMaxSceneDataBytes,
                            uint64_t file_limit = kMaxSceneFileBytes);
// Clinger's fast path ("How to Read Floating Point Numbers Accurately", 1990) for what mesh
// files hold: reads [-]digits[.digits] at `first` when its digits make an integer m <= 2^24
// with at most 10 after the point, and returns where it stopped; nullptr (nothing read)
// otherwise. m and 10^k are then exact floats, so the one correctly rounded division
// m / 10^k is the float nearest the decimal, which std::from_chars gives. The 871k-triangle
// dragon's coordinates took 235 instructions each through from_chars (the token scanned
// first), 136 this way with the scan included. The caller checks that the token ends where
// it stopped.
const char* parse_short_decimal(const char* first, const char* last, float& out);
// Parses a whole token [first, last) as a float with correct rounding (std::from_chars).
// Accepts a leading '+', "nan" and "inf"; an out-of-range magnitude becomes +-inf or 0
// as strtod would give. Returns false when the token is not a number.
bool parse_float(const char* first, const char* last, float& out);
// The run of fewer than 8 decimal digits at p, from the 8 bytes there (all readable): its
// value into `value` and p moved past it, true; false, with nothing changed, when all 8
// bytes are digits. Every byte is classified and the digits combined in a few word
// operations instead of a loop per digit: the 871k-triangle dragon's 3.5 million face
// indices took 7 instructions per digit that way.
inline bool short_digit_run(const char*& p, uint64_t& value) {
  static_assert(std::endian::native == std::endian::little);
  uint64_t word = 0;
  std::memcpy(&word, p, 8);  // byte i is p[i] (x86-64 is little-endian)
  // A byte's top bit ends up set iff it is below '0' (the subtraction borrows) or above '9'
  // (adding 0x46 reaches 0x80). Borrows and carries only ever cross out of a non-digit byte,
  // so the lowest byte flagged is the first non-digit.
  const uint64_t digits = word - 0x3030303030303030u;
  const uint64_t flags = (digits | (word + 0x4646464646464646u)) & 0x8080808080808080u;
  if (flags == 0) return false;
  const int n = std::countr_zero(flags) / 8;  // digits before the first non-digit
  if (n == 0) {
    value = 0;
    return true;
  }
  // The n digit values moved to the top bytes: zero bytes below are leading zeros (the
  // lowest byte is the most significant digit). Then pairs, quadruples and the whole word
  // are combined, each step multiplying the higher-order part by 10, 100 or 10^4.
  uint64_t v = digits << (8 * (8 - n));
  v = (v * 10 + (v >> 8)) & 0x00FF00FF00FF00FFu;
  v = (v * 100 + (v >> 16)) & 0x0000FFFF0000FFFFu;
  v = (v * 10000 + (v >> 32)) & 0xFFFFFFFFu;
  value = v;
  p += n;
  return true;
}

// std::from_chars(first, last, out) for a base-10 int64_t, the same answer for every input,
// with a fast path for what files hold: an optional '-' and at most 18 digits, which cannot
// overflow. Loading the 871k-triangle dragon spent a third of its face parsing in
// from_chars.
inline std::from_chars_result parse_int64(const char* first, const char* last, int64_t& out) {
  const char* digits = first + (first != last && *first == '-');
  if (digits != last && last - digits <= 18) {
    int64_t value = 0;
    const char* p = digits;
    for (; p != last && static_cast<unsigned>(*p - '0') <= 9u; ++p) value = value * 10 + (*p - '0');
    if (p == last) {
      out = digits == first ? value : -value;
      return {last, std::errc()};
    }
  }
  return std::from_chars(first, last, out);
}
}  // namespace detail

}  // namespace gs
