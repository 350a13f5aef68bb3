// The bodies of the fuzz targets. Each entry takes arbitrary bytes, feeds them to one part of
// gridscope and checks docs/design.md §3.10's promise on them: bad input is an InputError or a
// UsageError naming what is wrong, never a crash, a hang or a silent wrong answer. The
// libFuzzer executables (fuzz_target.cpp) and the GoogleTest replay of the corpora and of
// every finding kept as a regression (tests/test_fuzz_regressions.cpp) call the same entry,
// so the ordinary test run checks every input the fuzzers were ever given as seeds or found.
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace gs::fuzz {

struct Outcome {
  bool accepted = false;              // the input was valid: loaded, parsed, traced
  size_t checks = 0;                  // answers compared with an independent one
  std::vector<std::string> problems;  // broken promises, one line each; empty when none
};

using Entry = Outcome (*)(std::span<const uint8_t> data);

// Scene files through load_scene (the bytes are written to a scratch file NAME.obj or
// NAME.ply, gzip-compressed or not): a scene that loads is well formed and survives an
// export_obj round trip bit for bit; a rejection is an InputError naming the file.
Outcome fuzz_obj(std::span<const uint8_t> data);
Outcome fuzz_ply(std::span<const uint8_t> data);
// Ray and hit files through read_rays / read_hits: accepted exactly when the size is a
// multiple of the record, records equal the bytes and write back to the same bytes. The
// rays of an accepted ray file (at most 64) are also traced through every structure over a
// small scene of wall-aligned triangles and compared with brute force, as fuzz_differential.
Outcome fuzz_rays(std::span<const uint8_t> data);
Outcome fuzz_hits(std::span<const uint8_t> data);
// The bytes split at NUL into argv (without the program name) for app::parse_cli, which must
// return a runnable command or throw UsageError / InputError.
Outcome fuzz_cli(std::span<const uint8_t> data);
// The bytes choose a small scene (at most 64 triangles on and off a lattice, shared corners,
// T-junctions, coincident and degenerate triangles, raw floats), at most 64 rays (origins on
// walls, edges and vertices, directions with zero, -0 and tiny components, odd tmin/tmax)
// and structure parameters; every exact structure must answer as brute force (see
// fuzz_differential.cpp).
Outcome fuzz_differential(std::span<const uint8_t> data);

struct Target {
  const char* name;  // the corpus folder tests/fuzz/corpus/NAME and the executable fuzz_NAME
  Entry entry;
};
std::span<const Target> targets();
// The entry of target `name`, or nullptr.
Entry entry_named(const std::string& name);

}  // namespace gs::fuzz
