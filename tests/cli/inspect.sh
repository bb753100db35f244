#!/usr/bin/env bash
# Placing a garment on a character (issue 54): `invfem inspect FILE` tells a garment OBJ's and a
# rigged character's size, bounds after a transform, up axis, bones and clips; `check-scene` tells
# each object's and body's bounds at frame 0; a looped clip whose last pose differs from its first
# is refused naming the jump, and runs past its wrap with loop_blend. The parts on Debian's
# assimp-testmodels (/usr/share/assimp/models) are skipped, with a message, where they are absent.
#   inspect.sh INVFEM SOURCE_DIR WORKDIR
set -uo pipefail
invfem="$1" src="$2" work="$3"
source "$(dirname "$0")/lib.sh"
cli_setup

# bounds_ratio A.json B.json: B's bounds (min and max) over A's, the same ratio for every
# coordinate (printed), or a message.
bounds_ratio() {
  python3 - "$1" "$2" <<'PY'
import json, sys
a, b = (json.load(open(p))["bounds"] for p in sys.argv[1:3])
ratios = {round(y / x, 12) for k in ("min", "max", "size") for x, y in zip(a[k], b[k]) if x != 0}
print(ratios.pop() if len(ratios) == 1 else f"ratios {sorted(ratios)}")
PY
}

# The help and the command list.
expect_output 0 "usage: invfem inspect FILE [--transform JSON] [--json]" -- help inspect
expect_output 0 "  inspect FILE " -- --help

# A garment OBJ: counts, its pattern (vt) and panels (g), bounds after a transform.
poncho="$src/apps/scenes/data/poncho.obj"
expect_output 0 "vertices   2432" -- inspect "$poncho"
expect_output 0 "triangles  4608" -- inspect "$poncho"
expect_output 0 "UVs (vt)   2432, on 4608 of 4608 faces" -- inspect "$poncho"
expect_output 0 'panels     2: "front", "back"' -- inspect "$poncho"
expect_output 0 "stitches   0" -- inspect "$poncho"
expect_output 0 "bounds     [-0.55, 0, -0.55] to [0.55, 0, 0.55] m, size 1.1 x 0 x 1.1 m" -- inspect "$poncho"
expect_output 0 "likely up  y: the normal of a flat mesh" -- inspect "$poncho"
expect_output 0 "bounds     [-0.55, 1.56, -0.74] to [0.55, 1.56, 0.36] m" -- \
  inspect "$poncho" --transform '{"translate": [0, 1.56, -0.19]}'
"$invfem" inspect "$poncho" --json > "$work/poncho.json" &&
  "$invfem" inspect "$poncho" --json --transform '{"scale": 0.01}' > "$work/poncho_cm.json" ||
  { echo "FAIL: inspect --json on the poncho"; fail=1; }
[ "$(bounds_ratio "$work/poncho.json" "$work/poncho_cm.json")" = "0.01" ] ||
  { echo "FAIL: a transform's scale 0.01 should scale the poncho's bounds by 0.01: $(bounds_ratio "$work/poncho.json" "$work/poncho_cm.json")"; fail=1; }
python3 -c 'import json, sys; j = json.load(open(sys.argv[1])); sys.exit(not (j["uvs"]["vt"] == 2432 and j["panels"] == ["front", "back"]))' \
  "$work/poncho.json" || { echo "FAIL: inspect --json: the poncho's vt and panels"; fail=1; }

# Errors: a missing file and a bad transform, named, exit 2.
expect 2 "$work/none.obj: file not found" -- inspect "$work/none.obj"
expect 2 "inspect: --transform.scale: expected a scale in (0, 1e6]" -- inspect "$poncho" --transform '{"scale": -1}'
expect 2 "inspect: --transform: expected an object" -- inspect "$poncho" --transform '[1, 2]'
expect 2 "inspect: expected one file" -- inspect

models=/usr/share/assimp/models
if [ ! -d "$models" ]; then
  [ $fail -eq 0 ] && echo "skipped: $models is absent (Debian's assimp-testmodels; apps/deps.sh installs it): the garment parts passed"
  exit $fail
fi

# A rigged character: bones, clips with their lengths and keys, the likely up axis; its bounds
# scale with the transform.
dancer="$models/X/BCN_Epileptic.X"
expect_output 0 "$dancer: rigged character" -- inspect "$dancer"
expect_output 0 'bones      54; top "B_Root_Pelvis_L"' -- inspect "$dancer"
expect_output 0 '0 "Epileptisch": 3.3 s, 100 keys (57 channels), ends on its first pose' -- inspect "$dancer"
expect_output 0 "likely up  +y: from its 6 leg joints" -- inspect "$dancer"
expect_output 0 'likely up  +z' -- inspect "$dancer" --transform '{"rotate_degrees": [90, 0, 0]}'
"$invfem" inspect "$dancer" --json > "$work/dancer.json" &&
  "$invfem" inspect "$dancer" --json --transform '{"scale": 0.01}' > "$work/dancer_cm.json" ||
  { echo "FAIL: inspect --json on the dancer"; fail=1; }
[ "$(bounds_ratio "$work/dancer.json" "$work/dancer_cm.json")" = "0.01" ] ||
  { echo "FAIL: a transform's scale 0.01 should scale the dancer's bounds by 0.01: $(bounds_ratio "$work/dancer.json" "$work/dancer_cm.json")"; fail=1; }

# check-scene: the poncho's and the dancer's bounds at frame 0, after their transforms; stdout
# stays the scene's JSON.
scene="$src/apps/scenes/poncho_dance.json"
expect 0 'cloth "poncho" at frame 0: [-0.55, 1.56, -0.74] to [0.55, 1.56, 0.36] m, size 1.1 x 0 x 1.1 m' -- check-scene "$scene"
expect 0 'collider "dancer" at frame 0: [-0.309, 0.005661, -0.2969] to [0.277, 1.82, 0.08107] m' -- check-scene "$scene"
"$invfem" check-scene "$scene" 2>/dev/null | python3 -c 'import json, sys; json.load(sys.stdin)' ||
  { echo "FAIL: check-scene's stdout is not the scene's JSON"; fail=1; }

# A clip whose last pose is not its first (Testwuson's Wuson_Run ends 9.6 cm away), looped: refused
# at load naming the jump, by run and check-scene; with loop_blend the run passes the wrap.
wuson="$models/X/Testwuson.X"
expect_output 0 '0 "Wuson_Run": 0.9667 s, 30 keys (39 channels), ends 9.626 cm from its first pose (vertex 1703)' -- inspect "$wuson"
cat > "$work/wuson.json" <<JSON
{ "name": "wuson_loop", "fps": 25, "frames": 40,
  "solver": { "integrator": "implicit" },
  "cloths": [ { "name": "blanket", "grid": { "width": 0.6, "height": 0.8, "nx": 12, "ny": 16 },
                "transform": { "translate": [0, 1.62, 0.2] },
                "material": { "young": 1e5, "density": 300, "thickness": 0.001 } } ],
  "colliders": [
    { "name": "wuson", "type": "skinned", "file": "$wuson", "clip": "Wuson_Run",
      "after_end": "loop", "friction": 0.5, "query_radius": 0.02 },
    { "name": "ground", "type": "plane" } ] }
JSON
refusal='collider "wuson": skinned body "wuson": clip "Wuson_Run" ends 9.63 cm from its first pose (vertex 1703): after_end "loop" would jump there, further than the 1.9 cm a step can follow (query_radius - offset); set loop_blend (seconds) to blend the wrap'
expect 2 "$refusal" -- check-scene "$work/wuson.json"
expect 2 "$refusal" -- run "$work/wuson.json" --out "$work/o_jump"
expect 2 "loop_blend 0.5 s is more than half of clip \"Wuson_Run\"'s 0.967 s" -- \
  check-scene "$work/wuson.json" --set colliders.0.loop_blend=0.5
expect 2 '$.colliders[0].loop_blend: expected 0 with after_end "hold"' -- \
  check-scene "$work/wuson.json" --set colliders.0.loop_blend=0.3 --set colliders.0.after_end=hold
# 40 frames, 1.6 s: past the clip's 0.967 s and the blended loop's restart at 2 x 0.667 s.
expect 0 "" -- run "$work/wuson.json" --set colliders.0.loop_blend=0.3 --out "$work/o_blend" --quiet
[ -f "$work/o_blend/frames/wuson/0040.obj" ] || { echo "FAIL: the blended loop's run wrote no frame 40"; fail=1; }
expect_output 0 "no intersecting triangle pairs" -- check "$work/o_blend"

[ $fail -eq 0 ] && echo "all inspect CLI checks passed"
exit $fail
