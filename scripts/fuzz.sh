#!/bin/bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Builds the libFuzzer harnesses of the readers (test/fuzz, clang with ASan and UBSan) and runs each for a
# while; exits non-zero at the first finding (the crashing input is left in the corpus directory).
#
#   scripts/fuzz.sh [SECONDS [BUILD_DIR [PARALLEL]]]
#
# SECONDS per harness (default 60), BUILD_DIR the clang build tree (default build-fuzz), PARALLEL how many
# harnesses run at once (default 1). Each harness keeps its corpus in BUILD_DIR/corpus/FORMAT, seeded with a
# tetrahedron in its format. Run it at low priority on a shared machine: nice -n 19 scripts/fuzz.sh 600 build-fuzz 2
set -euo pipefail
seconds=${1:-60}
build=${2:-build-fuzz}
parallel=${3:-1}
root=$(cd "$(dirname "$0")/.." && pwd)
formats="off obj ply stl features"

cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
  -DCROSSPARAM_BUILD_FUZZERS=ON -DCROSSPARAM_BUILD_TESTS=OFF -DCROSSPARAM_BUILD_TOOLS=OFF \
  -DCROSSPARAM_BUILD_EXAMPLES=OFF -DCROSSPARAM_BUILD_BENCHMARKS=OFF >/dev/null
for f in $formats; do cmake --build "$build" --target "fuzz_$f" -j1; done

# A tetrahedron in each format (and a feature file), the seed of each corpus.
seed() {
  local v="0 0 0\n1 0 0\n0 1 0\n0 0 1\n" t="0 2 1\n0 1 3\n0 3 2\n1 2 3\n"
  case $1 in
  off) printf "OFF\n4 4 0\n$v" ; printf "$t" | sed 's/^/3 /' ;;
  obj) printf "$v" | sed 's/^/v /'; printf "1 3 2\n1 2 4\n1 4 3\n2 3 4\n" | sed 's/^/f /' ;;
  ply) printf "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
       printf "element face 4\nproperty list uchar int vertex_indices\nend_header\n$v"; printf "$t" | sed 's/^/3 /' ;;
  stl) printf "solid t\nfacet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 0 1 0\nvertex 1 0 0\nendloop\nendfacet\n"
       printf "facet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 0 1\nendloop\nendfacet\n"
       printf "facet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 0 0 1\nvertex 0 1 0\nendloop\nendfacet\n"
       printf "facet normal 0 0 0\nouter loop\nvertex 1 0 0\nvertex 0 1 0\nvertex 0 0 1\nendloop\nendfacet\nendsolid t\n" ;;
  features) printf "# source target\n0 0\n1 5\n2 9 # comment\n3 12\n" ;;
  esac
}

run_one() {
  local f=$1 corpus="$build/corpus/$1"
  mkdir -p "$corpus"
  seed "$f" >"$corpus/seed"
  echo "fuzz_$f: $seconds s"
  "$build/test/fuzz/fuzz_$f" "$corpus" -max_total_time="$seconds" -max_len=65536 -timeout=10 -rss_limit_mb=2048 \
    -artifact_prefix="$build/corpus/$f-" >"$build/fuzz_$f.log" 2>&1 \
    || { echo "fuzz_$f: FINDING, see $build/fuzz_$f.log"; return 1; }
  echo "fuzz_$f: $(grep -o 'Done [0-9]* runs' "$build/fuzz_$f.log" | tail -1), no finding"
}

status=0
running=0
for f in $formats; do
  run_one "$f" &
  running=$((running + 1))
  if [ "$running" -ge "$parallel" ]; then wait -n || status=1; running=$((running - 1)); fi
done
while [ "$running" -gt 0 ]; do wait -n || status=1; running=$((running - 1)); done
exit $status
