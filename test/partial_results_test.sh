#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Whole results or none: a run that fills the disk (a file-size limit, `ulimit -f`) or is killed (SIGTERM,
# SIGINT, SIGKILL at several moments) leaves either no result or the complete one in its output folder, never
# a part of one, and no temporary file in it; the staging folder of a run killed by SIGKILL is removed by the
# next run into the same folder.
#   partial_results_test.sh CLI
set -u
cli=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fails=0
passes=0
ok() { passes=$((passes + 1)); }
bad() { echo "FAIL: $*"; fails=$((fails + 1)); }

# A geodesic sphere (an octahedron subdivided 5 times: 1026 vertices, 2048 faces) and the same sphere
# squashed, with 6 features at the octahedron's corners: a layout whose refined meshes are about 50 KB each,
# a map of a second or so.
python3 - "$work" <<'EOM'
import sys, math
work = sys.argv[1]
v = [(1,0,0),(-1,0,0),(0,1,0),(0,-1,0),(0,0,1),(0,0,-1)]
f = [(0,2,4),(2,1,4),(1,3,4),(3,0,4),(2,0,5),(1,2,5),(3,1,5),(0,3,5)]
for _ in range(4):
    mid = {}
    def m(a, b):
        k = (min(a, b), max(a, b))
        if k not in mid:
            p = [(x + y) / 2 for x, y in zip(v[a], v[b])]
            n = math.sqrt(sum(x * x for x in p))
            v.append(tuple(x / n for x in p)); mid[k] = len(v) - 1
        return mid[k]
    f = [t for a, b, c in f for t in ((a, m(a, b), m(c, a)), (b, m(b, c), m(a, b)), (c, m(c, a), m(b, c)), (m(a, b), m(b, c), m(c, a)))]
for name, s in (("a.off", (1, 1, 1)), ("b.off", (1.4, 0.8, 0.6))):
    with open(f"{work}/{name}", "w") as out:
        out.write(f"OFF\n{len(v)} {len(f)} 0\n")
        for p in v: out.write(" ".join(repr(x * k) for x, k in zip(p, s)) + "\n")
        for t in f: out.write("3 %d %d %d\n" % t)
with open(f"{work}/features.txt", "w") as out:
    for i in range(6): out.write(f"{i} {i}\n")
EOM

layout_files="source_refined.off target_refined.off source_patches.txt target_patches.txt source_patches.ply
              target_patches.ply base_mesh.txt report.json"
map_files="source_to_target.txt target_to_source.txt checker.png checker.mtl source_checker.obj target_checker.obj
           report.json"

# check_whole DIR NAME [FILES]: DIR holds nothing or every file of the result (the layout's by default), and no
# temporary file.
check_whole() {
  local dir=$1 name=$2 files=${3:-$layout_files} present=0 missing=0
  for f in $files; do
    if [ -e "$dir/$f" ]; then present=$((present + 1)); else missing=$((missing + 1)); fi
  done
  if [ $present -ne 0 ] && [ $missing -ne 0 ]; then bad "$name: a partial result ($present files of $((present + missing)))"; return; fi
  if [ -n "$(find "$dir" -name '*.tmp-*' 2>/dev/null)" ]; then bad "$name: temporary files left"; return; fi
  ok
}

# The disk fills up: a file-size limit of 16 KB lets the small files through and stops the refined meshes.
out="$work/full"
(ulimit -f 16; "$cli" layout "$work/a.off" "$work/b.off" --features "$work/features.txt" -o "$out" --quiet) 2>"$work/stderr"
rc=$?
if [ $rc -ne 1 ]; then bad "disk full: exit code $rc, expected 1: $(cat "$work/stderr")"; else ok; fi
grep -qi "write error\|file too large\|disk" "$work/stderr" || bad "disk full: no write error reported: $(cat "$work/stderr")"
check_whole "$out" "disk full"
[ -z "$(ls -A "$out" 2>/dev/null)" ] || bad "disk full: files left in the output folder: $(ls -A "$out")"
[ -z "$(find "$work" -maxdepth 1 -name '.full.crossparam-*')" ] || bad "disk full: the staging folder was left"

# The complete map, for its duration.
start=$(date +%s%N)
"$cli" map "$work/a.off" "$work/b.off" --features "$work/features.txt" -o "$work/whole" --quiet || bad "the map failed"
ms=$((($(date +%s%N) - start) / 1000000))
check_whole "$work/whole" "complete run" "$map_files"

# Killed at moments spread over the run (the last ones while the files are being written).
for sig in TERM INT KILL; do
  for frac in 10 40 70 90 95 98; do
    out="$work/kill_${sig}_$frac"
    "$cli" map "$work/a.off" "$work/b.off" --features "$work/features.txt" -o "$out" --quiet 2>/dev/null &
    pid=$!
    sleep "$(awk -v ms="$ms" -v f="$frac" 'BEGIN {printf "%.3f", ms * f / 100000}')"
    kill -s "$sig" "$pid" 2>/dev/null
    wait "$pid" 2>/dev/null
    check_whole "$out" "kill -$sig at $frac%" "$map_files"
    if [ "$sig" != KILL ] && [ -n "$(find "$work" -maxdepth 1 -name ".kill_${sig}_$frac.crossparam-*")" ]; then
      bad "kill -$sig at $frac%: the staging folder was left"
    fi
  done
done

# The staging folder of a SIGKILLed run is removed by the next run into the same folder.
"$cli" layout "$work/a.off" "$work/b.off" --features "$work/features.txt" -o "$work/kill_KILL_40" --quiet ||
  bad "the run after a killed one failed"
check_whole "$work/kill_KILL_40" "after a killed run" "$layout_files"
[ -z "$(find "$work" -maxdepth 1 -name '.kill_KILL_40.crossparam-*')" ] || bad "a killed run's staging folder was not removed"

echo "partial results: $passes passed, $fails failed"
[ $fails -eq 0 ]
