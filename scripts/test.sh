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
