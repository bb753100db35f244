#!/usr/bin/env bash
# Issue 12, class 8: a surface to be tet-meshed is checked first (`invfem mesh`, and a solid given
# as a surface in a scene). A fin (an edge on three triangles) is refused, exit 2 naming the file;
# a flipped triangle, two interpenetrating boxes and a hole are warned about with their counts,
# and the volume ratio is not printed for a surface whose volume means nothing.
#   surface_defects.sh INVFEM SOURCE_DIR WORKDIR
set -uo pipefail
invfem="$1" src="$2" work="$3"
source "$(dirname "$0")/lib.sh"
cli_setup
cd "$work" || exit 1

# box FILE X0 Y0 Z0 X1 Y1 Z1 [FIRST_VERTEX] [DROP_TOP]: the 12 triangles of an axis-aligned box,
# wound outwards, appended to FILE (vertex numbers from FIRST_VERTEX, 1-based; DROP_TOP=1 leaves
# out the +z face).
box() {
  local f="$1" x0="$2" y0="$3" z0="$4" x1="$5" y1="$6" z1="$7" o="${8:-1}" drop="${9:-0}"
  local i
  for i in 0 1 2 3 4 5 6 7; do
    echo "v $(( i & 1 ? 1 : 0 )) $(( i & 2 ? 1 : 0 )) $(( i & 4 ? 1 : 0 ))" |
      awk -v a="$x0" -v b="$y0" -v c="$z0" -v A="$x1" -v B="$y1" -v C="$z1" \
        '{ printf "v %s %s %s\n", ($2 ? A : a), ($3 ? B : b), ($4 ? C : c) }' >> "$f"
  done
  local q
  for q in "0 2 3 1" "4 5 7 6" "0 1 5 4" "2 6 7 3" "0 4 6 2" "1 3 7 5"; do
    [ "$drop" = 1 ] && [ "$q" = "4 5 7 6" ] && continue
    set -- $q
    echo "f $(( $1 + o )) $(( $2 + o )) $(( $3 + o ))" >> "$f"
    echo "f $(( $1 + o )) $(( $3 + o )) $(( $4 + o ))" >> "$f"
  done
}

# A closed box: no warning, the volume ratio printed.
box good.obj 0 0 0 2 1 1
expect_output 0 "vs surface 2 (ratio" -- mesh good.obj --out good.vtk --resolution 8
out=$("$invfem" mesh good.obj --out good.vtk --resolution 8 2>&1 >/dev/null)
if [ -n "$out" ]; then echo "FAIL: a closed box gave stderr: $out"; fail=1; fi

# A fin: a triangle hung on the box's edge from vertex 2 to 4 (x = 2, z = 0), named as the box's
# second triangle (1, 4, 2) runs it. Refused.
box fin.obj 0 0 0 2 1 1
printf 'v 3 0.5 -1\nf 2 4 9\n' >> fin.obj
expect 2 "fin.obj: 1 edges are shared by an odd number (3 or more) of triangles (first: the edge (2, 1, 0)-(2, 0, 0), shared by 3): a fin" -- \
  mesh fin.obj --out fin.vtk --resolution 8
if [ -e fin.vtk ]; then echo "FAIL: a refused surface was written"; fail=1; fi

# The unit tetrahedron with its face (2, 3, 4) flipped: 3 edges, the ratio withheld. The first
# is 3-2 as the first triangle runs it, and the flipped one runs it so too.
cat > flipped.obj <<'OBJ'
v 0 0 0
v 1 0 0
v 0 1 0
v 0 0 1
f 1 3 2
f 1 2 4
f 1 4 3
f 2 4 3
OBJ
expect 0 "warning: flipped.obj: 3 edges are run in the same direction by both their triangles (first: the edge (0, 1, 0)-(1, 0, 0))" -- \
  mesh flipped.obj --out flipped.vtk --resolution 8
expect_output 0 "ratio n/a (the surface is not closed and consistently oriented)" -- mesh flipped.obj --out flipped.vtk --resolution 8

# A bar poking out of a box through its face x = 2: 8 intersecting triangle pairs (the unit test
# SurfaceCheck.InterpenetratingBoxesIntersectAlongTheirCrossing explains the count); the first is
# the box's triangle 11, (1, 7, 5) on x = 2, with the bar's first, on its face z = 0.8.
box boxes.obj 0 0 0 2 2 2
box boxes.obj 1 0.2 0.8 3 0.5 1.2 9
expect 0 "warning: boxes.obj: 8 pairs of triangles intersect (first: triangle 11 at (2, 0, 0) and triangle 12 at (1, 0.2, 0.8))" -- \
  mesh boxes.obj --out boxes.vtk --resolution 8

# A box without its top: 4 open edges, meshed by the winding number. The first is the top side of
# the face y = 0, as its triangle (1, 6, 5) runs it.
box open.obj 0 0 0 2 1 1 1 1
expect 0 "warning: open.obj: 4 open edges (used by one triangle; first: the edge (2, 0, 1)-(0, 0, 1))" -- mesh open.obj --out open.vtk --resolution 8
expect_output 0 "inside test winding-number" -- mesh open.obj --out open.vtk --resolution 8

# The same checks for a solid given as a surface in a scene (check-scene builds it as a run would).
torus="$src/apps/scenes/torus_puddle.json"
expect 2 "solid \"torus\": $work/fin.obj: 1 edges are shared by an odd number (3 or more) of triangles" -- \
  check-scene "$torus" --quick --set "solids.0.mesh=\"$work/fin.obj\"" --set solids.0.mesh_resolution=8
expect 0 "warning: $work/flipped.obj: 3 edges are run in the same direction" -- \
  check-scene "$torus" --quick --set "solids.0.mesh=\"$work/flipped.obj\"" --set solids.0.mesh_resolution=8
expect 0 "volume ratio n/a (the surface is not closed and consistently oriented)" -- \
  check-scene "$torus" --quick --set "solids.0.mesh=\"$work/flipped.obj\"" --set solids.0.mesh_resolution=8

if [ "$fail" -ne 0 ]; then exit 1; fi
echo "surface defects are refused or warned about with their counts"
