#!/usr/bin/env bash
# Every documented error is triggered by a bad input, and its exit code and message checked.
#   errors.sh INVFEM SOURCE_DIR WORKDIR
set -uo pipefail
invfem="$1" src="$2" work="$3"
source "$(dirname "$0")/lib.sh"
cli_setup
good="$src/apps/scenes/torus_puddle.json"

scene() {  # scene NAME JSON: write a scene file beside a copy of the torus mesh
  mkdir -p "$work/data"
  cp -n "$src/apps/scenes/data/torus_polyfem.msh" "$work/data/" 2>/dev/null || true
  printf '%s\n' "$2" > "$work/$1.json"
  echo "$work/$1.json"
}
solid='"solids": [{"name": "t", "mesh": "data/torus_polyfem.msh"'

expect 2 "unknown command" -- bogus
expect 2 "no scene file given" -- run --out "$work/o"
expect 2 "--out DIR is required" -- run "$good"
expect 2 "unknown option \"--bogus\"" -- run "$good" --out "$work/o" --bogus
expect 2 "cannot open the scene file" -- run "$work/missing.json" --out "$work/o"
expect 2 "not valid JSON" -- run "$(scene badjson '{ "frames": 3, ')" --out "$work/o"
expect 2 "\$.framez: unknown field" -- run "$(scene unknown '{ "framez": 3, '"$solid"' }] }')" --out "$work/o"
expect 2 "\$.frames: expected an integer" -- run "$(scene frames '{ "frames": "ten", '"$solid"' }] }')" --out "$work/o"
expect 2 "\$.solids[0].material.poisson: expected a Poisson's ratio in (-1, 0.5)" -- \
  run "$(scene poisson '{ '"$solid"', "material": {"poisson": 0.5} }] }')" --out "$work/o"
expect 2 "\$.solids[0].material.density: expected a density > 0" -- \
  run "$(scene density '{ '"$solid"', "material": {"density": -1} }] }')" --out "$work/o"
expect 2 "\$.solids[0].mesh: expected an existing mesh file" -- \
  run "$(scene nomesh '{ "solids": [{"name": "t", "mesh": "data/none.vtk"}] }')" --out "$work/o"
expect 2 "a name unique in the scene" -- \
  run "$(scene dup '{ '"$solid"' }, {"name": "t", "mesh": "data/torus_polyfem.msh"}] }')" --out "$work/o"
expect 2 "\$.solver.linear: expected \"cg\" or \"direct\"" -- \
  run "$(scene linear '{ "solver": {"integrator": "implicit", "linear": "lu"}, '"$solid"' }] }')" --out "$work/o"
expect 2 "\$.solver.linear: expected a string" -- \
  run "$(scene linear_type '{ "solver": {"linear": 1}, '"$solid"' }] }')" --out "$work/o"
expect 2 "\$.solver.preconditioner: expected \"auto\", \"block_jacobi\" or \"amg\"" -- \
  run "$(scene preconditioner '{ "solver": {"integrator": "implicit", "preconditioner": "ilu"}, '"$solid"' }] }')" --out "$work/o"
expect 2 "\$.gravity: expected an array of 3" -- run "$(scene grav '{ "gravity": [0, 1], '"$solid"' }] }')" --out "$work/o"
printf 'ASCII garbage\n' > "$work/data/broken.vtk"
expect 2 "broken.vtk" -- run "$(scene broken '{ "solids": [{"name": "t", "mesh": "data/broken.vtk"}] }')" --out "$work/o"
expect 2 "--set: \"frames\": expected path.to.field=value" -- run "$good" --out "$work/o" --set frames
expect 2 "--threads: expected a whole number" -- run "$good" --out "$work/o" --threads zero
expect 2 "--format: unknown format \"abc\"" -- run "$good" --out "$work/o" --format obj,abc
expect 2 "--frames: expected a frame range" -- run "$good" --out "$work/o" --frames 9-3
expect 2 "is past the scene's last frame" -- run "$good" --out "$work/o" --frames 0-100000
mkdir -p "$work/empty_run" && cp "$good" "$work/empty_run/scene.json"
expect 2 "no frames to render" -- render "$work/empty_run"
expect 2 "cannot open" -- render "$work/nothing"
expect 2 "no such scene file" -- batch "$work/missing.json" --out "$work/b"
expect 2 "--shard: expected I/N" -- batch "$good" --out "$work/b" --shard 3/2
# Fracture (apps/scenes/README.md "fracture"): a threshold is required, fields in range, and what
# does not follow a changing topology is refused.
expect 2 "\$.solids[0].fracture.max_principal_stress: expected a threshold" -- \
  run "$(scene frac_none '{ '"$solid"', "fracture": {"max_cuts_per_step": 2} }] }')" --out "$work/o"
expect 2 "\$.solids[0].fracture.front_fraction: expected a fraction in (0, 1]" -- \
  run "$(scene frac_front '{ '"$solid"', "fracture": {"max_principal_stress": 1e4, "front_fraction": 2} }] }')" --out "$work/o"
expect 2 "\$.solids[0].fracture.seed.factor: expected a fraction of the thresholds in (0, 1]" -- \
  run "$(scene frac_seed_factor '{ '"$solid"', "fracture": {"max_principal_stress": 1e4, "seed": {"point": [0, 0, 0], "normal": [0, 1, 0], "factor": 0}} }] }')" --out "$work/o"
expect 2 "\$.solids[0].fracture.seed.normal: expected a non-zero vector" -- \
  run "$(scene frac_seed_normal '{ '"$solid"', "fracture": {"max_principal_stress": 1e4, "seed": {"point": [0, 0, 0], "normal": [0, 0, 0]}} }] }')" --out "$work/o"
expect 2 "\$.solids[0].fracture.seed.max: expected both corners of the seed's box, or neither" -- \
  run "$(scene frac_seed_box '{ '"$solid"', "fracture": {"max_principal_stress": 1e4, "seed": {"point": [0, 0, 0], "normal": [0, 1, 0], "min": [0, 0, 0]}} }] }')" --out "$work/o"
expect 2 "\$.solids[0].fracture: expected a \"plasticity\" block as well for max_plastic_strain" -- \
  run "$(scene frac_plastic '{ '"$solid"', "fracture": {"max_plastic_strain": 0.5} }] }')" --out "$work/o"
expect 2 "\$.solids[0].fracture: expected a finite-element material.model" -- \
  run "$(scene frac_springs '{ '"$solid"', "material": {"model": "mass_spring"}, "fracture": {"max_principal_stress": 1e4} }] }')" --out "$work/o"
# Garments: a cloth field, a group, a vertex and a stitch that do not exist, a pattern asked of a non-OBJ.
printf 'v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\ng front\nf 1 2 3\nf 1 3 4\n' > "$work/data/sheet.obj"
printf 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n' > "$work/data/tri.ply"
cloth='"cloths": [{"name": "c", "mesh": "data/sheet.obj"'
expect 2 "no group \"back\" in" -- run "$(scene nogroup '{ '"$cloth"', "pins": [{"group": "back"}] }] }')" --out "$work/o"
expect 2 "pins[0]: vertex 9 but the mesh has 4 vertices" -- \
  run "$(scene pinrange '{ '"$cloth"', "pins": [{"vertices": [9]}] }] }')" --out "$work/o"
expect 2 "cloth \"c\": pin_vertices: vertex 4294967297 but the mesh has 4 vertices" -- \
  run "$(scene pinbig '{ '"$cloth"', "pin_vertices": [4294967297] }] }')" --out "$work/o"
expect 2 "cloth \"c\": stitches.list[0]: vertex 9 but the mesh has 4 vertices" -- \
  run "$(scene stitchrange '{ '"$cloth"', "stitches": {"list": [[0, 1, 9, 0.5]]} }] }')" --out "$work/o"
expect 2 "has no vt lines" -- run "$(scene novt '{ '"$cloth"', "rest_shape": "pattern" }] }')" --out "$work/o"
expect 2 "this is not an OBJ file" -- \
  run "$(scene plypattern '{ "cloths": [{"name": "c", "mesh": "data/tri.ply", "rest_shape": "pattern" }] }')" --out "$work/o"
expect 2 "\$.cloths[0].rest_shape: expected \"mesh\" for a grid" -- \
  run "$(scene gridpattern '{ "cloths": [{"name": "c", "rest_shape": "pattern" }] }')" --out "$work/o"
# One-way coupling: attachments to a solid that is not there, selecting nothing; a coupling naming no cloth.
both=''"$solid"' }], "cloths": [{"name": "c", "mesh": "data/sheet.obj"'
expect 2 "\$.cloths[0].attachments[0].solid: expected the name of a solid of the scene" -- \
  run "$(scene attachsolid '{ '"$both"', "attachments": [{"solid": "nobody", "vertices": [0]}] }] }')" --out "$work/o"
expect 2 "\$.cloths[0].attachments[0] (cloth \"c\") selects no vertex" -- \
  run "$(scene attachempty '{ '"$both"', "attachments": [{"solid": "t", "box": {"min": [5, 5, 5], "max": [6, 6, 6]}}] }] }')" --out "$work/o"
expect 2 "\$.cloths[0].attachments[0].vertices: expected exactly one of" -- \
  run "$(scene attachtwo '{ '"$both"', "attachments": [{"solid": "t", "vertices": [0], "group": "front"}] }] }')" --out "$work/o"
expect 2 "\$.solids[0].cloth_coupling.cloths: expected names of cloths of the scene" -- \
  run "$(scene couplecloth '{ '"$solid"', "cloth_coupling": {"cloths": ["cape"]} }] }')" --out "$work/o"
if [ "$fail" -ne 0 ]; then exit 1; fi
echo "every documented error gives its message and exit code 2"
