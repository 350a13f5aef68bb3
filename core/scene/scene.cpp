// Scene basics shared by every loader: boxes, degeneracy, dispatch by SCENE spec, whole-file
// reading (with gzip), validation, OBJ export and polygon triangulation (docs/design.md §3).
#include "core/scene/scene.h"

#include <libdeflate.h>
#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <memory>
#include <optional>
#include <string_view>

#include "core/base/error.h"

namespace gs {

void Box::extend(const glm::vec3& p) {
  lo = glm::vec3(std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z));
  hi = glm::vec3(std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z));
}

Box Scene::bounds() const {
  Box box;
  for (const glm::uvec3& t : triangles) {
    for (int c = 0; c < 3; ++c) box.extend(vertices[t[c]]);
  }
  return box;
}

bool Scene::is_degenerate(uint32_t triangle) const {
  // Products of float differences are (nearly always) exact in double, so "exactly zero"
  // means the corners really are collinear or coincident, not that float rounding said so.
  const glm::dvec3 a(vertex(triangle, 0)), b(vertex(triangle, 1)), c(vertex(triangle, 2));
  const glm::dvec3 n = glm::cross(b - a, c - a);
  return n.x == 0.0 && n.y == 0.0 && n.z == 0.0;
}

size_t Scene::degenerate_count() const {
  size_t count = 0;
  for (uint32_t t = 0; t < triangles.size(); ++t) count += is_degenerate(t) ? 1 : 0;
  return count;
}

// ---------------------------------------------------------------------------------------
// Reading files

namespace detail {
namespace {

using FilePtr = std::unique_ptr<FILE, int (*)(FILE*)>;

std::string errno_text() { return std::strerror(errno); }

// fopen() happily opens a directory on Linux and only the first read fails, with a less
// helpful message; a missing file is left to fopen(), whose errno says why.
void check_not_directory(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) fail_input(path, "is a directory, not a file");
}

bool starts_with_gzip_magic(FILE* f) {
  unsigned char magic[2] = {0, 0};
  const size_t got = std::fread(magic, 1, 2, f);
  std::rewind(f);
  return got == 2 && magic[0] == 0x1f && magic[1] == 0x8b;
}

uint64_t file_size(const std::string& path, FILE* f) {
  std::fseek(f, 0, SEEK_END);
  const long size = std::ftell(f);
  std::rewind(f);
  if (size < 0) fail_input(path, "cannot read file: " + errno_text());
  return static_cast<uint64_t>(size);
}

std::string read_plain(const std::string& path, FILE* f, uint64_t size) {
  std::string data(static_cast<size_t>(size), '\0');
  if (std::fread(data.data(), 1, data.size(), f) != data.size()) {
    fail_input(path, "cannot read file: " + errno_text());
  }
  return data;
}

// The gzip trailer holds the input size modulo 2^32: a hint for reserving, never trusted
// beyond the maximum deflate ratio (~1032:1) so that a forged trailer allocates nothing big.
size_t gzip_size_hint(FILE* f, uint64_t limit) {
  unsigned char t[4];
  std::fseek(f, 0, SEEK_END);
  const long size = std::ftell(f);
  if (size < 18 || std::fseek(f, -4, SEEK_END) != 0 || std::fread(t, 1, 4, f) != 4) return 0;
  std::rewind(f);
  const uint64_t hint = t[0] | (t[1] << 8) | (t[2] << 16) | (uint64_t{t[3]} << 24);
  return static_cast<size_t>(std::min({hint, limit, uint64_t(size) * 1032}));
}

// The fast path of read_gzip: the whole file decompressed by libdeflate into a buffer of
// the trailer's size (three times zlib's speed: 38 ms against 115 ms for the 8 MB dragon),
// member after member. Null when the data do not fit that buffer or anything is wrong with
// them: then zlib's streaming path reads the file, with its checks and its messages.
std::optional<std::string> read_gzip_whole(FILE* f, uint64_t compressed, size_t hint) {
  std::string in(static_cast<size_t>(compressed), '\0');
  std::rewind(f);
  if (std::fread(in.data(), 1, in.size(), f) != in.size()) return std::nullopt;
  std::unique_ptr<libdeflate_decompressor, void (*)(libdeflate_decompressor*)> decompressor(
      libdeflate_alloc_decompressor(), libdeflate_free_decompressor);
  if (!decompressor) return std::nullopt;
  std::string out(hint, '\0');
  size_t read = 0, written = 0;
  while (read < in.size()) {
    size_t member_in = 0, member_out = 0;
    if (libdeflate_gzip_decompress_ex(decompressor.get(), in.data() + read, in.size() - read,
                                      out.data() + written, out.size() - written, &member_in,
                                      &member_out) != LIBDEFLATE_SUCCESS)
      return std::nullopt;
    read += member_in;
    written += member_out;
  }
  out.resize(written);
  return out;
}

std::string read_gzip(const std::string& path, FILE* f, uint64_t compressed, uint64_t limit) {
  const size_t hint = gzip_size_hint(f, limit);
  if (std::optional<std::string> whole = read_gzip_whole(f, compressed, hint)) return *whole;
  constexpr size_t kChunk = size_t{1} << 20;
  std::string data;
  data.reserve(hint + kChunk);  // the last read asks for a whole chunk
  gzFile gz = gzopen(path.c_str(), "rb");
  if (gz == nullptr) fail_input(path, "cannot open file: " + errno_text());
  std::unique_ptr<gzFile_s, int (*)(gzFile)> guard(gz, gzclose);
  gzbuffer(gz, 1 << 18);
  for (;;) {
    const size_t old = data.size();
    data.resize(old + kChunk);
    const int got = gzread(gz, data.data() + old, kChunk);
    if (got < 0) {
      int code = 0;
      fail_input(path, std::string("corrupt gzip data: ") + gzerror(gz, &code));
    }
    data.resize(old + static_cast<size_t>(got));
    if (data.size() > limit) {
      fail_input(path, "decompressed data exceeds the " + std::to_string(limit) + "-byte limit");
    }
    if (got == 0) break;
  }
  // zlib reports a stream cut short only through gzerror, after a short read.
  int code = Z_OK;
  const char* message = gzerror(gz, &code);
  if (code != Z_OK) fail_input(path, std::string("corrupt gzip data: ") + message);
  return data;
}

}  // namespace

std::string read_scene_file(const std::string& path, uint64_t limit, uint64_t file_limit) {
  check_not_directory(path);
  FilePtr f(std::fopen(path.c_str(), "rb"), std::fclose);
  if (!f) fail_input(path, "cannot open file: " + errno_text());
  const bool gzip = starts_with_gzip_magic(f.get());
  const uint64_t size = file_size(path, f.get());
  // A plain file's bytes are its data: both limits apply to it.
  const uint64_t most = gzip ? file_limit : std::min(file_limit, limit);
  if (size > most) {
    fail_input(path, "file is larger than the " + std::to_string(most) + "-byte limit");
  }
  return gzip ? read_gzip(path, f.get(), size, limit) : read_plain(path, f.get(), size);
}

const char* parse_short_decimal(const char* first, const char* last, float& out) {
  static constexpr float kTens[] = {1e0f, 1e1f, 1e2f, 1e3f, 1e4f, 1e5f,
                                    1e6f, 1e7f, 1e8f, 1e9f, 1e10f};
  const bool negative = first != last && *first == '-';
  const char* p = first + negative;
  uint64_t m = 0;  // wraps past 19 digits, which are declined
  int digits = 0;
  for (; p != last && static_cast<unsigned>(*p - '0') <= 9u; ++p, ++digits)
    m = m * 10 + uint64_t(*p - '0');
  int fraction = 0;
  if (p != last && *p == '.')
    for (++p; p != last && static_cast<unsigned>(*p - '0') <= 9u; ++p, ++fraction)
      m = m * 10 + uint64_t(*p - '0');
  if (digits + fraction == 0 || digits + fraction > 19 || fraction > 10 || m > (uint64_t{1} << 24))
    return nullptr;
  // m and 10^fraction are exact floats: one correctly rounded division.
  const float value = float(m) / kTens[fraction];
  out = negative ? -value : value;
  return p;
}

bool parse_float(const char* first, const char* last, float& out) {
  // std::from_chars rejects a leading '+' that strtod and most writers accept.
  if (first != last && *first == '+' && last - first > 1 && first[1] != '-' && first[1] != '+') {
    ++first;
  }
  if (parse_short_decimal(first, last, out) == last) return true;
  const auto [ptr, ec] = std::from_chars(first, last, out);
  if (ptr != last || first == last) return false;
  if (ec == std::errc()) return true;
  if (ec != std::errc::result_out_of_range) return false;
  // Overflow must become inf (then rejected as non-finite), underflow zero or a denormal:
  // strtod knows which; it needs a terminated copy, and this path is rare.
  const std::string copy(first, last);
  out = std::strtof(copy.c_str(), nullptr);
  return true;
}

}  // namespace detail

// ---------------------------------------------------------------------------------------
// Dispatch and validation

namespace {

enum class Format { Obj, Ply, Unknown };

Format format_of(const std::string& path) {
  std::string lower(path);
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  const std::string_view s(lower);
  if (s.ends_with(".obj") || s.ends_with(".obj.gz")) return Format::Obj;
  if (s.ends_with(".ply") || s.ends_with(".ply.gz")) return Format::Ply;
  return Format::Unknown;
}

// Checks what every structure relies on; `first_index` is 1 for OBJ so that a message
// quotes the vertex number a person would look up in the file.
void validate(const Scene& scene, const std::string& file, int first_index) {
  if (scene.triangles.empty()) fail_input(file, "no triangles");
  check_scene_counts(file, scene.vertices.size(), scene.triangles.size());
  for (const glm::uvec3& t : scene.triangles) {
    for (int c = 0; c < 3; ++c) {
      const uint32_t v = t[c];
      if (v >= scene.vertices.size()) {
        fail_input(file, "vertex index " + std::to_string(v + first_index) + " out of range");
      }
      const glm::vec3& p = scene.vertices[v];
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
        fail_input(file,
                   "vertex " + std::to_string(v + first_index) + " has a non-finite coordinate");
      }
    }
  }
}

}  // namespace

void check_scene_counts(const std::string& file, uint64_t vertices, uint64_t triangles,
                        uint64_t max_vertices, uint64_t max_triangles) {
  const auto check = [&](uint64_t count, uint64_t most, const char* what) {
    if (count > most)
      fail_input(file, std::to_string(count) + " " + what + ", more than the limit of " +
                           std::to_string(most));
  };
  check(vertices, max_vertices, "vertices");
  check(triangles, max_triangles, "triangles");
}

Scene load_scene(const std::string& spec) {
  constexpr std::string_view kBuiltin = "builtin:";
  Scene scene;
  int first_index = 0;
  if (std::string_view(spec).starts_with(kBuiltin)) {
    scene = make_builtin_scene(spec.substr(kBuiltin.size()));
  } else {
    switch (format_of(spec)) {
      case Format::Obj:
        scene = load_obj(spec);
        first_index = 1;
        break;
      case Format::Ply:
        scene = load_ply(spec);
        break;
      case Format::Unknown:
        fail_input(spec,
                   "unknown scene format (expected .obj, .ply, .obj.gz, .ply.gz or "
                   "builtin:NAME)");
    }
  }
  validate(scene, spec, first_index);
  scene.name = spec;
  return scene;
}

// ---------------------------------------------------------------------------------------
// Export

void export_obj(const Scene& scene, const std::string& path) {
  detail::FilePtr f(std::fopen(path.c_str(), "wb"), std::fclose);
  if (!f) fail_input(path, "cannot write file: " + detail::errno_text());
  std::fprintf(f.get(), "# gridscope export of %s: %zu vertices, %zu triangles\n",
               scene.name.c_str(), scene.vertices.size(), scene.triangles.size());
  // %.9g: nine significant digits bring every float back bit for bit.
  for (const glm::vec3& v : scene.vertices) {
    std::fprintf(f.get(), "v %.9g %.9g %.9g\n", v.x, v.y, v.z);
  }
  for (const glm::uvec3& t : scene.triangles) {
    std::fprintf(f.get(), "f %u %u %u\n", t.x + 1, t.y + 1, t.z + 1);
  }
  const bool write_error = std::ferror(f.get()) != 0;
  if (std::fclose(f.release()) != 0 || write_error) {
    fail_input(path, "cannot write file: " + detail::errno_text());
  }
}

// ---------------------------------------------------------------------------------------
// Triangulation

namespace {

// Ear clipping is quadratic or worse; real concave faces have at most a few hundred corners
// (gears: 144), so beyond this a polygon is fanned instead of risking a hang.
constexpr size_t kMaxEarClipCorners = 1024;

void fan(const std::vector<uint32_t>& polygon, std::vector<glm::uvec3>& out) {
  for (size_t i = 1; i + 1 < polygon.size(); ++i) {
    out.emplace_back(polygon[0], polygon[i], polygon[i + 1]);
  }
}

double orient(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

// Projects the polygon onto the plane of its Newell normal, in a right-handed frame around
// that normal, so that the polygon's own winding becomes counter-clockwise (positive area).
// Returns false when the normal vanishes (collinear or self-cancelling polygon).
bool project(const std::vector<glm::vec3>& vertices, const std::vector<uint32_t>& polygon,
             std::vector<glm::dvec2>& out) {
  const size_t n = polygon.size();
  const glm::dvec3 origin(vertices[polygon[0]]);
  glm::dvec3 normal(0.0);
  for (size_t i = 0; i < n; ++i) {
    const glm::dvec3 a = glm::dvec3(vertices[polygon[i]]) - origin;
    const glm::dvec3 b = glm::dvec3(vertices[polygon[(i + 1) % n]]) - origin;
    normal +=
        glm::dvec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
  }
  const double length = glm::length(normal);
  if (!(length > 0.0) || !std::isfinite(length)) return false;
  const glm::dvec3 w = normal / length;
  const glm::dvec3 helper = std::abs(w.x) > 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0);
  const glm::dvec3 u = glm::normalize(glm::cross(helper, w));
  const glm::dvec3 v = glm::cross(w, u);
  out.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const glm::dvec3 p = glm::dvec3(vertices[polygon[i]]) - origin;
    out[i] = glm::dvec2(glm::dot(p, u), glm::dot(p, v));
  }
  return true;
}

// Convex when no corner turns right by more than rounding noise: nearly straight corners
// of a convex face must keep the fan, which is what the file's author most likely meant.
bool is_convex(const std::vector<glm::dvec2>& p) {
  const size_t n = p.size();
  for (size_t i = 0; i < n; ++i) {
    const glm::dvec2& a = p[(i + n - 1) % n];
    const glm::dvec2& b = p[i];
    const glm::dvec2& c = p[(i + 1) % n];
    const double scale = glm::length(b - a) * glm::length(c - b);
    if (orient(a, b, c) < -1e-9 * scale) return false;
  }
  return true;
}

class EarClipper {
 public:
  EarClipper(const std::vector<glm::dvec2>& points, const std::vector<uint32_t>& polygon)
      : p_(points), polygon_(polygon), next_(points.size()), prev_(points.size()) {
    const size_t n = points.size();
    for (size_t i = 0; i < n; ++i) {
      next_[i] = (i + 1) % n;
      prev_[i] = (i + n - 1) % n;
    }
  }

  void run(std::vector<glm::uvec3>& out) {
    size_t remaining = p_.size();
    size_t i = 1;  // first ear (0,1,2) when possible, so clipping starts like the fan
    size_t misses = 0;
    bool relaxed = false;  // second chance: allow zero-area ears at collinear corners
    while (remaining > 3) {
      if (is_ear(i, relaxed)) {
        emit(i, out);
        const size_t after = next_[i];
        unlink(i);
        i = after;
        --remaining;
        misses = 0;
        relaxed = false;
      } else if (++misses <= remaining) {
        i = next_[i];
      } else if (!relaxed) {
        relaxed = true;
        misses = 0;
      } else {
        return fan_rest(i, out);  // self-intersecting: a fan still gives n-2 triangles
      }
    }
    emit(i, out);
  }

 private:
  bool is_ear(size_t i, bool relaxed) const {
    const glm::dvec2 &a = p_[prev_[i]], &b = p_[i], &c = p_[next_[i]];
    const double turn = orient(a, b, c);
    if (relaxed) {
      // Collinear corner (up to rounding): cutting it off adds a zero-area triangle on the
      // boundary and nothing can lie inside it.
      return std::abs(turn) <= 1e-12 * glm::length(b - a) * glm::length(c - b);
    }
    if (!(turn > 0.0)) return false;
    for (size_t j = next_[next_[i]]; j != prev_[i]; j = next_[j]) {
      const glm::dvec2& q = p_[j];
      if (q == a || q == b || q == c) continue;  // a repeated corner (bridge) does not block
      if (orient(a, b, q) >= 0.0 && orient(b, c, q) >= 0.0 && orient(c, a, q) >= 0.0) {
        return false;
      }
    }
    return true;
  }

  void emit(size_t i, std::vector<glm::uvec3>& out) const {
    out.emplace_back(polygon_[prev_[i]], polygon_[i], polygon_[next_[i]]);
  }

  void unlink(size_t i) {
    next_[prev_[i]] = next_[i];
    prev_[next_[i]] = prev_[i];
  }

  void fan_rest(size_t start, std::vector<glm::uvec3>& out) const {
    std::vector<uint32_t> rest{polygon_[start]};
    for (size_t j = next_[start]; j != start; j = next_[j]) rest.push_back(polygon_[j]);
    fan(rest, out);
  }

  const std::vector<glm::dvec2>& p_;
  const std::vector<uint32_t>& polygon_;
  std::vector<size_t> next_, prev_;
};

}  // namespace

void triangulate_polygon(const std::vector<glm::vec3>& vertices,
                         const std::vector<uint32_t>& polygon, std::vector<glm::uvec3>& out) {
  const size_t n = polygon.size();
  if (n < 3) return;
  if (n == 3) {
    out.emplace_back(polygon[0], polygon[1], polygon[2]);
    return;
  }
  std::vector<glm::dvec2> points;
  if (n > kMaxEarClipCorners || !project(vertices, polygon, points) || is_convex(points)) {
    return fan(polygon, out);
  }
  EarClipper(points, polygon).run(out);
}

}  // namespace gs
