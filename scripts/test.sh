#!/bin/sh
# The test job on a fresh Debian 12 machine (as root): install what gridscope needs, then
# run the stages below, each timed. CI runs exactly this (.ci/run) on 2 cores and must stay
# under 30 minutes. Every stage is a CMake preset (CMakePresets.json) a person can run alone:
#   cmake --preset NAME && cmake --build --preset NAME && ctest --preset NAME
# The presets hold the per-test time limit and the sanitizer options; `timeout` adds an
# overall one, so a hung test fails the run instead of stalling it.
set -eu
cd "$(dirname "$0")/.."
./scripts/install-deps.sh

summary=""
# Runs stage $1 (the rest of the arguments is its command) and prints its elapsed time.
stage() {
  name=$1
  shift
  echo "== stage $name" >&2
  start=$(date +%s)
  "$@"
  elapsed=$(($(date +%s) - start))
  echo "== stage $name: ${elapsed} s" >&2
  summary="$summary $name ${elapsed}s"
}

# 1. Every suite on the Release build (build/).
release() {
  cmake --preset release
  cmake --build --preset release
  timeout 3600 ctest --preset release
}

# 2. The whole suite again under AddressSanitizer + UndefinedBehaviorSanitizer
# (build-asan/): any memory error, leak or undefined behaviour fails its test. The gridscope
# binary the CLI, shot and view tests run is instrumented too. Built at -O1 with line tables
# only (-g1): half the compile time of -O2 with full debug information, and a report still
# names file and line.
asan() {
  cmake --preset asan
  cmake --build --preset asan
  timeout 3600 ctest --preset asan
}

# 3. The lazy builds (grid1d, grid3d) are shared by tracing threads, and the progressive
# renderer runs on worker threads: their multi-threaded tests (the preset's GTEST_FILTER)
# again under ThreadSanitizer (build-tsan/; any data race fails the test).
tsan() {
  cmake --preset tsan
  cmake --build --preset tsan
  timeout 1800 ctest --preset tsan
}

stage release release
stage asan asan
stage tsan tsan
# 4. Every fuzz target (tests/fuzz) for 10 s on a copy of its seed corpus: any crash, leak,
# hang or disagreement with brute force fails the run.
stage fuzz ./scripts/fuzz.sh 10
echo "== all stages passed:$summary" >&2
