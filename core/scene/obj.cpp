// Wavefront OBJ loading through tinyobjloader, without its triangulation (docs/design.md §3).
//
// tinyobjloader is lenient where we must be strict: it reads indices with atoi (an index
// too large for int silently becomes another vertex), turns an unparsable coordinate into
// 0, and drops faces with bad indices with only a warning. So a strict scan of the `v` and
// `f` lines runs first; it rejects what tinyobjloader would accept wrongly, and it supplies
// the coordinates (std::from_chars rounds correctly, which makes export round trips exact).
// tinyobjloader then provides the face structure, cross-checked against the scan.
#include <tiny_obj_loader.h>

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <istream>
#include <streambuf>
#include <string>
#include <string_view>
#include <vector>

#include "core/base/error.h"
#include "core/scene/scene.h"

namespace gs {
namespace {

// Statements of the OBJ format (and tinyobjloader's extensions) that may appear; anything
// else means the file is not OBJ or is damaged.
constexpr std::string_view kKnownStatements[] = {
    "v",          "vt",        "vn",    "vp",    "f",      "l",        "p",
    "g",          "o",         "s",     "mg",    "usemtl", "mtllib",   "maplib",
    "usemap",     "cstype",    "deg",   "bmat",  "step",   "curv",     "curv2",
    "surf",       "parm",      "trim",  "hole",  "scrv",   "sp",       "end",
    "con",        "lod",       "ctech", "stech", "bevel",  "c_interp", "d_interp",
    "shadow_obj", "trace_obj", "call",  "csh",   "vw",     "t"};

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

// Splits one line into whitespace-separated tokens (views into the line).
void split(std::string_view line, std::vector<std::string_view>& tokens) {
  tokens.clear();
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_space(line[i])) ++i;
    const size_t start = i;
    while (i < line.size() && !is_space(line[i])) ++i;
    if (i > start) tokens.push_back(line.substr(start, i - start));
  }
}

// What the strict scan learned: coordinates and the faces as 0-based vertex indices.
struct ObjScan {
  std::vector<glm::vec3> vertices;
  std::vector<uint32_t> face_indices;  // all faces' corners, concatenated
  std::vector<uint32_t> face_sizes;
  int64_t max_positive = 0;  // positive indices may refer forward: checked at the end
  size_t max_positive_line = 0;
};

class ObjScanner {
 public:
  explicit ObjScanner(const std::string& path) : path_(path) {}

  ObjScan run(const std::string& text) {
    size_t start = 0;
    while (start < text.size()) {
      size_t end = text.find('\n', start);
      if (end == std::string::npos) end = text.size();
      ++line_;
      scan_line(std::string_view(text).substr(start, end - start));
      start = end + 1;
    }
    if (scan_.max_positive > static_cast<int64_t>(scan_.vertices.size())) {
      line_ = scan_.max_positive_line;
      fail("vertex index " + std::to_string(scan_.max_positive) + " out of range (" +
           std::to_string(scan_.vertices.size()) + " vertices)");
    }
    return std::move(scan_);
  }

 private:
  [[noreturn]] void fail(const std::string& problem) const {
    fail_input(path_, "line " + std::to_string(line_) + ": " + problem);
  }

  void scan_line(std::string_view line) {
    split(line, tokens_);
    if (tokens_.empty() || tokens_[0][0] == '#') return;
    const std::string_view keyword = tokens_[0];
    if (keyword == "v") return scan_vertex();
    if (keyword == "f") return scan_face();
    for (std::string_view known : kKnownStatements) {
      if (keyword == known) return;
    }
    fail("unknown statement '" + printable(keyword) + "'");
  }

  void scan_vertex() {
    if (tokens_.size() < 4) fail("a vertex needs x y z coordinates");
    float xyz[3] = {0, 0, 0};
    for (size_t i = 1; i < tokens_.size(); ++i) {
      float value = 0;
      const std::string_view t = tokens_[i];
      if (!detail::parse_float(t.data(), t.data() + t.size(), value)) {
        fail("bad vertex coordinate '" + printable(t) + "'");
      }
      if (i <= 3) xyz[i - 1] = value;
    }
    scan_.vertices.emplace_back(xyz[0], xyz[1], xyz[2]);
  }

  void scan_face() {
    if (tokens_.size() < 4) fail("a face needs at least 3 vertices");
    for (size_t i = 1; i < tokens_.size(); ++i) {
      scan_.face_indices.push_back(resolve(tokens_[i]));
    }
    scan_.face_sizes.push_back(static_cast<uint32_t>(tokens_.size() - 1));
  }

  // "i", "i/t", "i//n" or "i/t/n": returns the 0-based vertex index of i.
  uint32_t resolve(std::string_view token) {
    const size_t slash = token.find('/');
    const std::string_view digits = token.substr(0, slash);
    int64_t index = 0;
    const auto [ptr, ec] = detail::parse_int64(digits.data(), digits.data() + digits.size(), index);
    // tinyobjloader keeps indices in int: anything beyond is an overflow for both of us.
    if (ec == std::errc::result_out_of_range || index > INT32_MAX || index < INT32_MIN) {
      fail("vertex index '" + printable(digits) + "' overflows");
    }
    if (ec != std::errc() || ptr != digits.data() + digits.size()) {
      fail("bad vertex index '" + printable(token) + "'");
    }
    if (index == 0) fail("vertex index 0 (OBJ indices start at 1)");
    if (index > 0) {
      if (index > scan_.max_positive) {
        scan_.max_positive = index;
        scan_.max_positive_line = line_;
      }
      return static_cast<uint32_t>(index - 1);
    }
    const int64_t count = static_cast<int64_t>(scan_.vertices.size());
    if (count + index < 0) {
      fail("relative vertex index " + std::to_string(index) + " out of range (" +
           std::to_string(count) + " vertices so far)");
    }
    return static_cast<uint32_t>(count + index);
  }

  // Garbage may hold control bytes: keep messages on one printable line.
  static std::string printable(std::string_view s) {
    std::string out;
    for (char c : s.substr(0, 40)) {
      out += (static_cast<unsigned char>(c) < 32 || c == 127) ? '?' : c;
    }
    return s.size() > 40 ? out + "..." : out;
  }

  const std::string& path_;
  size_t line_ = 0;
  ObjScan scan_;
  std::vector<std::string_view> tokens_;
};

// Lets tinyobjloader read the in-memory text (inflated .obj.gz included) without a copy.
class MemoryBuffer : public std::streambuf {
 public:
  explicit MemoryBuffer(std::string& text) {
    setg(text.data(), text.data(), text.data() + text.size());
  }
};

std::string first_line(const std::string& s) {
  const size_t start = s.find_first_not_of("\n. ");
  if (start == std::string::npos) return s;
  return s.substr(start, s.find('\n', start) - start);
}

// Warnings about indices or dropped faces mean tinyobjloader changed the geometry;
// warnings about materials do not matter here.
bool is_geometry_warning(const std::string& line) {
  return line.find("ndex") != std::string::npos || line.find("ndices") != std::string::npos ||
         line.find("egenerate") != std::string::npos || line.find("face") != std::string::npos;
}

void check_tinyobj_messages(const std::string& path, bool ok, const std::string& warn,
                            const std::string& err) {
  if (!ok || !err.empty()) fail_input(path, "tinyobjloader: " + first_line(err));
  size_t start = 0;
  while (start < warn.size()) {
    const size_t end = std::min(warn.find('\n', start), warn.size());
    const std::string line = warn.substr(start, end - start);
    if (is_geometry_warning(line)) fail_input(path, "tinyobjloader: " + line);
    start = end + 1;
  }
}

// tinyobjloader's faces, concatenated over its shapes (which follow file order).
void collect_faces(const std::vector<tinyobj::shape_t>& shapes, std::vector<uint32_t>& indices,
                   std::vector<uint32_t>& sizes) {
  for (const tinyobj::shape_t& shape : shapes) {
    size_t k = 0;
    for (const unsigned int n : shape.mesh.num_face_vertices) {
      for (unsigned int c = 0; c < n; ++c) {
        indices.push_back(static_cast<uint32_t>(shape.mesh.indices[k++].vertex_index));
      }
      sizes.push_back(n);
    }
  }
}

}  // namespace

Scene load_obj(const std::string& path) {
  std::string text = detail::read_scene_file(path);
  ObjScan scan = ObjScanner(path).run(text);

  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warn, err;
  MemoryBuffer buffer(text);
  std::istream stream(&buffer);
  // No material reader: materials are ignored, so a missing .mtl cannot fail the load.
  const bool ok = tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, &stream, nullptr,
                                   /*triangulate=*/false, /*default_vcols_fallback=*/false);
  check_tinyobj_messages(path, ok, warn, err);

  std::vector<uint32_t> indices, sizes;
  collect_faces(shapes, indices, sizes);
  if (attrib.vertices.size() != 3 * scan.vertices.size() || indices != scan.face_indices ||
      sizes != scan.face_sizes) {
    fail_input(path, "tinyobjloader and the strict scan disagree about the faces");
  }

  Scene scene;
  scene.name = path;
  scene.vertices = std::move(scan.vertices);
  scene.triangles.reserve(indices.size() - 2 * sizes.size());
  std::vector<uint32_t> polygon;
  size_t k = 0;
  for (const uint32_t n : sizes) {
    polygon.assign(indices.begin() + k, indices.begin() + k + n);
    k += n;
    triangulate_polygon(scene.vertices, polygon, scene.triangles);
  }
  return scene;
}

}  // namespace gs
