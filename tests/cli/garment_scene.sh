#!/usr/bin/env bash
# A garment through the scene file, as a user writes it: two panels of an OBJ with a sewing
# pattern (vt) as rest shape, a stitch from the file and one from the scene, an initial shape from
# another file, and one panel pinned by its group name and carried by keyframes. Checks that the
# run succeeds, that the pinned panel lands exactly on its keyframed positions, that the output
# keeps the file's vertex numbering, and that the seams stay closed.
#   garment_scene.sh INVFEM WORKDIR
set -euo pipefail
invfem="$1" work="$2"
rm -rf "$work" && mkdir -p "$work"
# Panel "yoke" (vertices 1-4) and panel "skirt" (5-8), 0.3 m squares, skirt hanging below the
# yoke and sewn to it along y = 1 (vertex 4 onto 0->1 at r = 0, vertex 5 onto 0->1 at r = 1).
cat > "$work/garment.obj" <<'OBJ'
v 0 1.3 0
v 0.3 1.3 0
v 0.3 1.0 0
v 0 1.0 0
v 0 1.0 0
v 0.3 1.0 0
v 0.3 0.7 0
v 0 0.7 0
vt 0 0.3
vt 0.3 0.3
vt 0.3 0
vt 0 0
vt 0 0.3
vt 0.3 0.3
vt 0.3 0
vt 0 0
g yoke
f 1/1 2/2 3/3
f 1/1 3/3 4/4
g skirt
f 5/5 6/6 7/7
f 5/5 7/7 8/8
stitch 4 3 2 0
OBJ
# The initial shape: the same mesh, the skirt swung out a little.
sed -e '7s/.*/v 0.3 0.7 0.05/' -e '8s/.*/v 0 0.7 0.05/' "$work/garment.obj" > "$work/start.obj"
cat > "$work/scene.json" <<'JSON'
{
  "name": "garment_cli",
  "fps": 20,
  "frames": 10,
  "cloths": [{
    "name": "dress",
    "mesh": "garment.obj",
    "rest_shape": "pattern",
    "initial_shape": { "mesh": "start.obj" },
    "material": { "model": "neo_hookean", "young": 1e5, "density": 300, "thickness": 0.001 },
    "stitches": { "list": [[5, 3, 2, 1.0]], "stiffness": 1e5 },
    "pins": [{ "group": "yoke", "motion": { "translate_keys": [[0, [0, 0, 0]], [0.5, [0.2, 0.1, 0]]] } }]
  }]
}
JSON
"$invfem" run "$work/scene.json" --out "$work/out" --quiet
last="$work/out/frames/dress/0010.obj"
[ "$(grep -c '^v ' "$last")" -eq 8 ] || { echo "FAIL: the output does not keep the file's 8 vertices"; exit 1; }
# Yoke vertices 1-4 moved by exactly (0.2, 0.1, 0) at t = 0.5 s.
awk -v fail=0 '
  NR == FNR { if ($1 == "v") { n++; x0[n] = $2; y0[n] = $3; z0[n] = $4 } next }
  $1 == "v" { m++; if (m <= 4) { d = ($2 - x0[m] - 0.2)^2 + ($3 - y0[m] - 0.1)^2 + ($4 - z0[m])^2;
              if (d > 1e-14) { print "FAIL: pinned vertex " m - 1 " is off its keyframe by " sqrt(d); fail = 1 } }
              x[m] = $2; y[m] = $3; z[m] = $4 }
  END {
    # Seams: vertex 4 onto vertex 3 and vertex 5 onto vertex 2 (0-based), within 1 mm.
    g1 = sqrt((x[5]-x[4])^2 + (y[5]-y[4])^2 + (z[5]-z[4])^2); g2 = sqrt((x[6]-x[3])^2 + (y[6]-y[3])^2 + (z[6]-z[3])^2)
    if (g1 > 1e-3 || g2 > 1e-3) { print "FAIL: a seam opened: " g1 ", " g2; fail = 1 }
    exit fail }' "$work/out/frames/dress/0000.obj" "$last"
# The seams for `invfem check`: stitch 4 3 2 0 sews 4 onto 3, the scene's [5, 3, 2, 1] 5 onto 2.
welds=$(grep -v '^#' "$work/out/frames/dress/welds.txt" 2>/dev/null | sort | tr '\n' ';')
[ "$welds" = "4 3;5 2;" ] || { echo "FAIL: frames/dress/welds.txt holds \"$welds\" (want 4 3;5 2;)"; exit 1; }
"$invfem" check "$work/out" > "$work/check.txt" || { echo "FAIL: invfem check finds intersections:"; cat "$work/check.txt"; exit 1; }
echo "garment scene: pattern rest, initial shape, stitches from file and scene, pins by group with keyframes"
