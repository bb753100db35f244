#!/usr/bin/env bash
# `invfem check`: a run-like folder with two objects and two frames (frame 0 clean, frame 1 with
# one tetrahedron's apex pushed through the other's face: exactly 3 crossing pairs), welds.txt
# honoured, seam gaps measured, MESH mode, and the bad-input errors (exit 2, naming the file).
#   check_intersections.sh INVFEM WORKDIR
set -uo pipefail
invfem="$1" work="$2"
source "$(dirname "$0")/lib.sh"
cli_setup

# tet FILE APEX_Z: tetrahedron B is the unit corner tet; tetrahedron A has its apex at
# (0.2, 0.2, APEX_Z) and its base at z = -1 (see tests/unit/collisions/certificate/intersection_certificate.cpp).
tet_b() {
  printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n' > "$1"
}
tet_a() {
  printf 'v 0.2 0.2 %s\nv 2.2 0.2 -1\nv -0.8 1.932 -1\nv -0.8 -1.532 -1\nf 1 2 3\nf 1 3 4\nf 1 4 2\nf 2 4 3\n' "$2" > "$1"
}
out="$work/run"
mkdir -p "$out/frames/a" "$out/frames/b"
tet_a "$out/frames/a/0000.obj" -0.01
tet_b "$out/frames/b/0000.obj"
tet_a "$out/frames/a/0001.obj" 0.05
tet_b "$out/frames/b/0001.obj"

rows=$("$invfem" check "$out" --json "$work/rows.json")
code=$?
[ "$code" -eq 1 ] || { echo "FAIL: check of a run with an intersection exited $code (want 1)"; fail=1; }
# Columns: frame a:self b:self cross total seconds.
got0=$(awk '$1 == "0" && NF == 6 { print $2, $3, $4, $5 }' <<<"$rows")
got1=$(awk '$1 == "1" && NF == 6 { print $2, $3, $4, $5 }' <<<"$rows")
[ "$got0" = "0 0 0 0" ] || { echo "FAIL: frame 0 row \"$got0\" (want 0 0 0 0)"; echo "$rows"; fail=1; }
[ "$got1" = "0 0 3 3" ] || { echo "FAIL: frame 1 row \"$got1\" (want 0 0 3 3)"; echo "$rows"; fail=1; }
grep -q '"total": 3' "$work/rows.json" || { echo "FAIL: --json lacks frame 1's total of 3"; fail=1; }
expect_output 0 "no intersecting triangle pairs" -- check "$out" --frames 0
expect_output 0 "2 frames of 1 surface checked" -- check "$out" --objects a
expect_output 1 "a with b: 3" -- check "$out" --frames 1-1

# Welds: two triangles touching at one point through two distinct vertices (0 and 3) count as one
# pair; welds.txt making them one vertex makes them adjacent.
mkdir -p "$out/frames/c"
printf 'v 0 0 5\nv 1 0 5\nv 0 1 5\nv 0 0 5\nv -1 0 5\nv 0 -1 5\nf 1 2 3\nf 4 5 6\n' > "$out/frames/c/0000.obj"
cp "$out/frames/c/0000.obj" "$out/frames/c/0001.obj"
expect_output 1 "c with itself: 2" -- check "$out" --objects c
printf '# welds of "c"\n0 3\n' > "$out/frames/c/welds.txt"
expect_output 0 "no intersecting triangle pairs" -- check "$out" --objects c
printf '0 3\n1 x\n' > "$out/frames/c/welds.txt"
expect_output 2 "$out/frames/c/welds.txt:2: \"x\" is not a vertex index" -- check "$out"
printf '0 99\n' > "$out/frames/c/welds.txt"
expect_output 2 "weld vertex 99 outside [0, 6)" -- check "$out"
rm "$out/frames/c/welds.txt"

# Seam gaps: in object d, vertex 0 is stitched at r = 0.25 onto the edge (3, 4), at 0.75 x_3 +
# 0.25 x_4 = (0, 0, 5): it sits there in frame 0 and 3 mm above it in frame 1.
mkdir -p "$work/seams/frames/d"
seam_frame() {
  printf 'v 0 0 %s\nv 1 0 5\nv 0 1 5\nv -1 0 5\nv 3 0 5\nv 0 -1 5\nf 1 2 3\nf 4 5 6\n' "$2" > "$1"
}
seam_frame "$work/seams/frames/d/0000.obj" 5
seam_frame "$work/seams/frames/d/0001.obj" 5.003
printf '# welds of "d"\n0 3 4 0.25\n' > "$work/seams/frames/d/welds.txt"
rows=$("$invfem" check "$work/seams")
code=$?
[ "$code" -eq 0 ] || { echo "FAIL: check of the seam folder exited $code (want 0)"; echo "$rows"; fail=1; }
# Columns: frame d:self cross total seam-mm seconds.
gaps=$(awk 'NF == 6 && $1 ~ /^[0-9]+$/ { print $5 }' <<<"$rows" | tr '\n' ' ')
[ "$gaps" = "0.000 3.000 " ] || { echo "FAIL: seam gaps \"$gaps\" (want 0.000 3.000)"; echo "$rows"; fail=1; }
expect_output 0 "widest seam gap: 3.000 mm (d, frame 1, vertex 0 on the edge 3-4)" -- check "$work/seams"
expect_output 1 "1 frame over --max-seam-gap 0.002 m" -- check "$work/seams" --max-seam-gap 0.002
expect_output 0 "0 frames over --max-seam-gap 0.004 m" -- check "$work/seams" --max-seam-gap 0.004
expect_output 2 "--max-seam-gap: expected a number" -- check "$work/seams" --max-seam-gap 2mm
# Without r the gap is the distance to the edge: 3 mm as well.
printf '0 3 4\n' > "$work/seams/frames/d/welds.txt"
expect_output 0 "widest seam gap: 3.000 mm" -- check "$work/seams"
printf '0 3 4 1.5\n' > "$work/seams/frames/d/welds.txt"
expect_output 2 "$work/seams/frames/d/welds.txt:1: r \"1.5\" is not a number in (0, 1)" -- check "$work/seams"

# MESH mode: the two files of frame 1 as meshes (equal stems: named by path); a welds file for
# the touching pair.
expect_output 1 "frames/a/0001.obj with $out/frames/b/0001.obj: 3" -- check "$out/frames/a/0001.obj" "$out/frames/b/0001.obj"
expect_output 0 "no intersecting triangle pairs" -- check "$out/frames/a/0000.obj" "$out/frames/b/0000.obj"
printf '0 3\n' > "$work/c_welds.txt"
expect_output 0 "no intersecting triangle pairs" -- check "$out/frames/c/0000.obj" --welds "$work/c_welds.txt"

# Bad input: exit 2 with the path named.
expect_output 2 "$work/nowhere: no such file or folder" -- check "$work/nowhere"
mkdir -p "$work/empty"
expect_output 2 "$work/empty: no frames/ folder" -- check "$work/empty"
printf 'v 0 0 0\nv 1 0 0\nf 1 2 3\n' > "$out/frames/a/0001.obj"
expect_output 2 "$out/frames/a/0001.obj" -- check "$out"
rm "$out/frames/a/0001.obj"
expect_output 2 "frame 1 of 0-1 missing (first: frames/a/0001.obj); the run wrote frames 0-1; nothing was checked" -- check "$out"
# Frame file names: one past int (11 digits) is refused naming it, one that is not a number is not
# a frame (ignored).
tet_b "$out/frames/b/0001.obj"
tet_a "$out/frames/a/0001.obj" -0.01
tet_b "$out/frames/b/99999999999.obj"
expect_output 2 "$out/frames/b/99999999999.obj: frame number too large" -- check "$out"
rm "$out/frames/b/99999999999.obj"
tet_b "$out/frames/b/00x1.obj"
expect_output 0 "2 frames of 2 surfaces checked" -- check "$out" --objects a,b
rm "$out/frames/b/00x1.obj" "$out/frames/a/0001.obj" "$out/frames/b/0001.obj"
expect_output 2 "--objects: no object \"zz\"" -- check "$out" --objects zz
expect_output 2 "--welds $work/c_welds.txt: give it after the mesh" -- check --welds "$work/c_welds.txt" "$out/frames/c/0000.obj"

[ "$fail" -eq 0 ] && echo "invfem check: counts, welds, seam gaps, MESH mode and errors as documented"
exit "$fail"
