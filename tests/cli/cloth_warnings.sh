#!/usr/bin/env bash
# The warnings a cloth earns at load, with their count and first example: a pattern whose scale
# is far from the mesh's (vt in [0, 1] on a 10 m square: a median 0.1), and a cloth that starts
# crossing itself (two squares through one another) or a body (a square through a box); a pattern
# in the mesh's units and a clean start earn none. --strict refuses a scene that earns any.
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
# A cloth that starts through a body: warned with the certificate's count of crossing pairs (a run
# goes on), refused under --strict by check-scene and run (exit 2, before any frame); a clean start
# passes --strict.
cat > "$work/box.obj" <<'OBJ'
v 0.3 -0.2 0.3
v 0.7 -0.2 0.3
v 0.7 -0.2 0.7
v 0.3 -0.2 0.7
v 0.3 0.2 0.3
v 0.7 0.2 0.3
v 0.7 0.2 0.7
v 0.3 0.2 0.7
f 1 3 2
f 1 4 3
f 5 6 7
f 5 7 8
f 1 2 6
f 1 6 5
f 2 3 7
f 2 7 6
f 3 4 8
f 3 8 7
f 4 1 5
f 4 5 8
OBJ
echo "{\"frames\": 1, \"cloths\": [{\"name\": \"c\", \"mesh\": \"$work/unit.obj\"}],
  \"colliders\": [{\"name\": \"body\", \"type\": \"mesh\", \"mesh\": \"$work/box.obj\"}]}" > "$work/through.json"
log=$("$invfem" check-scene "$work/through.json" 2>&1 >/dev/null)
grep -q "warning: .*through.json: \"c\" starts through body \"body\": [1-9][0-9]* pairs of their triangles intersect (first: its triangle" <<<"$log" ||
  { echo "FAIL: no warning of a start through the body: $log"; exit 1; }
for cmd in "check-scene $work/through.json --strict" "run $work/through.json --out $work/through --strict"; do
  set +e
  log=$($invfem $cmd 2>&1 >/dev/null)
  code=$?
  set -e
  [ "$code" = 2 ] && grep -q "through.json: --strict: 1 warning at load, refused:" <<<"$log" ||
    { echo "FAIL: $cmd: exit $code, $log"; exit 1; }
done
[ ! -e "$work/through/frames" ] || { echo "FAIL: a refused --strict run wrote frames"; exit 1; }
"$invfem" check-scene "$work/unit.json" --strict > /dev/null 2>&1 || { echo "FAIL: --strict refused a clean garment"; exit 1; }
echo "a pattern of the wrong scale and a start that crosses itself or a body are warned about (refused with --strict); a clean garment is not"
