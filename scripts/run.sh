#!/bin/sh
# The main job on a fresh Debian 12 machine (as root): install what gridscope needs, build a
# Release binary into build/, and render the built-in "lumpy" scene to out/lumpy.png.
set -eu
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j2 --target gridscope
mkdir -p out
# The "teapot" cluster at the centre of the stadium, seen from inside it.
image=$(build/app/gridscope render builtin:lumpy --out out/lumpy.png --size 640x480 \
  --camera "eye=3.2,-4.2,2.2;target=0,0,0.35;up=0,0,1;fov=40")
echo "run.sh: image written to $(pwd)/$image"
