// Our own PLY reader: ascii, binary little- and big-endian, gzip-compressed or not.
// Elements other than `vertex` and `face` and properties other than x, y, z and the face's
// index list are skipped by their declared types. Every count is checked against the bytes
// that could hold it before anything is allocated, so a forged header cannot exhaust memory.
#include <algorithm>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "core/base/error.h"
#include "core/scene/scene.h"

namespace gs {
namespace {

enum class Type : uint8_t { I8, U8, I16, U16, I32, U32, F32, F64 };

struct TypeName {
  std::string_view name;
  Type type;
};
constexpr TypeName kTypeNames[] = {
    {"char", Type::I8},   {"int8", Type::I8},     {"uchar", Type::U8},   {"uint8", Type::U8},
    {"short", Type::I16}, {"int16", Type::I16},   {"ushort", Type::U16}, {"uint16", Type::U16},
    {"int", Type::I32},   {"int32", Type::I32},   {"uint", Type::U32},   {"uint32", Type::U32},
    {"float", Type::F32}, {"float32", Type::F32}, {"double", Type::F64}, {"float64", Type::F64}};

bool is_integer(Type t) { return t < Type::F32; }

size_t size_of(Type t) {
  constexpr size_t kSizes[] = {1, 1, 2, 2, 4, 4, 4, 8};
  return kSizes[static_cast<int>(t)];
}

// The range a value of an integer type can take, to reject ascii values that do not fit.
void integer_range(Type t, int64_t& lo, int64_t& hi) {
  static constexpr int64_t kLo[] = {INT8_MIN, 0, INT16_MIN, 0, INT32_MIN, 0};
  static constexpr int64_t kHi[] = {INT8_MAX,   UINT8_MAX, INT16_MAX,
                                    UINT16_MAX, INT32_MAX, UINT32_MAX};
  lo = kLo[static_cast<int>(t)];
  hi = kHi[static_cast<int>(t)];
}

struct Property {
  std::string name;
  Type type = Type::F32;  // the item type for a list
  bool list = false;
  Type count_type = Type::U8;
};

struct Element {
  std::string name;
  uint64_t count = 0;
  std::vector<Property> properties;
};

enum class Encoding { Ascii, Little, Big };

struct Header {
  Encoding encoding = Encoding::Ascii;
  std::vector<Element> elements;
  size_t data_start = 0;  // offset of the first byte after end_header
};

std::string printable(std::string_view s) {
  std::string out;
  for (char c : s.substr(0, 40)) out += (static_cast<unsigned char>(c) < 32) ? '?' : c;
  return s.size() > 40 ? out + "..." : out;
}

std::string plural(const std::string& element) {
  if (element == "vertex") return "vertices";
  if (element == "face") return "faces";
  return "'" + element + "' elements";
}

// ---------------------------------------------------------------------------------------
// Header

class HeaderParser {
 public:
  HeaderParser(const std::string& path, const std::string& data) : path_(path), data_(data) {}

  Header run() {
    if (!next_line() || line_ != "ply") fail("not a PLY file (it does not start with 'ply')");
    bool have_format = false;
    while (true) {
      if (!next_line()) fail("header has no end_header line");
      split();
      if (tokens_.empty() || tokens_[0] == "comment" || tokens_[0] == "obj_info") continue;
      if (tokens_[0] == "end_header" && tokens_.size() == 1) break;
      if (tokens_[0] == "format") {
        parse_format();
        have_format = true;
      } else if (tokens_[0] == "element") {
        parse_element();
      } else if (tokens_[0] == "property") {
        parse_property();
      } else {
        fail("unexpected header line '" + printable(line_) + "'");
      }
    }
    if (!have_format) fail("header has no format line");
    header_.data_start = pos_;
    return std::move(header_);
  }

 private:
  [[noreturn]] void fail(const std::string& problem) const {
    fail_input(path_, "header line " + std::to_string(line_number_) + ": " + problem);
  }

  bool next_line() {
    const size_t end = data_.find('\n', pos_);
    if (end == std::string::npos) return false;
    line_ = std::string_view(data_).substr(pos_, end - pos_);
    if (!line_.empty() && line_.back() == '\r') line_.remove_suffix(1);
    pos_ = end + 1;
    ++line_number_;
    return true;
  }

  void split() {
    tokens_.clear();
    size_t i = 0;
    while (i < line_.size()) {
      while (i < line_.size() && (line_[i] == ' ' || line_[i] == '\t')) ++i;
      const size_t start = i;
      while (i < line_.size() && line_[i] != ' ' && line_[i] != '\t') ++i;
      if (i > start) tokens_.push_back(line_.substr(start, i - start));
    }
  }

  void parse_format() {
    if (tokens_.size() != 3) fail("malformed format line");
    if (tokens_[2] != "1.0") fail("unsupported PLY version '" + printable(tokens_[2]) + "'");
    if (tokens_[1] == "ascii") {
      header_.encoding = Encoding::Ascii;
    } else if (tokens_[1] == "binary_little_endian") {
      header_.encoding = Encoding::Little;
    } else if (tokens_[1] == "binary_big_endian") {
      header_.encoding = Encoding::Big;
    } else {
      fail("unknown format '" + printable(tokens_[1]) + "'");
    }
  }

  void parse_element() {
    if (tokens_.size() != 3) fail("malformed element line");
    Element element;
    element.name = std::string(tokens_[1]);
    const std::string_view count = tokens_[2];
    const auto [ptr, ec] =
        std::from_chars(count.data(), count.data() + count.size(), element.count);
    if (ec != std::errc() || ptr != count.data() + count.size()) {
      fail("bad element count '" + printable(count) + "'");
    }
    for (const Element& e : header_.elements) {
      if (e.name == element.name) fail("element '" + e.name + "' declared twice");
    }
    header_.elements.push_back(std::move(element));
  }

  Type parse_type(std::string_view name) const {
    for (const TypeName& t : kTypeNames) {
      if (t.name == name) return t.type;
    }
    fail("unknown property type '" + printable(name) + "'");
  }

  void parse_property() {
    if (header_.elements.empty()) fail("property before any element");
    Property p;
    if (tokens_.size() == 5 && tokens_[1] == "list") {
      p.list = true;
      p.count_type = parse_type(tokens_[2]);
      if (!is_integer(p.count_type)) fail("list count type must be an integer type");
      p.type = parse_type(tokens_[3]);
      p.name = std::string(tokens_[4]);
    } else if (tokens_.size() == 3) {
      p.type = parse_type(tokens_[1]);
      p.name = std::string(tokens_[2]);
    } else {
      fail("malformed property line '" + printable(line_) + "'");
    }
    header_.elements.back().properties.push_back(std::move(p));
  }

  const std::string& path_;
  const std::string& data_;
  size_t pos_ = 0;
  size_t line_number_ = 0;
  std::string_view line_;
  std::vector<std::string_view> tokens_;
  Header header_;
};

// The fewest bytes one item of `e` can take: binary, its scalars and list counts (lists may
// be empty); ascii, one digit and one separator per scalar or list count.
uint64_t min_item_bytes(const Element& e, Encoding encoding) {
  uint64_t bytes = 0;
  for (const Property& p : e.properties) {
    if (encoding == Encoding::Ascii) {
      bytes += 2;
    } else {
      bytes += size_of(p.list ? p.count_type : p.type);
    }
  }
  return bytes;
}

// Rejects counts the data cannot hold (before anything is allocated from them).
void check_counts(const std::string& path, const Header& header, size_t data_bytes) {
  unsigned __int128 need = 0;
  for (const Element& e : header.elements) {
    need += static_cast<unsigned __int128>(e.count) * min_item_bytes(e, header.encoding);
    // An ascii file may end without a separator after its last value.
    const unsigned __int128 slack = header.encoding == Encoding::Ascii ? 1 : 0;
    if (need > data_bytes + slack) {
      fail_input(path, "element '" + e.name + "' declares " + std::to_string(e.count) +
                           " items, more than the " + std::to_string(data_bytes) +
                           " bytes of data can hold");
    }
  }
}

// ---------------------------------------------------------------------------------------
// Value sources: where the next number comes from. Each read returns false at the end of the
// data (the caller reports truncation) and throws for a malformed value.

class AsciiSource {
 public:
  AsciiSource(const std::string& path, const std::string& data, size_t start)
      : path_(path), data_(data), p_(data.data() + start), end_(data.data() + data.size()) {}

  bool read_float(Type t, float& out) {
    if (is_integer(t)) {
      int64_t value = 0;
      if (!read_int(t, value)) return false;
      out = static_cast<float>(value);
      return true;
    }
    if (!next_short_decimal(out)) {
      if (!next_token()) return false;
      if (!detail::parse_float(token_, token_end_, out)) bad_token("a number");
    }
    return true;
  }

  // Only for integer types: the header admits no other type for list counts and indices.
  // Inlined into the face loop, where it runs 3.5 million times for the dragon: as a call
  // (which GCC chose once next_digits grew) it cost 30 more instructions each.
  [[gnu::always_inline]] bool read_int(Type t, int64_t& out) {
    if (!next_digits(out)) {
      if (!next_token()) return false;
      const auto [ptr, ec] = detail::parse_int64(token_, token_end_, out);
      if (ec != std::errc() || ptr != token_end_) bad_token("an integer");
    }
    int64_t lo = 0, hi = 0;
    integer_range(t, lo, hi);
    if (out < lo || out > hi) bad_token("a value that fits its type");
    return true;
  }

  bool skip(Type t) {
    float f = 0;
    int64_t i = 0;
    return is_integer(t) ? read_int(t, i) : read_float(t, f);
  }

  // Whether `count` list items could still follow (each needs at least two bytes).
  bool could_hold(uint64_t count, Type) const {
    return count <= static_cast<uint64_t>(end_ - p_) / 2 + 1;
  }

 private:
  // ' ' or one of '\t' '\n' '\v' '\f' '\r', which are consecutive: two compares per byte,
  // not six.
  static bool is_space(char c) { return c == ' ' || static_cast<unsigned>(c - '\t') <= 4u; }

  bool next_token() {
    while (p_ != end_ && is_space(*p_)) ++p_;
    if (p_ == end_) return false;
    token_ = p_;
    while (p_ != end_ && !is_space(*p_)) ++p_;
    token_end_ = p_;
    return true;
  }

  // The next token read and parsed in one pass when it is what face lists hold, up to 18
  // digits and nothing else (no sign, no overflow possible); false, with nothing consumed,
  // for anything else, which the general path then reads. Its own digit loop, not a scan
  // followed by detail::parse_int64: that took 15% more instructions to load the dragon.
  bool next_digits(int64_t& out) {
    const char* p = p_;
    while (p != end_ && is_space(*p)) ++p;
    const char* first = p;
    uint64_t value = 0;  // unsigned: a longer run of digits wraps (and is declined) unharmed
    // Fewer than 8 digits with 8 bytes to read are read a word at a time, others digit by digit.
    if (end_ - p < 8 || !detail::short_digit_run(p, value))
      for (; p != end_ && static_cast<unsigned>(*p - '0') <= 9u; ++p)
        value = value * 10 + unsigned(*p - '0');
    if (p == first || p - first > 18 || (p != end_ && !is_space(*p))) return false;
    token_ = first, token_end_ = p_ = p;
    out = int64_t(value);
    return true;
  }

  // The next token read and parsed in one pass when it is what vertex lists hold, a short
  // decimal (detail::parse_short_decimal) and nothing else; false, with nothing consumed,
  // for anything else, which the general path then reads. Scanning the token first, then
  // parsing it, read every coordinate's bytes twice.
  bool next_short_decimal(float& out) {
    const char* p = p_;
    while (p != end_ && is_space(*p)) ++p;
    const char* stop = detail::parse_short_decimal(p, end_, out);
    if (!stop || (stop != end_ && !is_space(*stop))) return false;
    token_ = p, token_end_ = p_ = stop;
    return true;
  }

  [[noreturn]] void bad_token(const char* expected) const {
    const size_t line = 1 + std::count(data_.data(), token_, '\n');
    fail_input(path_, "line " + std::to_string(line) + ": expected " + expected + ", found '" +
                          printable(std::string_view(token_, token_end_ - token_)) + "'");
  }

  const std::string& path_;
  const std::string& data_;
  const char* p_;
  const char* end_;
  const char* token_ = nullptr;
  const char* token_end_ = nullptr;
};

template <bool kBigEndian>
class BinarySource {
 public:
  BinarySource(const std::string& data, size_t start)
      : p_(data.data() + start), end_(data.data() + data.size()) {}

  bool read_float(Type t, float& out) {
    unsigned char raw[8];
    if (!take(t, raw)) return false;
    out = decode<float>(t, raw);
    return true;
  }

  bool read_int(Type t, int64_t& out) {
    unsigned char raw[8];
    if (!take(t, raw)) return false;
    out = decode<int64_t>(t, raw);
    return true;
  }

  bool skip(Type t) {
    if (static_cast<size_t>(end_ - p_) < size_of(t)) return false;
    p_ += size_of(t);
    return true;
  }

  bool could_hold(uint64_t count, Type t) const {
    return count <= static_cast<uint64_t>(end_ - p_) / size_of(t);
  }

 private:
  bool take(Type t, unsigned char* raw) {
    const size_t n = size_of(t);
    if (static_cast<size_t>(end_ - p_) < n) return false;
    for (size_t i = 0; i < n; ++i)
      raw[i] = static_cast<unsigned char>(p_[kBigEndian ? n - 1 - i : i]);
    p_ += n;
    return true;
  }

  // `raw` is little-endian here whatever the file's order.
  template <class Out>
  static Out decode(Type t, const unsigned char* raw) {
    switch (t) {
      case Type::I8:
        return static_cast<Out>(load<int8_t>(raw));
      case Type::U8:
        return static_cast<Out>(load<uint8_t>(raw));
      case Type::I16:
        return static_cast<Out>(load<int16_t>(raw));
      case Type::U16:
        return static_cast<Out>(load<uint16_t>(raw));
      case Type::I32:
        return static_cast<Out>(load<int32_t>(raw));
      case Type::U32:
        return static_cast<Out>(load<uint32_t>(raw));
      case Type::F32:
        return convert<Out>(load<float>(raw));
      case Type::F64:
        return convert<Out>(load<double>(raw));
    }
    return Out{};
  }

  template <class T>
  static T load(const unsigned char* raw) {
    T value;
    std::memcpy(&value, raw, sizeof(T));
    return value;
  }

  // A float read where an integer is wanted (only for skipped values): avoid the undefined
  // conversion of NaN or huge values.
  template <class Out>
  static Out convert(double v) {
    if constexpr (std::is_integral_v<Out>) {
      return (v > -9e18 && v < 9e18) ? static_cast<Out>(v) : Out{};
    } else {
      return static_cast<Out>(v);
    }
  }

  const char* p_;
  const char* end_;
};

// ---------------------------------------------------------------------------------------
// Body

struct Layout {
  int vertex_element = -1, face_element = -1;
  int xyz[3] = {-1, -1, -1};  // property positions in the vertex element
  int indices = -1;           // position of the index list in the face element
};

int find_property(const Element& e, std::initializer_list<std::string_view> names) {
  for (size_t k = 0; k < e.properties.size(); ++k) {
    for (std::string_view name : names) {
      if (e.properties[k].name == name) return static_cast<int>(k);
    }
  }
  return -1;
}

Layout find_layout(const std::string& path, const Header& header) {
  Layout layout;
  for (size_t i = 0; i < header.elements.size(); ++i) {
    if (header.elements[i].name == "vertex") layout.vertex_element = static_cast<int>(i);
    if (header.elements[i].name == "face") layout.face_element = static_cast<int>(i);
  }
  if (layout.vertex_element >= 0) {
    const Element& v = header.elements[layout.vertex_element];
    const char* names[3] = {"x", "y", "z"};
    for (int c = 0; c < 3; ++c) {
      layout.xyz[c] = find_property(v, {names[c]});
      if (layout.xyz[c] < 0 || v.properties[layout.xyz[c]].list) {
        fail_input(path, std::string("vertex element has no scalar '") + names[c] + "' property");
      }
    }
    if (v.count > UINT32_MAX)
      fail_input(path, "too many vertices (" + std::to_string(v.count) + ")");
  }
  if (layout.face_element >= 0) {
    const Element& f = header.elements[layout.face_element];
    layout.indices = find_property(f, {"vertex_indices", "vertex_index"});
    if (layout.indices < 0 || !f.properties[layout.indices].list ||
        !is_integer(f.properties[layout.indices].type)) {
      fail_input(path, "face element has no integer list 'vertex_indices'");
    }
  }
  return layout;
}

template <class Source>
class BodyReader {
 public:
  BodyReader(const std::string& path, const Header& header, const Layout& layout, Source source)
      : path_(path), header_(header), layout_(layout), source_(source) {
    if (layout.vertex_element >= 0) vertex_count_ = header.elements[layout.vertex_element].count;
  }

  Scene run() {
    for (size_t i = 0; i < header_.elements.size(); ++i) {
      const Element& e = header_.elements[i];
      if (static_cast<int>(i) == layout_.vertex_element) {
        read_vertices(e);
      } else if (static_cast<int>(i) == layout_.face_element) {
        read_faces(e);
      } else {
        skip_element(e);
      }
    }
    return triangulate();
  }

 private:
  [[noreturn]] void truncated(const Element& e, uint64_t got) const {
    fail_input(path_, "truncated: expected " + std::to_string(e.count) + " " + plural(e.name) +
                          ", got " + std::to_string(got));
  }

  bool skip_property(const Property& p) {
    if (!p.list) return source_.skip(p.type);
    int64_t n = 0;
    if (!source_.read_int(p.count_type, n)) return false;
    if (n < 0) fail_input(path_, "negative list length " + std::to_string(n));
    if (!source_.could_hold(static_cast<uint64_t>(n), p.type)) return false;
    for (int64_t k = 0; k < n; ++k) {
      if (!source_.skip(p.type)) return false;
    }
    return true;
  }

  void skip_element(const Element& e) {
    if (e.properties.empty()) return;  // nothing to read, however large the count
    for (uint64_t i = 0; i < e.count; ++i) {
      for (const Property& p : e.properties) {
        if (!skip_property(p)) truncated(e, i);
      }
    }
  }

  void read_vertices(const Element& e) {
    vertices_.resize(e.count);  // bounded by check_counts
    for (uint64_t i = 0; i < e.count; ++i) {
      for (size_t k = 0; k < e.properties.size(); ++k) {
        const Property& p = e.properties[k];
        const int axis = k == size_t(layout_.xyz[0])   ? 0
                         : k == size_t(layout_.xyz[1]) ? 1
                         : k == size_t(layout_.xyz[2]) ? 2
                                                       : -1;
        const bool ok =
            axis >= 0 ? source_.read_float(p.type, vertices_[i][axis]) : skip_property(p);
        if (!ok) truncated(e, i);
      }
    }
  }

  void read_faces(const Element& e) {
    sizes_.reserve(e.count);
    for (uint64_t i = 0; i < e.count; ++i) {
      for (size_t k = 0; k < e.properties.size(); ++k) {
        const bool ok = k == size_t(layout_.indices) ? read_polygon(e.properties[k], i)
                                                     : skip_property(e.properties[k]);
        if (!ok) truncated(e, i);
      }
    }
  }

  bool read_polygon(const Property& p, uint64_t face) {
    int64_t n = 0;
    if (!source_.read_int(p.count_type, n)) return false;
    if (n < 3) {
      fail_input(path_, "face " + std::to_string(face) + " has " + std::to_string(n) +
                            " vertices (at least 3 needed)");
    }
    if (!source_.could_hold(static_cast<uint64_t>(n), p.type)) return false;
    for (int64_t k = 0; k < n; ++k) {
      int64_t index = 0;
      if (!source_.read_int(p.type, index)) return false;
      if (index < 0 || static_cast<uint64_t>(index) >= vertex_count_) {
        fail_input(path_, "face " + std::to_string(face) + ": vertex index " +
                              std::to_string(index) + " out of range (" +
                              std::to_string(vertex_count_) + " vertices)");
      }
      indices_.push_back(static_cast<uint32_t>(index));
    }
    sizes_.push_back(static_cast<uint32_t>(n));
    return true;
  }

  // Done after all elements so that faces may come before vertices in the file.
  Scene triangulate() {
    Scene scene;
    scene.name = path_;
    scene.vertices = std::move(vertices_);
    scene.triangles.reserve(indices_.size() - 2 * sizes_.size());
    std::vector<uint32_t> polygon;
    const uint32_t* next = indices_.data();
    for (const uint32_t n : sizes_) {
      if (n == 3) {
        scene.triangles.emplace_back(next[0], next[1], next[2]);
      } else {
        polygon.assign(next, next + n);
        triangulate_polygon(scene.vertices, polygon, scene.triangles);
      }
      next += n;
    }
    return scene;
  }

  const std::string& path_;
  const Header& header_;
  const Layout& layout_;
  Source source_;
  uint64_t vertex_count_ = 0;
  std::vector<glm::vec3> vertices_;
  std::vector<uint32_t> indices_;  // every polygon's corners, concatenated
  std::vector<uint32_t> sizes_;
};

template <class Source>
Scene read_body(const std::string& path, const Header& header, const Layout& layout,
                Source source) {
  return BodyReader<Source>(path, header, layout, source).run();
}

}  // namespace

Scene load_ply(const std::string& path) {
  const std::string data = detail::read_scene_file(path);
  const Header header = HeaderParser(path, data).run();
  check_counts(path, header, data.size() - header.data_start);
  const Layout layout = find_layout(path, header);
  switch (header.encoding) {
    case Encoding::Ascii:
      return read_body(path, header, layout, AsciiSource(path, data, header.data_start));
    case Encoding::Little:
      return read_body(path, header, layout, BinarySource<false>(data, header.data_start));
    case Encoding::Big:
      return read_body(path, header, layout, BinarySource<true>(data, header.data_start));
  }
  return Scene();
}

}  // namespace gs
