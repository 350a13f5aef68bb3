// The file-format and command-line entries (fuzz_entries.h) and the list of targets; the
// differential entry is in fuzz_differential.cpp.
#include "tests/fuzz/fuzz_entries.h"

#include <unistd.h>

#include <cmath>
#include <cstring>
#include <exception>
#include <filesystem>
#include <glm/vec2.hpp>
#include <string_view>
#include <system_error>

#include "app/cli.h"
#include "core/base/error.h"
#include "core/base/files.h"
#include "core/geometry/ray_io.h"
#include "core/scene/scene.h"
#include "tests/fuzz/differential.h"

namespace gs::fuzz {
namespace {

constexpr size_t kMaxTracedRays = 64;  // keeps an execution of the ray-file target fast

// The loaders take paths, and load_scene picks the format by the extension, so the bytes go
// to a file: in a folder of this process's own (removed at exit), as fuzzers may run in
// parallel processes.
class ScratchFolder {
 public:
  ScratchFolder()
      : folder_(std::filesystem::temp_directory_path() /
                ("gridscope-fuzz-" + std::to_string(::getpid()))) {
    std::filesystem::create_directories(folder_);
  }
  ~ScratchFolder() {
    std::error_code ignored;
    std::filesystem::remove_all(folder_, ignored);
  }
  std::string path(const std::string& name) const { return (folder_ / name).string(); }

 private:
  std::filesystem::path folder_;
};

std::string scratch_path(const std::string& name) {
  static const ScratchFolder folder;
  return folder.path(name);
}

std::string write_scratch(const std::string& name, std::span<const uint8_t> data) {
  const std::string path = scratch_path(name);
  write_file(path, {reinterpret_cast<const char*>(data.data()), data.size()});
  return path;
}

// Anything but the documented errors escaping an entry breaks docs/design.md §3.10's promise (main
// would report "error: ..."); a std::bad_alloc on inputs this small means a count read from
// the input was trusted.
template <class Body>
Outcome guarded(Body&& body) {
  try {
    return body();
  } catch (const std::exception& e) {
    Outcome outcome;
    outcome.problems.push_back(std::string("unexpected exception: ") + e.what());
    return outcome;
  }
}

// Every loader words its errors "FILE: problem".
void expect_names_file(const InputError& e, const std::string& path, Outcome& outcome) {
  const std::string_view message = e.what();
  if (!message.starts_with(path + ": ") || message.size() == path.size() + 2)
    outcome.problems.push_back("InputError does not name the file " + path + ": " +
                               std::string(message));
}

// What load_scene promises of a scene it returns (core/scene/scene.h).
void check_scene(const Scene& scene, Outcome& outcome) {
  if (scene.triangles.empty()) outcome.problems.push_back("a scene with no triangles loaded");
  for (const glm::uvec3& triangle : scene.triangles) {
    for (int c = 0; c < 3; ++c) {
      if (triangle[c] >= scene.vertices.size()) {
        outcome.problems.push_back("vertex index " + std::to_string(triangle[c]) +
                                   " out of range loaded");
        return;
      }
      const glm::vec3& p = scene.vertices[triangle[c]];
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
        outcome.problems.push_back("a triangle with a non-finite corner loaded");
        return;
      }
    }
  }
  ++outcome.checks;
}

// Equal bits, or both NaN (a NaN can only be in a vertex no triangle uses; its payload
// does not survive printing).
bool same_float(float a, float b) {
  return std::memcmp(&a, &b, sizeof a) == 0 || (std::isnan(a) && std::isnan(b));
}

// export_obj writes each float with 9 significant digits, so loading the export gives back
// the same triangles, in the same order, and the same vertices bit for bit.
void check_export_round_trip(const Scene& scene, Outcome& outcome) {
  const std::string path = scratch_path("export.obj");
  export_obj(scene, path);
  Scene again;
  try {
    again = load_scene(path);
  } catch (const InputError& e) {
    outcome.problems.push_back(std::string("the export does not load: ") + e.what());
    return;
  }
  bool same = again.triangles == scene.triangles && again.vertices.size() == scene.vertices.size();
  for (size_t i = 0; same && i < scene.vertices.size(); ++i)
    for (int a = 0; a < 3; ++a)
      same = same && same_float(again.vertices[i][a], scene.vertices[i][a]);
  if (!same) outcome.problems.push_back("the export loads as another scene");
  ++outcome.checks;
}

Outcome fuzz_scene_file(std::span<const uint8_t> data, const std::string& name) {
  return guarded([&] {
    Outcome outcome;
    const std::string path = write_scratch(name, data);
    try {
      const Scene scene = load_scene(path);
      outcome.accepted = true;
      check_scene(scene, outcome);
      check_export_round_trip(scene, outcome);
    } catch (const InputError& e) {
      expect_names_file(e, path, outcome);
    }
    return outcome;
  });
}

// A file of fixed-size records: read exactly when its size is a multiple of the record,
// the records are its bytes, and writing them back gives the same bytes.
template <class Record>
Outcome check_record_file(std::span<const uint8_t> data, const std::string& name,
                          std::vector<Record> (*read)(const std::string&),
                          void (*write)(const std::string&, std::span<const Record>)) {
  Outcome outcome;
  const std::string path = write_scratch(name, data);
  const bool whole = data.size() % sizeof(Record) == 0;
  try {
    const std::vector<Record> records = read(path);
    outcome.accepted = true;
    if (!whole) outcome.problems.push_back("accepted a size not a multiple of the record");
    const bool same = records.size() * sizeof(Record) == data.size() &&
                      (data.empty() || std::memcmp(records.data(), data.data(), data.size()) == 0);
    if (!same) outcome.problems.push_back("the records read differ from the file's bytes");
    const std::string copy = scratch_path("copy-" + name);
    write(copy, records);
    const std::vector<char> written = read_file(copy);
    if (written.size() != data.size() ||
        (!data.empty() && std::memcmp(written.data(), data.data(), data.size()) != 0))
      outcome.problems.push_back("the records written back differ from the file");
    outcome.checks += 2;
  } catch (const InputError& e) {
    if (whole) outcome.problems.push_back(std::string("rejected whole records: ") + e.what());
    expect_names_file(e, path, outcome);
  }
  return outcome;
}

// The scene ray files are traced through: the unit box's faces and its mid-planes x, y, z =
// 1/2, each square two triangles, so that rays meet triangles lying in cell walls, and edges
// and corners shared by several triangles.
Scene wall_scene() {
  Scene scene;
  scene.name = "walls";
  for (int axis = 0; axis < 3; ++axis) {
    for (const float c : {0.0f, 0.5f, 1.0f}) {
      const uint32_t first = uint32_t(scene.vertices.size());
      for (const glm::vec2 st :
           {glm::vec2(0, 0), glm::vec2(1, 0), glm::vec2(1, 1), glm::vec2(0, 1)}) {
        glm::vec3 p;
        p[axis] = c, p[(axis + 1) % 3] = st.x, p[(axis + 2) % 3] = st.y;
        scene.vertices.push_back(p);
      }
      scene.triangles.emplace_back(first, first + 1, first + 2);
      scene.triangles.emplace_back(first, first + 2, first + 3);
    }
  }
  return scene;
}

std::vector<std::string> split_at_nul(std::span<const uint8_t> data) {
  std::vector<std::string> words;
  std::string word;
  for (const uint8_t c : data) {
    if (c != 0) {
      word += char(c);
    } else {
      words.push_back(std::move(word));
      word.clear();
    }
  }
  if (!word.empty()) words.push_back(std::move(word));  // a final NUL ends the last word
  return words;
}

}  // namespace

Outcome fuzz_obj(std::span<const uint8_t> data) { return fuzz_scene_file(data, "input.obj"); }

Outcome fuzz_ply(std::span<const uint8_t> data) { return fuzz_scene_file(data, "input.ply"); }

Outcome fuzz_hits(std::span<const uint8_t> data) {
  return guarded([&] { return check_record_file<Hit>(data, "input.hits", read_hits, write_hits); });
}

Outcome fuzz_rays(std::span<const uint8_t> data) {
  return guarded([&] {
    Outcome outcome = check_record_file<Ray>(data, "input.rays", read_rays, write_rays);
    if (!outcome.accepted || !outcome.problems.empty()) return outcome;
    std::vector<Ray> rays(std::min(data.size() / sizeof(Ray), kMaxTracedRays));
    if (!rays.empty()) std::memcpy(rays.data(), data.data(), rays.size() * sizeof(Ray));
    StructureSettings settings;
    settings.params.memory_budget = uint64_t{16} << 20;
    check_against_brute(wall_scene(), rays, settings, outcome);
    return outcome;
  });
}

Outcome fuzz_cli(std::span<const uint8_t> data) {
  return guarded([&] {
    Outcome outcome;
    try {
      const app::Command command = app::parse_cli(split_at_nul(data));
      outcome.accepted = true;
      if (!command.run) outcome.problems.push_back("parse_cli returned nothing to run");
      ++outcome.checks;
    } catch (const UsageError&) {
    } catch (const InputError&) {
    }
    return outcome;
  });
}

std::span<const Target> targets() {
  static constexpr Target kTargets[] = {{"obj", fuzz_obj},   {"ply", fuzz_ply},
                                        {"rays", fuzz_rays}, {"hits", fuzz_hits},
                                        {"cli", fuzz_cli},   {"differential", fuzz_differential}};
  return kTargets;
}

Entry entry_named(const std::string& name) {
  for (const Target& target : targets())
    if (name == target.name) return target.entry;
  return nullptr;
}

}  // namespace gs::fuzz
