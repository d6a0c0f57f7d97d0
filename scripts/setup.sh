#!/usr/bin/env bash
# crossparam set-up: install what is missing (Debian 12, as root), build, then
#   demo  - run the crossparam CLI on the built-in example with pictures (writes out/demo/; installs POV-Ray,
#           which renders them)
#   test  - run the whole test suite
# SPDX-License-Identifier: GPL-3.0-or-later
set -euo pipefail
mode=${1:-demo}
case "$mode" in
  demo|test) ;;
  *) echo "usage: scripts/setup.sh [demo|test]" >&2; exit 2;;
esac
here=$(cd "$(dirname "$0")/.." && pwd)
cd "$here"

packages=(g++ make cmake libcgal-dev libeigen3-dev libboost-dev libgmp-dev libmpfr-dev libgtest-dev libbenchmark-dev)
if [ "$mode" = demo ]; then
  packages+=(povray) # renders the demo's pictures (--png)
fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

jobs=$(nproc)
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
case "$mode" in
  demo)
    cmake --build build --target crossparam_cli -j "$jobs"
    ./build/tools/crossparam demo -o out/demo --png
    echo "setup: the demo's meshes and pictures (*.png) are in $here/out/demo/ and $here/out/demo/morph/"
    ;;
  test)
    cmake --build build -j "$jobs"
    cd build && ctest --output-on-failure -j "$jobs"
    ;;
  *) echo "usage: scripts/setup.sh [demo|test]" >&2; exit 2;;
esac
