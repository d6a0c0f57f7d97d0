#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# End-to-end checks of the crossparam CLI: bad input gives one line on stderr, a non-zero exit code and no
# output; the demo and (when ../shared is present) a bench case write every promised file.
set -u
cli=$1
shared=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fails=0
passes=0
ok() { passes=$((passes + 1)); }
bad() { echo "FAIL: $*"; fails=$((fails + 1)); }

# expect_error NAME EXPECTED_WORDS -- ARGS...: non-zero exit, one stderr line containing the words, no output dir
expect_error() {
  local name=$1 words=$2
  shift 3
  rm -rf "$work/out"
  "$cli" "$@" >"$work/stdout" 2>"$work/stderr"
  local rc=$?
  local lines
  lines=$(wc -l <"$work/stderr")
  if [ $rc -eq 0 ]; then bad "$name: exit code 0"; return; fi
  if [ "$lines" -ne 1 ]; then bad "$name: $lines stderr lines: $(cat "$work/stderr")"; return; fi
  if ! grep -qi -- "$words" "$work/stderr"; then bad "$name: message lacks '$words': $(cat "$work/stderr")"; return; fi
  if [ -e "$work/out" ] && [ -n "$(ls -A "$work/out")" ]; then bad "$name: wrote output"; return; fi
  ok
}

# A valid octahedron.
cat >"$work/octa.off" <<'EOM'
OFF
6 8 0
1 0 0
-1 0 0
0 1 0
0 -1 0
0 0 1
0 0 -1
3 0 2 4
3 2 1 4
3 1 3 4
3 3 0 4
3 2 0 5
3 1 2 5
3 3 1 5
3 0 3 5
EOM
printf '0 0\n1 1\n2 2\n4 4\n' >"$work/f4.txt"
printf '0 0\n1 1\n2 2\n' >"$work/f3.txt"
printf '0 0\n1 1\n2 2\n9 4\n' >"$work/frange.txt"
printf '0 0\n1 1\nx 2\n4 4\n' >"$work/fbad.txt"
printf '0 0\n1 1\n1 2\n4 4\n' >"$work/fdup.txt"
head -c 40 "$work/octa.off" >"$work/truncated.off"
sed 's/^3 0 2 4$/4 0 2 4 5/' "$work/octa.off" >"$work/quad.off"
sed '/^3 0 3 5$/d; s/^6 8 0$/6 7 0/' "$work/octa.off" >"$work/open.off"
sed 's/^1 0 0$/nan 0 0/' "$work/octa.off" >"$work/nan.off"
sed 's/^3 0 2 4$/3 0 2 44/' "$work/octa.off" >"$work/index.off"
printf 'OFF\n999999999999 1 0\n0 0 0\n' >"$work/huge.off"

expect_error missing-file "does not exist\|no such\|cannot" -- layout "$work/none.off" "$work/octa.off" --features "$work/f4.txt" -o "$work/out"
expect_error truncated "truncated\|end of file\|expected" -- layout "$work/truncated.off" "$work/octa.off" --features "$work/f4.txt" -o "$work/out"
expect_error non-triangle "triangle" -- layout "$work/quad.off" "$work/octa.off" --features "$work/f4.txt" -o "$work/out"
expect_error open "open\|boundary\|border" -- layout "$work/open.off" "$work/octa.off" --features "$work/f4.txt" -o "$work/out"
expect_error nan "finite\|nan" -- layout "$work/nan.off" "$work/octa.off" --features "$work/f4.txt" -o "$work/out"
expect_error face-index "range" -- layout "$work/index.off" "$work/octa.off" --features "$work/f4.txt" -o "$work/out"
expect_error huge-count "count\|vertices\|size" -- layout "$work/huge.off" "$work/octa.off" --features "$work/f4.txt" -o "$work/out"
awk 'NR>=3 && NR<=8 {printf "%.17g %.17g %.17g\n", $1*1e150, $2*1e150, $3*1e150; next} {print}' "$work/octa.off" >"$work/huge_scale.off"
awk 'NR>=3 && NR<=8 {printf "%.17g %.17g %.17g\n", $1*1e-150, $2*1e-150, $3*1e-150; next} {print}' "$work/octa.off" >"$work/tiny_scale.off"
expect_error huge-scale "range" -- layout "$work/huge_scale.off" "$work/octa.off" --features "$work/f4.txt" -o "$work/out"
if "$cli" layout "$work/tiny_scale.off" "$work/octa.off" --features "$work/f4.txt" -o "$work/tiny" --quiet; then ok; else bad "coordinates at 1e-150 should work"; fi
expect_error few-features "4" -- layout "$work/octa.off" "$work/octa.off" --features "$work/f3.txt" -o "$work/out"
expect_error feature-range "range" -- layout "$work/octa.off" "$work/octa.off" --features "$work/frange.txt" -o "$work/out"
expect_error feature-malformed "line 3" -- layout "$work/octa.off" "$work/octa.off" --features "$work/fbad.txt" -o "$work/out"
expect_error feature-duplicate "twice\|same\|duplicate\|already" -- layout "$work/octa.off" "$work/octa.off" --features "$work/fdup.txt" -o "$work/out"
expect_error usage "usage\|needs\|help" -- layout "$work/octa.off"
expect_error unknown-command "unknown" -- frobnicate
expect_error map-few-features "4" -- map "$work/octa.off" "$work/octa.off" --features "$work/f3.txt" -o "$work/out"
expect_error bad-iterations "iterations" -- map "$work/octa.off" "$work/octa.off" --features "$work/f4.txt" -o "$work/out" --iterations x
if [ -d "$shared/data/nasty" ]; then
  expect_error nasty-cubes "non-manifold" -- layout "$shared/data/nasty/cgal/cubes.off" "$work/octa.off" --features "$work/f4.txt" -o "$work/out"
  expect_error nasty-crasher "" -- layout "$shared/data/nasty/cgal-io-crashers/ply_binary_huge_alloc.ply" "$work/octa.off" --features "$work/f4.txt" -o "$work/out"
  expect_error genus "genus" -- layout "$shared/data/models/cgal/knot.off" "$work/octa.off" --features "$work/f4.txt" -o "$work/out"
fi

# A valid run: octahedron to itself with 4 features.
if "$cli" layout "$work/octa.off" "$work/octa.off" --features "$work/f4.txt" -o "$work/ok" --quiet; then
  for f in source_refined.off target_refined.off source_patches.txt target_patches.txt base_mesh.txt \
           source_patches.ply target_patches.ply report.json; do
    [ -s "$work/ok/$f" ] || bad "layout: missing $f"
  done
  [ "$(grep -vc '^#' "$work/ok/base_mesh.txt")" -eq 4 ] || bad "layout: octahedron with 4 features should have 4 base triangles"
  ok
else
  bad "layout on a valid octahedron failed"
fi

# The demo.
if "$cli" demo -o "$work/demo" --quiet; then
  for f in source.off target.off features.txt source_patches.txt report.json source_to_target.txt \
           target_to_source.txt source_checker.obj target_checker.obj checker.png checker.mtl \
           source_compatible.off target_compatible.off target_error.ply morph/frame_000.off morph/frame_008.off; do
    [ -s "$work/demo/$f" ] || bad "demo: missing $f"
  done
  # The source-shaped output starts with the source's vertices, unchanged.
  nv=$(sed -n 2p "$work/demo/source.off" | awk '{print $1}')
  cmp -s <(sed -n "3,$((nv + 2))p" "$work/demo/source.off") <(sed -n "3,$((nv + 2))p" "$work/demo/source_compatible.off") ||
    bad "remesh: source_compatible.off does not start with the source's vertices"
  # Same face lists.
  ns=$(sed -n 2p "$work/demo/source_compatible.off" | awk '{print $1}')
  grep -q '"verification": {"valid": true' "$work/demo/report.json" || bad "demo: the remeshing is not verified valid"
  cmp -s <(tail -n +$((ns + 3)) "$work/demo/source_compatible.off") <(tail -n +$((ns + 3)) "$work/demo/target_compatible.off") ||
    bad "remesh: the two outputs have different faces"
  ok
  # morph rejects meshes that are not compatible, and bad frame counts.
  expect_error morph-incompatible "not compatible" -- morph "$work/demo/source.off" "$work/demo/target.off" --frames 3 -o "$work/out"
  expect_error morph-frames "frames" -- morph "$work/demo/source_compatible.off" "$work/demo/target_compatible.off" --frames 1 -o "$work/out"
  expect_error remesh-tolerance "tolerance" -- remesh "$work/octa.off" "$work/octa.off" --features "$work/f4.txt" -o "$work/out" --tolerance -1
  if "$cli" morph "$work/demo/source_compatible.off" "$work/demo/target_compatible.off" --frames 3 -o "$work/m3" --quiet; then
    [ -s "$work/m3/frame_002.off" ] && [ ! -e "$work/m3/frame_003.off" ] || bad "morph: wrong frames"
    ok
  else
    bad "morph of the demo's outputs failed"
  fi
else
  bad "demo failed"
fi

# A real bench case.
if [ -d "$shared/bench/wolf0_wolf2" ]; then
  b="$shared/bench/wolf0_wolf2"
  if "$cli" layout "$b/source.off" "$b/target.off" --features "$b/features.txt" -o "$work/wolf" --quiet; then
    nfaces=$(sed -n 2p "$work/wolf/source_refined.off" | awk '{print $2}')
    [ "$(wc -l <"$work/wolf/source_patches.txt")" -eq "$nfaces" ] || bad "wolf: one patch id per refined face"
    ok
  else
    bad "layout on wolf0_wolf2 failed"
  fi
  if "$cli" map "$b/source.off" "$b/target.off" --features "$b/features.txt" -o "$work/wolfmap" --quiet; then
    nv=$(sed -n 2p "$b/source.off" | awk '{print $1}')
    [ "$(wc -l <"$work/wolfmap/source_to_target.txt")" -eq "$nv" ] || bad "map: one line per source vertex"
    nvt=$(sed -n 2p "$b/target.off" | awk '{print $1}')
    nft=$(sed -n 2p "$b/target.off" | awk '{print $2}')
    [ "$(wc -l <"$work/wolfmap/target_to_source.txt")" -eq "$nvt" ] || bad "map: one line per target vertex"
    awk -v nf="$nft" '$1 < 0 || $1 >= nf || NF != 4 {exit 1}' "$work/wolfmap/source_to_target.txt" || bad "map: face index out of range"
    grep -q '"valid": true' "$work/wolfmap/report.json" || bad "map: certificate not reported valid"
    ok
  else
    bad "map on wolf0_wolf2 failed"
  fi
  if "$cli" remesh "$b/source.off" "$b/target.off" --features "$b/features.txt" -o "$work/wolfremesh" --quiet; then
    for f in source_compatible.off target_compatible.off target_error.ply report.json; do
      [ -s "$work/wolfremesh/$f" ] || bad "remesh: missing $f"
    done
    grep -q '"psnr"' "$work/wolfremesh/report.json" || bad "remesh: no PSNR in the report"
    grep -q '"verification": {"valid": true, "compatible": true' "$work/wolfremesh/report.json" ||
      bad "remesh: the independent verification is not reported valid"
    ok
  else
    bad "remesh on wolf0_wolf2 failed"
  fi
else
  echo "shared data not found at $shared: skipping the bench case"
fi

echo "cli: $passes passed, $fails failed"
[ $fails -eq 0 ]
