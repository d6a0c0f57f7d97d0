#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Regenerates the tables of doc/results.md from the bench programs. Builds nothing: build the targets
# bench_layout, bench_map, bench_remesh, bench_accuracy and test_pipeline first.
#
#   bash benchmark/make_results.sh [BUILD_DIR [BENCH_DIR [TABLE...]]]
#
# BUILD_DIR defaults to build, BENCH_DIR to ../shared/bench beside the repository; TABLE is one of layout, map, remesh-0.5, remesh-1,
# remesh-overlay, accuracy, wide, wide-off, wide-all, wide-straight, wide-map (default: all; the five wider-bench tables read ../shared/data through
# bench_accuracy, not BENCH_DIR). Each table's output replaces the text between its markers in doc/results.md:
#   <!-- make_results: TABLE BEGIN --> ... <!-- make_results: TABLE END -->
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
bench=${2:-$here/../shared/bench}
shift $(( $# < 2 ? $# : 2 ))
tables=("$@")
[ ${#tables[@]} -gt 0 ] || tables=(layout map remesh-0.5 remesh-1 remesh-overlay accuracy wide wide-off wide-all wide-straight wide-map)
results="$here/doc/results.md"
cd "$here"

need() {
  [ -x "$1" ] || { echo "make_results: $1 not found; build it first (cmake --build $build --target $(basename "$1"))" >&2; exit 1; }
}

# Replaces the text between the markers of table $1 in doc/results.md with the contents of file $2.
replace() {
  local name=$1 body=$2 out
  grep -q "<!-- make_results: $name BEGIN -->" "$results" || { echo "make_results: no markers for $name in $results" >&2; exit 1; }
  out=$(mktemp)
  awk -v name="$name" -v body="$body" '
    $0 == "<!-- make_results: " name " BEGIN -->" { print; while ((getline line < body) > 0) print line; skip = 1; next }
    $0 == "<!-- make_results: " name " END -->" { skip = 0 }
    !skip { print }' "$results" > "$out"
  mv "$out" "$results"
}

tmp=$(mktemp)
trap 'rm -f "$tmp"' EXIT
for t in "${tables[@]}"; do
  echo "make_results: $t" >&2
  case "$t" in
    layout)     need "$build/benchmark/bench_layout"; "$build/benchmark/bench_layout" "$bench" > "$tmp" ;;
    map)        need "$build/benchmark/bench_map"; "$build/benchmark/bench_map" "$bench" > "$tmp" ;;
    remesh-0.5) need "$build/benchmark/bench_remesh"; "$build/benchmark/bench_remesh" "$bench" 0.5 > "$tmp" ;;
    remesh-1)   need "$build/benchmark/bench_remesh"; "$build/benchmark/bench_remesh" "$bench" 1.0 > "$tmp" ;;
    remesh-overlay)
      # The decimated overlay alone at every tolerance, one case at a time; the first case's output keeps its
      # header.
      need "$build/benchmark/bench_remesh"
      first=1
      for c in wolf0_wolf2 shrec_381_382 shrec_383_385 horse0_horse7 yang_cat_horse lion_cat; do
        if [ $first = 1 ]; then
          "$build/benchmark/bench_remesh" "$bench" 1,0.5,0.2,0.1 "$c" --construction=overlay > "$tmp"; first=0
        else
          "$build/benchmark/bench_remesh" "$bench" 1,0.5,0.2,0.1 "$c" --construction=overlay | grep "^| $c " >> "$tmp"
        fi
      done ;;
    accuracy)
      need "$build/test/test_pipeline"
      { echo '```text'
        "$build/test/test_pipeline" --gtest_filter='Shared/BenchMap*' | grep '^\[ accuracy \]'
        echo '```'; } > "$tmp" ;;
    wide)           need "$build/benchmark/bench_accuracy"; "$build/benchmark/bench_accuracy" > "$tmp" ;;
    wide-off)       need "$build/benchmark/bench_accuracy"; "$build/benchmark/bench_accuracy" --extremity-features off > "$tmp" ;;
    wide-all)       need "$build/benchmark/bench_accuracy"; "$build/benchmark/bench_accuracy" --extremity-features all > "$tmp" ;;
    wide-straight)  need "$build/benchmark/bench_accuracy"; "$build/benchmark/bench_accuracy" --straighten-paths > "$tmp" ;;
    wide-map)       need "$build/benchmark/bench_accuracy"; "$build/benchmark/bench_accuracy" --map-smoothing on > "$tmp" ;;
    *) echo "make_results: unknown table '$t' (layout, map, remesh-0.5, remesh-1, remesh-overlay, accuracy, wide, wide-off, wide-all, wide-straight, wide-map)" >&2; exit 2 ;;
  esac
  # The bench programs print a header line, a blank line and a table; drop trailing blank lines.
  sed -i -e :a -e '/^\n*$/{$d;N;ba' -e '}' "$tmp"
  replace "$t" "$tmp"
done
