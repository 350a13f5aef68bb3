#!/bin/sh
# The main job on a fresh Debian 12 machine (as root): install what gridscope needs, build a
# Release binary into build/, and render the built-in "lumpy" scene to out/lumpy.png.
set -eu
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j2 --target gridscope
mkdir -p out
image=$(build/app/gridscope render builtin:lumpy --out out/lumpy.png --size 640x480)
echo "run.sh: image written to $(pwd)/$image"
