#!/bin/sh
# The test job on a fresh Debian 12 machine (as root): install what gridscope needs, build
# into build/, run every test suite. CI runs exactly this (.ci/run).
set -eu
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j2
# Per-test limit (--timeout) and an overall one, so a hung test fails the run instead of
# stalling it.
timeout 3600 ctest --test-dir build --output-on-failure -j2 --timeout 600
# The lazy build is shared by tracing threads: run the multi-threaded tests again under
# ThreadSanitizer (any data race it reports fails the test).
cmake -S . -B build-tsan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DGRIDSCOPE_TSAN=ON
cmake --build build-tsan -j2 --target test_grid1d test_stress test_progressive test_grid3d_bvh
TSAN_OPTIONS="halt_on_error=1 exitcode=66" timeout 1800 ctest --test-dir build-tsan \
  --output-on-failure -j2 --timeout 600 -R 'lazy_t2|Grid1DBuild|Grid3DBuild|Laziness|Progressive'
