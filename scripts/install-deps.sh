#!/bin/sh
# Installs the Debian 12 packages gridscope builds, tests and runs with.
# Idempotent: packages already present are skipped, so a warm machine pays nothing.
set -eu
packages="cmake ninja-build g++ pkg-config zlib1g-dev libdeflate-dev libpng-dev libglm-dev libtinyobjloader-dev libstb-dev
nlohmann-json3-dev libgtest-dev libbenchmark-dev libembree-dev libtbb-dev
libglfw3-dev libimgui-dev libosmesa6-dev python3-glad xvfb xauth
clang libclang-rt-14-dev"
missing=""
for p in $packages; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "ok installed" || missing="$missing $p"
done
[ -z "$missing" ] && exit 0
if [ "$(id -u)" != 0 ]; then
  echo "install-deps: missing Debian packages:$missing (run this script as root)" >&2
  exit 1
fi
echo "install-deps: installing$missing" >&2
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
# shellcheck disable=SC2086
apt-get install -y -qq --no-install-recommends $missing >/dev/null
