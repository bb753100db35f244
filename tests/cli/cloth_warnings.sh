#!/usr/bin/env bash
# The warnings a cloth earns at load, with their count and first example: a pattern whose scale
# is far from the mesh's (vt in [0, 1] on a 10 m square: a median 0.1), and a cloth that starts
# crossing itself (two squares through one another); a pattern in the mesh's units and a clean
# start earn none.
#   cloth_warnings.sh INVFEM WORKDIR
set -euo pipefail
invfem="$1" work="$2"
rm -rf "$work" && mkdir -p "$work"
cat > "$work/big.obj" <<'OBJ'
v 0 0 0
v 10 0 0
v 10 0 10
v 0 0 10
vt 0 0
vt 1 0
vt 1 1
vt 0 1
f 1/1 2/2 3/3
f 1/1 3/3 4/4
OBJ
sed 's/^v \([0-9]*\) 0 \([0-9]*\)$/v \1 0 \2/; s/10/1/g' "$work/big.obj" > "$work/unit.obj"
cat > "$work/crossing.obj" <<'OBJ'
v 0 0 0
v 1 0 0
v 1 0 1
v 0 0 1
v 0.5 -0.5 0.2
v 0.5 0.5 0.2
v 0.5 0.5 0.8
v 0.5 -0.5 0.8
f 1 2 3
f 1 3 4
f 5 6 7
f 5 7 8
OBJ
scene() { echo "{\"frames\": 1, \"cloths\": [{\"name\": \"c\", \"mesh\": \"$1\"$2}]}" > "$work/$3.json"; }
scene "$work/big.obj" ', "rest_shape": "pattern"' big
scene "$work/unit.obj" ', "rest_shape": "pattern"' unit
scene "$work/crossing.obj" '' crossing
log=$("$invfem" check-scene "$work/big.json" 2>&1 >/dev/null)
grep -q "warning: .*big.obj: the pattern's edges are a median 0.1 times the mesh's" <<<"$log" ||
  { echo "FAIL: no pattern scale warning: $log"; exit 1; }
log=$("$invfem" check-scene "$work/crossing.json" 2>&1 >/dev/null)
grep -q "warning: .*crossing.obj: the cloth starts crossing itself: [1-9][0-9]* pairs of triangles intersect (first: triangles" <<<"$log" ||
  { echo "FAIL: no crossing warning: $log"; exit 1; }
log=$("$invfem" check-scene "$work/unit.json" 2>&1 >/dev/null)
if grep -q "warning: " <<<"$log"; then echo "FAIL: a warning for a clean garment: $log"; exit 1; fi
echo "a pattern of the wrong scale and a start that crosses itself are warned about; a clean garment is not"
