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
  grep -q '"where": {"farthest_target_vertex": {"index": ' "$work/demo/report.json" || bad "demo: the verification's places missing"
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

# Honest exit codes and whole results.
# expect_code NAME CODE WORDS -- ARGS...: exit code CODE and a stderr line containing WORDS.
expect_code() {
  local name=$1 code=$2 words=$3
  shift 4
  "$cli" "$@" >"$work/stdout" 2>"$work/stderr"
  local rc=$?
  if [ $rc -ne "$code" ]; then bad "$name: exit code $rc, expected $code: $(cat "$work/stderr")"; return; fi
  if [ -n "$words" ] && ! grep -qi -- "$words" "$work/stderr"; then bad "$name: message lacks '$words': $(cat "$work/stderr")"; return; fi
  ok
}
# A feature file with a UTF-8 byte order mark is read as OFF and OBJ files with one are.
printf '\xEF\xBB\xBF0 0\n1 1\n2 2\n4 4\n' >"$work/fbom.txt"
expect_code feature-bom 0 "" -- layout "$work/octa.off" "$work/octa.off" --features "$work/fbom.txt" -o "$work/bom" --quiet
# A mesh with all its vertices at one point: the message names the file.
awk 'NR>=3 && NR<=8 {print "1 1 1"; next} {print}' "$work/octa.off" >"$work/point.off"
expect_error degenerate-box "point.off.*degenerate bounding box" -- layout "$work/point.off" "$work/octa.off" --features "$work/f4.txt" -o "$work/out"
# morph refuses open and non-manifold meshes.
expect_error morph-open "open" -- morph "$work/open.off" "$work/open.off" --frames 3 -o "$work/out"
if [ -d "$shared/data/nasty" ]; then
  expect_error morph-non-manifold "non-manifold" -- morph "$shared/data/nasty/cgal/cubes.off" "$shared/data/nasty/cgal/cubes.off" -o "$work/out"
fi
# An unusable -o is refused before any work, with exit code 1.
touch "$work/a_file"
expect_code output-is-file 1 "not a folder" -- remesh "$work/octa.off" "$work/octa.off" --features "$work/f4.txt" -o "$work/a_file"
expect_code output-under-file 1 "cannot create" -- map "$work/octa.off" "$work/octa.off" --features "$work/f4.txt" -o "$work/a_file/sub"
if [ "$(id -u)" -ne 0 ]; then
  mkdir -p "$work/readonly" && chmod a-w "$work/readonly"
  expect_code output-read-only 1 "cannot write" -- layout "$work/octa.off" "$work/octa.off" --features "$work/f4.txt" -o "$work/readonly"
  chmod u+w "$work/readonly"
fi
expect_code time-limit-usage 2 "time-limit" -- remesh "$work/octa.off" "$work/octa.off" --features "$work/f4.txt" -o "$work/out" --time-limit -3
# Small and degenerate but valid inputs through the whole pipeline: the octahedron and the tetrahedron with
# 4 features, the octahedron against itself rotated by its features, a mesh with a zero-length edge.
cat >"$work/tetra.off" <<'EOM'
OFF
4 4 0
1 1 1
1 -1 -1
-1 1 -1
-1 -1 1
3 0 1 2
3 0 3 1
3 0 2 3
3 1 3 2
EOM
printf '0 0\n1 1\n2 2\n3 3\n' >"$work/f4t.txt"
printf '0 2\n2 1\n1 3\n4 4\n' >"$work/f4rot.txt"
# The octahedron with its vertex 0 doubled: vertex 6 at the same point, on a zero-length edge 0-6.
cat >"$work/zero_edge.off" <<'EOM'
OFF
7 10 0
1 0 0
-1 0 0
0 1 0
0 -1 0
0 0 1
0 0 -1
1 0 0
3 0 2 4
3 2 1 4
3 1 3 4
3 3 6 4
3 6 0 4
3 2 0 5
3 1 2 5
3 3 1 5
3 6 3 5
3 0 6 5
EOM
for c in "octahedron octa.off octa.off f4.txt" "tetrahedron tetra.off tetra.off f4t.txt" \
         "rotated-octahedron octa.off octa.off f4rot.txt" "zero-length-edge zero_edge.off octa.off f4.txt"; do
  set -- $c
  expect_code "remesh-$1" 0 "" -- remesh "$work/$2" "$work/$3" --features "$work/$4" -o "$work/small_$1" --quiet
done
# A tolerance that cannot be met before the vertex cap: the tetrahedron (4 vertices) fitted to the octahedron at
# 0.001 % by the refinement alone stops at four times its vertices, about 4 % from the octahedron. The result is
# written, exit code 4; with --best-effort, exit code 0.
printf '0 0\n1 4\n2 2\n3 5\n' >"$work/f4to.txt"
expect_code failed-verification 4 "failed its independent verification" -- remesh "$work/tetra.off" "$work/octa.off" --features "$work/f4to.txt" -o "$work/strict" --tolerance 0.001 --construction refinement --quiet
[ -s "$work/strict/report.json" ] && grep -q '"valid": false' "$work/strict/report.json" || bad "failed verification: no report of it"
# A remeshing that fails the checks is done again with the map smoothing; here that fails too, and the first is kept.
grep -q '"map_smoothing_retry": {"tried": true, "kept": false' "$work/strict/report.json" || bad "failed verification: no second attempt reported"
grep -q '"map_smoothing_retry": {"tried": false' "$work/small_octahedron/report.json" || bad "remesh: a second attempt where the first is valid"
expect_code no-retry 4 "failed its independent verification" -- remesh "$work/tetra.off" "$work/octa.off" --features "$work/f4to.txt" -o "$work/strict3" --tolerance 0.001 --construction refinement --no-map-smoothing-retry --quiet
grep -q '"map_smoothing_retry": {"tried": false' "$work/strict3/report.json" || bad "--no-map-smoothing-retry: a second attempt"
expect_code failed-verification-best-effort 0 "best-effort" -- remesh "$work/tetra.off" "$work/octa.off" --features "$work/f4to.txt" -o "$work/strict2" --tolerance 0.001 --construction refinement --best-effort --quiet
# By default the overlay makes the octahedron's vertices, but the first map squeezes one of them beyond the exact
# tests; the second attempt, with the map smoothed, inserts it and is kept (exit code 0, 15 vertices).
expect_code retry-kept 0 "" -- remesh "$work/tetra.off" "$work/octa.off" --features "$work/f4to.txt" -o "$work/strict4" --tolerance 0.001 --quiet
grep -q '"map_smoothing_retry": {"tried": true, "kept": true' "$work/strict4/report.json" || bad "remesh: the second attempt not kept"
# The demo's pair (written by the demo above) for the time limit and the decimated overlay.
if [ -s "$work/demo/source.off" ]; then
  d="$work/demo"
  rm -rf "$work/limited"
  expect_code time-limit 3 "time limit of 0.5 s reached during" -- remesh "$d/source.off" "$d/target.off" --features "$d/features.txt" -o "$work/limited" --time-limit 0.5 --quiet
  [ -z "$(ls -A "$work/limited" 2>/dev/null)" ] || bad "time limit: files written: $(ls -A "$work/limited")"
  [ "$(wc -l <"$work/stderr")" -eq 1 ] || bad "time limit: more than one line: $(cat "$work/stderr")"
  # The decimated overlay, asked for: valid, and reported as used.
  expect_code overlay 0 "" -- remesh "$d/source.off" "$d/target.off" --features "$d/features.txt" -o "$work/overlay" --construction overlay --quiet
  grep -q '"used": true' "$work/overlay/report.json" || bad "overlay: not used"
  expect_code construction-usage 2 "construction" -- remesh "$d/source.off" "$d/target.off" --features "$d/features.txt" -o "$work/out" --construction best
  # Extremity features: the option is accepted and the pairs added are reported (all kept: one here).
  expect_code extremity-features 0 "" -- map "$d/source.off" "$d/target.off" --features "$d/features.txt" -o "$work/extremity" --extremity-features --quiet
  grep -q '"extremity_features": \[' "$work/extremity/report.json" || bad "extremity features: not in report.json"
  grep -q '"map_adopted": false' "$work/extremity/report.json" || bad "extremity features: a map adopted with a pair added"
  # By default the pair found is not kept (the selection): the final map is the probe's, adopted.
  expect_code map-adopted 0 "" -- map "$d/source.off" "$d/target.off" --features "$d/features.txt" -o "$work/adopted" --quiet
  grep -q '"map_adopted": true' "$work/adopted/report.json" || bad "map: the probe's map not adopted"
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
  # The same pair at the ends of the readers' range: a valid result in the user's units, the same size up to the
  # decisions that the rounding of the scaled coordinates can tip (within 2 % of the vertices), then a morph.
  nref=$(sed -n 2p "$work/wolfremesh/target_compatible.off" | awk '{print $1}')
  for factor in 1e-150 1e90; do
    for m in source target; do
      # OFF: the header, the counts, then (blank lines skipped) one vertex per line.
      awk -v f="$factor" 'NF == 0 {next} h < 2 {if (h == 1) n = $1; ++h; print; next}
        k < n {printf "%.17g %.17g %.17g\n", $1*f, $2*f, $3*f; ++k; next} {print}' "$b/$m.off" >"$work/wolf_$m.off"
    done
    if "$cli" remesh "$work/wolf_source.off" "$work/wolf_target.off" --features "$b/features.txt" -o "$work/wolf_$factor" --quiet; then
      grep -q '"verification": {"valid": true, "compatible": true' "$work/wolf_$factor/report.json" || bad "remesh at $factor: not valid"
      n=$(sed -n 2p "$work/wolf_$factor/target_compatible.off" | awk '{print $1}')
      awk -v a="$n" -v b="$nref" 'BEGIN {d = a - b; if (d < 0) d = -d; exit !(d <= 0.02 * b)}' || bad "remesh at $factor: $n vertices, $nref at scale 1"
      # Coordinates in the user's units: the largest magnitude is that of the scaled input, up to the shape change.
      awk -v f="$factor" -v n="$n" 'NR>=3 && NR<3+n {for (i = 1; i <= 3; ++i) {x = $i < 0 ? -$i : $i; if (x > m) m = x}} END {r = m / f; exit !(r > 10 && r < 1000)}' \
        "$work/wolf_$factor/target_compatible.off" || bad "remesh at $factor: outputs not in the user's units"
      if "$cli" morph "$work/wolf_$factor/source_compatible.off" "$work/wolf_$factor/target_compatible.off" --frames 3 -o "$work/wolf_morph_$factor" --quiet; then
        ! grep -qiE 'nan|inf' "$work/wolf_morph_$factor"/*.off || bad "morph at $factor: non-finite coordinates"
        ok
      else
        bad "morph at $factor failed"
      fi
    else
      bad "remesh of wolf0_wolf2 at $factor failed (exit $?)"
    fi
  done
else
  echo "shared data not found at $shared: skipping the bench case"
fi

# Every report.json written is valid JSON (a strict parser: no NaN, no Infinity).
for r in $(find "$work" -name report.json); do
  python3 -c 'import json, sys
def refuse(c): raise ValueError("non-finite number " + c)
json.load(open(sys.argv[1]), parse_constant=refuse)' "$r" 2>"$work/json_err" && ok || bad "invalid JSON in $r: $(cat "$work/json_err")"
done

echo "cli: $passes passed, $fails failed"
[ $fails -eq 0 ]
