#!/usr/bin/env bash
# A solid's initial_shape and damping_model in the scene file: every bad value gives its message
# and exit code 2; a mirrored start runs, starts with every tet inverted and recovers; a start
# from a file is where the solid starts.
#   solid_initial_shape.sh INVFEM WORKDIR
set -uo pipefail
invfem="$1" work="$2"
source "$(dirname "$0")/lib.sh"
cli_setup

write_tet_pair "$work/pair.vtk"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' > "$work/three.obj"
scene() {  # scene NAME SOLID_FIELDS: a scene of the two tets with these extra solid fields
  printf '{"frames": 3, "gravity": [0, 0, 0], "solids": [{"name": "p", "mesh": "pair.vtk", %s}]}\n' "$2" \
    > "$work/$1.json"
  echo "$work/$1.json"
}
at='$.solids[0].initial_shape'
expect 2 "$at.scramble: expected one of point, line, plane, mirror, box" -- \
  run "$(scene kind '"initial_shape": {"scramble": "sphere"}')" --out "$work/o"
expect 2 "$at.file: expected either a \"file\" or a \"scramble\", found both" -- \
  run "$(scene both '"initial_shape": {"scramble": "point", "file": "three.obj"}')" --out "$work/o"
expect 2 "$at.file: expected either a \"file\" or a \"scramble\", found neither" -- \
  run "$(scene neither '"initial_shape": {"seed": 3}')" --out "$work/o"
expect 2 "$at.size: expected the box's edge [m]" -- \
  run "$(scene nosize '"initial_shape": {"scramble": "box"}')" --out "$work/o"
expect 2 "$at.size: expected a box edge > 0 [m]" -- \
  run "$(scene zerosize '"initial_shape": {"scramble": "box", "size": 0}')" --out "$work/o"
expect 2 "$at.size: expected no \"size\" on a line scramble" -- \
  run "$(scene linesize '"initial_shape": {"scramble": "line", "size": 1}')" --out "$work/o"
expect 2 "$at.seed: expected" -- \
  run "$(scene seed '"initial_shape": {"scramble": "line", "seed": -1}')" --out "$work/o"
expect 2 "$at.transform: expected no transform with a scramble" -- \
  run "$(scene scrtr '"initial_shape": {"scramble": "plane", "transform": {"scale": 2}}')" --out "$work/o"
expect 2 "$at.seed: expected no \"seed\" with a file" -- \
  run "$(scene fileseed '"initial_shape": {"file": "three.obj", "seed": 1}')" --out "$work/o"
expect 2 "$at.spin: unknown field" -- \
  run "$(scene unknown '"initial_shape": {"scramble": "point", "spin": 1}')" --out "$work/o"
expect 2 "$at.file: expected an existing mesh file" -- \
  run "$(scene nofile '"initial_shape": {"file": "none.obj"}')" --out "$work/o"
expect 2 "three.obj: an initial shape needs the solid's nodes in the same order: it has 3 nodes, the solid's mesh" -- \
  run "$(scene count '"initial_shape": {"file": "three.obj"}')" --out "$work/o"
expect 2 "has 5" -- run "$work/count.json" --out "$work/o"
expect 2 '$.solids[0].material.damping_model: expected "rotated" or "spin_free"' -- \
  run "$(scene damping '"material": {"damping_model": "green"}')" --out "$work/o"

# A mirrored start: frame 0 has both tets inverted, the last frame none; scene.json keeps the fields.
if "$invfem" run "$(scene mirror '"initial_shape": {"scramble": "mirror", "seed": 5},
    "material": {"damping": 0.01, "damping_model": "spin_free"}')" --out "$work/mirror" --quiet 2>/dev/null; then
  first=$(awk -F, 'NR == 2 {print $7 "/" $8}' "$work/mirror/energies.csv")
  last=$(awk -F, 'END {print $7 "/" $8}' "$work/mirror/energies.csv")
  [ "$first" = "2/2" ] || { echo "FAIL: mirrored start: frame 0 has $first inverted, want 2/2"; fail=1; }
  [ "$last" = "0/2" ] || { echo "FAIL: mirrored start: last frame has $last inverted, want 0/2"; fail=1; }
  grep -q '"scramble": "mirror"' "$work/mirror/scene.json" && grep -q '"damping_model": "spin_free"' "$work/mirror/scene.json" ||
    { echo "FAIL: scene.json lacks the initial_shape or damping_model"; fail=1; }
else
  echo "FAIL: the mirrored start did not run"; fail=1
fi

# A start from a file (a VTK of the same nodes, node 4 moved): frame 0 shows it, scaled by the
# solid's transform.
sed 's/^0.1 0.1 0.1$/0.2 0.2 0.2/' "$work/pair.vtk" > "$work/moved.vtk"
if "$invfem" run "$(scene file '"transform": {"scale": 2}, "initial_shape": {"file": "moved.vtk"}')" \
    --out "$work/file" --quiet 2>/dev/null; then
  grep -q '^v 0.4 0.4 0.4$' "$work/file/frames/p/0000.obj" ||
    { echo "FAIL: frame 0 of the file start does not hold the moved node at (0.4, 0.4, 0.4)"; fail=1; }
else
  echo "FAIL: the start from a file did not run"; fail=1
fi

if [ "$fail" -ne 0 ]; then exit 1; fi
echo "initial_shape and damping_model: every error gives its message and exit code 2; starts run"
